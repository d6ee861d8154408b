"""Folders replaced whole or not at all: a saved behaviour is never half old, half new.

:func:`replace_folder` writes the complete new folder beside the old one under a hidden name
(``.<name>.<pid>.new``, every file and the folder fsynced), renames the old one aside
(``.<name>.<pid>.old``), renames the new one into place, fsyncs the parent and only then
removes the old one. A process killed at any point leaves either the old folder or the new
one under the real name, or (between the two renames) the old one aside: :func:`recover`,
run before a folder is read, listed or saved, puts that one back and removes unfinished new
folders and old ones already replaced, with one logged line each. Only leftovers of processes
that have ended are touched (their process id is in the name), so a reader never undoes a
save that is still running; a reader that finds the folder missing while such a save runs
waits for it (:func:`saving`).
"""

from __future__ import annotations

import logging
import os
import re
import shutil
from pathlib import Path
from typing import Mapping

from tabletop.files import alive, fsync_folder, write_synced

log = logging.getLogger("tabletop")

_LEFTOVER = re.compile(r"^(\d+)\.(?:(new|old)|[A-Za-z0-9_]+\.tmp)$")   # after ".<name>."
_HIDDEN = re.compile(r"^\.(.+)\.\d+\.(?:new|old|[A-Za-z0-9_]+\.tmp)$")


def _leftovers(target: Path) -> list[tuple[Path, int, str]]:
    """(path, writer's process id, "new", "old" or "tmp") of the hidden folders that saves of
    ``target`` made beside it."""
    prefix = f".{target.name}."
    try:
        names = [n for n in os.listdir(target.parent) if n.startswith(prefix)]
    except OSError:
        return []
    out = []
    for n in sorted(names):
        m = _LEFTOVER.match(n[len(prefix):])
        if m and (target.parent / n).is_dir():
            out.append((target.parent / n, int(m.group(1)), m.group(2) or "tmp"))
    return out


def saving(target: Path) -> bool:
    """Is a running process between the two renames of a save of ``target`` (the folder is
    then briefly missing, its old version aside)?"""
    return any(kind == "old" and pid != os.getpid() and alive(pid)
               for _, pid, kind in _leftovers(target))


def recover(target: Path) -> list[str]:
    """Finish or undo the interrupted saves of ``target`` (by processes that have ended): an
    old version aside with no folder in place is put back, unfinished new folders and old
    versions already replaced are removed. Returns (and logs) one line per leftover."""
    done = []
    for path, pid, kind in sorted(_leftovers(target), key=lambda x: x[2] != "old"):
        if pid == os.getpid() or alive(pid):
            continue
        try:
            if kind == "old" and not os.path.lexists(target):
                os.rename(path, target)
                fsync_folder(target.parent)
                done.append(f"{target}: a save was interrupted before the new version was in "
                            f"place; the previous version is restored from {path.name}")
            else:
                shutil.rmtree(path)
                what = ("the previous version, already replaced" if kind == "old"
                        else "an unfinished save")
                done.append(f"{target}: removed {path.name}, {what}")
        except OSError as exc:
            done.append(f"{target}: leftover {path.name} not cleaned: {exc.strerror or exc}")
    for line in done:
        log.warning("%s", line)
    return done


def recover_all(parent: Path) -> list[str]:
    """:func:`recover` every folder in ``parent`` that an interrupted save left a hidden
    folder for (also one now missing, its old version aside)."""
    try:
        names = os.listdir(parent)
    except OSError:
        return []
    found = {m.group(1) for m in map(_HIDDEN.match, names) if m}
    return [line for name in sorted(found) for line in recover(parent / name)]


def replace_folder(target: Path, files: Mapping[str, str]) -> None:
    """Replace the folder ``target`` by one holding ``files`` (name -> text) and a copy of
    every other file or folder it held, whole or not at all (see the module's docstring);
    OSError on failure, the old folder then kept."""
    parent, pid = target.parent, os.getpid()
    new, old = parent / f".{target.name}.{pid}.new", parent / f".{target.name}.{pid}.old"
    for stale in (new, old):
        shutil.rmtree(stale, ignore_errors=True)
    os.mkdir(new)
    try:
        for name, text in files.items():
            write_synced(new / name, text)
        for entry in os.scandir(target):                # nothing else it held is lost
            if entry.name not in files:
                if entry.is_dir(follow_symlinks=False):
                    shutil.copytree(entry.path, new / entry.name, symlinks=True)
                else:
                    shutil.copy2(entry.path, new / entry.name, follow_symlinks=False)
        os.chmod(new, os.stat(target).st_mode & 0o7777)
        fsync_folder(new)
        os.rename(target, old)
        try:
            os.rename(new, target)
        except BaseException:
            os.rename(old, target)
            raise
    except BaseException:
        shutil.rmtree(new, ignore_errors=True)
        raise
    fsync_folder(parent)
    shutil.rmtree(old, ignore_errors=True)

