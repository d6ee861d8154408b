"""Folders replaced whole or not at all: a saved behaviour is never half old, half new.

A save of ``<parent>/<name>`` holds an exclusive ``flock`` on the lock file
``<parent>/.<name>.tabletop-lock`` from start to end (:func:`locked`), so two saves of one
name, in threads of one process or in two processes, run one after the other.
:func:`replace_folder` writes the complete new folder beside the old one under a hidden name
(``.<name>.tabletop-swap-<random>.new``, every file and the folder fsynced), renames the old one
aside (``.<name>.tabletop-swap-<random>.old``), renames the new one into place, fsyncs the
parent and only then removes the old one. A process killed at any point leaves either the old
folder or the new one under the real name, or (between the two renames) the old one aside:
:func:`recover`, run before a folder is read, listed or saved, puts that one back and removes
unfinished new folders and old ones already replaced, with one logged line each. It touches
only hidden folders carrying the ``tabletop-swap`` marker, and only when it gets the lock
without waiting: the lock of a killed saver is released by the system with its process (a
process id reused after a reboot holds nothing), so a reader never undoes a save that is still
running; a reader that finds the folder missing while the lock is held waits (:func:`saving`).
A folder named through a symbolic link is swapped at the link's target, the link kept.
"""

from __future__ import annotations

import fcntl
import logging
import os
import re
import shutil
import tempfile
import threading
from contextlib import contextmanager
from pathlib import Path
from typing import Any, Callable, Iterator, Mapping

from tabletop.files import fsync_folder, write_synced
from tabletop.frames import InputError

log = logging.getLogger("tabletop")

MARKER = "tabletop-swap"          # in every hidden folder a save makes beside the behaviour
LOCK_SUFFIX = ".tabletop-lock"    # ".<name>.tabletop-lock": kept, removing it races its waiters
_LEFTOVER = re.compile(rf"^{MARKER}-[A-Za-z0-9_]+\.(new|old|tmp)$")   # after ".<name>."
_HIDDEN = re.compile(rf"^\.(.+)\.{MARKER}-[A-Za-z0-9_]+\.(?:new|old|tmp)$")


def real(target: Path) -> Path:
    """The folder ``target`` names, symbolic links followed (also when it is missing)."""
    return Path(os.path.realpath(target))


def _lock_file(target: Path) -> Path:
    return target.parent / f".{target.name}{LOCK_SUFFIX}"


def _leftovers(target: Path) -> list[tuple[Path, str]]:
    """(path, "new", "old" or "tmp") of the hidden folders that saves of ``target`` made
    beside it."""
    prefix = f".{target.name}."
    try:
        names = [n for n in os.listdir(target.parent) if n.startswith(prefix)]
    except OSError:
        return []
    out = []
    for n in sorted(names):
        m = _LEFTOVER.match(n[len(prefix):])
        path = target.parent / n
        if m and (path.is_dir() or path.is_symlink()):
            out.append((path, m.group(1)))
    return out


def _open_lock(target: Path) -> int:
    """An open descriptor of ``target``'s lock file, made if missing, readable by every user
    (a flock needs only read access: under umask 077 a 0600 file of one user stopped every
    other user saving that name)."""
    fd = os.open(_lock_file(target), os.O_RDONLY | os.O_CREAT, 0o644)
    try:
        if os.fstat(fd).st_uid == os.geteuid():
            os.fchmod(fd, 0o644)
    except OSError:
        pass
    return fd


def _try_lock(target: Path) -> int | None:
    """An open descriptor of ``target``'s lock file, locked, or None if another open file holds
    the lock (or the lock file cannot be opened)."""
    try:
        fd = _open_lock(target)
    except OSError:
        return None
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        os.close(fd)
        return None
    return fd


_GIVEN_UP: dict[str, threading.Event] = {}   # lock file: its given-up waiter's end, set when
                                             # that waiter is no longer blocked in flock
_WAITERS = threading.Lock()


def _close(fd: int) -> None:
    try:
        os.close(fd)
    except OSError:
        pass


def _flock_within(fd: int, wait_s: float, key: str) -> bool:
    """Take the exclusive ``flock`` of ``fd`` (lock file ``key``) within ``wait_s`` seconds.
    The blocking call runs in a helper thread, so the wait keeps its place in the system's
    queue (polling with LOCK_NB starved against a run keeping 40 takes in a row); True once
    held. False when the time is up: the helper then closes ``fd`` itself, at once or when it
    gets the lock; until then every further wait on ``key`` is False at once (while another
    run stalls, each keep would leave one more blocked thread and descriptor, and freeze the
    frame loop ``wait_s`` again); that waiter is given 0.1 s to end (its holder just let go,
    it takes the lock and closes at once). A failing flock (ENOLCK on a mount without locks)
    raises its OSError at once, ``fd`` closed."""
    with _WAITERS:
        pending = _GIVEN_UP.get(key)
    if pending is not None and not pending.wait(0.1):
        _close(fd)
        return False
    state: dict = {"done": False, "given_up": False, "error": None}
    held = threading.Event()

    def take() -> None:
        error = None
        try:
            fcntl.flock(fd, fcntl.LOCK_EX)
        except OSError as exc:
            error = exc
        with _WAITERS:
            state["done"], state["error"] = True, error
            if state["given_up"] or error is not None:
                _close(fd)
            if _GIVEN_UP.get(key) is held:
                del _GIVEN_UP[key]
            held.set()

    threading.Thread(target=take, name="lock-wait", daemon=True).start()
    held.wait(wait_s)
    with _WAITERS:
        if state["done"]:
            if state["error"] is not None:
                raise state["error"]
            return True
        state["given_up"] = True
        _GIVEN_UP[key] = held
        return False


@contextmanager
def exclusive(target: Path, wait_s: float | None = None) -> Iterator[None]:
    """Hold the lock of ``target`` (``.<name>.tabletop-lock`` beside it), waiting for another
    process holding it: a file read, changed and written back by one process at a time. With
    ``wait_s`` (seconds) the wait is bounded: a holder stalled longer (a run stopped with
    Ctrl-Z, a hung network mount) gets InputError, so a frame loop taking the lock never
    freezes, and a lock call that fails raises its OSError at once; without it the wait is
    unbounded (a save in its own thread)."""
    fd = _open_lock(target)
    if wait_s is None:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX)
        except BaseException:
            os.close(fd)
            raise
    elif not _flock_within(fd, wait_s, str(_lock_file(target))):
        raise InputError(f"{target}: busy, another run is saving into it "
                         f"(waited {wait_s:g} s); try again")
    try:
        yield
    finally:
        os.close(fd)                                   # releases the lock


@contextmanager
def locked(target: Path) -> Iterator[list[str]]:
    """Hold the save lock of ``target`` (waiting for a save running elsewhere), its interrupted
    saves recovered first; yields the recovery's lines (see :func:`recover`)."""
    target = real(target)
    with exclusive(target):
        yield _recover_held(target)


def saving(target: Path) -> bool:
    """Does another save (or recovery) hold the lock of ``target`` (the folder may then be
    briefly missing, its old version aside)?"""
    target = real(target)
    if not os.path.exists(_lock_file(target)):
        return False
    fd = _try_lock(target)
    if fd is None:
        return True
    os.close(fd)
    return False


def recover(target: Path) -> list[str]:
    """Finish or undo the interrupted saves of ``target`` (those whose lock nobody holds): an
    old version aside with no folder in place is put back, unfinished new folders and old
    versions already replaced are removed. Returns (and logs) one line per leftover; nothing
    while a save holds the lock."""
    target = real(target)
    if not _leftovers(target):
        return []
    fd = _try_lock(target)
    if fd is None:
        return []
    try:
        return _recover_held(target)
    finally:
        os.close(fd)


def _recover_held(target: Path) -> list[str]:
    done = []
    for path, kind in sorted(_leftovers(target), key=lambda x: x[1] != "old"):
        try:
            if kind == "old" and not os.path.lexists(target):
                os.rename(path, target)
                fsync_folder(target.parent)
                done.append(f"{target}: a save was interrupted before the new version was in "
                            f"place; the previous version is restored from {path.name}")
                continue
            if path.is_symlink():
                os.unlink(path)
            else:
                shutil.rmtree(path, onerror=_writable_and_again)
            what = ("the previous version, already replaced" if kind == "old"
                    else "an unfinished save")
            done.append(f"{target}: removed {path.name}, {what}")
        except OSError as exc:
            done.append(f"{target}: leftover {path.name} not cleaned: {exc.strerror or exc}")
    for line in done:
        log.warning("%s", line)
    return done


def _writable_and_again(func: Callable[[str], Any], path: str, _exc_info: object) -> None:
    """``shutil.rmtree``'s error handler: a read-only folder inside (a designer's ``refs/`` at
    0555, not run as root) is made writable and the removal tried again; OSError if not."""
    os.chmod(os.path.dirname(path), 0o700)
    if os.path.isdir(path) and not os.path.islink(path):
        os.chmod(path, 0o700)
    func(path)


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
    """Replace the folder ``target`` by one holding ``files`` (name -> text, each keeping the
    permission mode of the file it replaces) and a copy of every other file, folder and
    symbolic link it held (modes and times kept, links copied as links), whole or not at all
    (see the module's docstring); OSError on failure, the old folder then kept. The caller
    holds :func:`locked`; a ``target`` named through a link is replaced at the link's target."""
    target = real(target)
    parent = target.parent
    new = Path(tempfile.mkdtemp(prefix=f".{target.name}.{MARKER}-", suffix=".new", dir=parent))
    old = new.with_suffix(".old")
    try:
        for name, text in files.items():
            write_synced(new / name, text)
            if os.path.isfile(target / name):
                os.chmod(new / name, os.stat(target / name).st_mode & 0o7777)
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
    done = old.with_suffix(".tmp")    # never put back: a removal that fails part way leaves a
    try:                              # leftover recovery removes, not one it restores over a
        os.rename(old, done)          # behaviour deleted later (the studio's trash)
    except OSError:
        done = old
    try:
        shutil.rmtree(done, onerror=_writable_and_again)
    except OSError as exc:
        log.warning("%s: the previous version %s not removed: %s", target, done.name,
                    exc.strerror or exc)
