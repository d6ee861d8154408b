"""A recordings folder: how the recorder names session files and which of them ``keep`` prunes.

A folder recording is named ``session-DATE-TIME-MICROSECONDS.jsonl``; an exact file name that
exists already continues as ``NAME-2.jsonl``, ``NAME-3.jsonl``... (never overwritten). Each
file's header carries an ``order`` (one more than the highest in the folder when it was made);
pruning removes the oldest by that order, never by the clock (a clock set back gives the newest
files the oldest times). ``keep`` counts parts, so the disk holds at most ``keep`` x ``max_mb``; the
parts of one session (``max_mb`` reached, a resume after a full disk) carry one ``session`` id, made
anew for each session (:func:`new_session`: two runs starting together read the same highest
order, so an order would give both one id), and closed sessions are removed whole, oldest
first, so a kept session replays whole. A part a slow or full disk stopped stays marked while its
run goes on (:func:`keep_held`): released, a disk stalled past ``max_queue`` lines let a second
run starting in the folder remove the running session's recording. A running session that
alone holds more than ``keep`` parts loses its oldest parts (each part replays on its own), only
the recorder's own. Used by :class:`tabletop.recorder.Recorder`.
"""

from __future__ import annotations

import datetime as _dt
import fcntl
import itertools
import logging
import os
import re
import secrets
from pathlib import Path
from typing import Any, Iterator

log = logging.getLogger("tabletop")

# The start of every header line the recorder writes; the ``order`` is read back from the
# file's first bytes, so pruning never parses a header (which carries every file the config
# names, megabytes at times).
# ``session`` is a number in recordings of an older tabletop (the first part's order), a
# quoted id (:func:`new_session`) in later ones; a file without one is a session of its own.
ORDER = re.compile(rb'^\{"format":"[^"]*","version":\d+,"order":(\d+)'
                   rb'(?:,"session":(\d+|"[0-9a-f]{1,32}"))?[,}]')
ORDER_BYTES = 128
# A file of the naming whose first bytes are no session header (``recorder.path: notes.txt``
# beside the technician's own notes.txt) is no recording: numbered past, never counted by keep
# nor removed. A recording of an older tabletop (no ``order``) names its format there; an
# empty file is a recording whose header never reached the disk.
FORMAT_MARK = b'"tabletop-session"'
FOREIGN = -1     # (``orders``' mark of such a file)

# A recording's path -> (its header's ``order``, None for a file without one, FOREIGN for no
# recording; its modification time, seconds since the epoch; its ``session``, None for a file
# without one: a session of its own).
Recordings = dict[Path, tuple[int | None, float, str | None]]
# (the headers' ``order`` and ``session``, read once per file)
Orders = dict[Path, tuple[int | None, str | None]]


def new_session() -> str:
    """A new session's id for its parts' headers: 16 random hex digits (64 bits), so runs
    started together in one folder never share one, and the header's ``order`` and
    ``session`` stay within the ``ORDER_BYTES`` that pruning reads."""
    return secrets.token_hex(8)


def _stamp() -> str:
    return _dt.datetime.now().strftime("%Y%m%d-%H%M%S-%f")


def candidates(folder: Path, stem: str | None, suffix: str, first: int = 1) -> Iterator[Path]:
    """File names to try in turn for a new part: ``stem`` (None: a new ``session-`` stamp),
    then ``stem-2``, ``stem-3``...; from number ``first`` on (1: ``stem`` itself)."""
    base = f"session-{_stamp()}" if stem is None else stem
    if first <= 1:
        yield folder / f"{base}{suffix}"
    for n in itertools.count(max(2, first)):   # exclusive creation ends it: never endless
        yield folder / f"{base}-{n}{suffix}"


def number(name: str, stem: str | None, suffix: str) -> int:
    """The N of a ``stem-N`` name of this naming (1 for ``stem`` itself; 0 for a folder's
    stamped names, which never collide)."""
    if stem is None:
        return 0
    rest = name[len(stem):len(name) - len(suffix)]
    return int(rest[1:]) if rest else 1


def _is_mine_name(name: str, stem: str | None, suffix: str) -> bool:
    if not name.endswith(suffix) or len(name) == len(suffix):
        return False
    if stem is None:
        return name.startswith("session-")
    rest = name[len(stem):len(name) - len(suffix)]
    return name.startswith(stem) and (rest == "" or (rest[0] == "-" and rest[1:].isdigit()
                                                     and rest[1:].isascii()))


def recordings(folder: Path, stem: str | None, suffix: str,
               orders: Orders) -> Recordings:
    """This naming's recordings in ``folder``: path -> (its header's ``order``, None for a
    file without one: written by an older tabletop, or empty; its modification time, read
    only for a file without an order, else 0; its ``session``). ``orders`` caches the headers'
    orders and sessions, so each
    is read once (later parts, resumes). One directory listing (names and types from it, no
    call per file but the first read of a header): 20,000 recordings took 190-280 ms on each
    new part, in the frame loop, when every file was also stat()ed twice."""
    out: Recordings = {}
    try:
        with os.scandir(folder) as it:
            entries = [(Path(e.path), e) for e in it if _is_mine_name(e.name, stem, suffix)
                       and Path(e.name).suffix == suffix and e.is_file()]
    except OSError:
        return out
    for p, e in entries:
        try:
            if p not in orders:
                with open(p, "rb") as f:
                    head = f.read(ORDER_BYTES)
                m = ORDER.match(head)
                orders[p] = ((int(m.group(1)), m.group(2).strip(b'"').decode() if m.group(2)
                              else None) if m
                             else (None if not head or FORMAT_MARK in head else FOREIGN, None))
            order, session = orders[p]
            out[p] = (order, e.stat().st_mtime if order is None else 0.0, session)
        except OSError:
            continue                 # removed meanwhile, or unreadable: not counted
    return out


def create_part(folder: Path, stem: str | None, suffix: str, orders: Orders,
                last: tuple[int, int], listed: bool) -> tuple[Recordings, int, Path, Any]:
    """A session's next part created exclusively (unbuffered: each line one write), as
    (``folder``'s recordings of this naming, its ``order``, its path, the open file). ``last``:
    the session's last part's order and name number (0, 0 before its first); unless ``listed``
    (nothing to prune), the folder is not listed again (a listing grows with every recording
    kept) and the part goes on from ``last``, the recordings returned empty."""
    if not listed:
        mine: Recordings = {}
        order, first = last[0] + 1, last[1] + 1
    else:
        mine = recordings(folder, stem, suffix, orders)
        order = max((o for o, *_ in mine.values() if o is not None and o != FOREIGN),
                    default=0) + 1
        # on after the highest name: trying NAME, NAME-2 ... one by one cost an open()
        # per recording kept (20,000 of them: 0.1 s, at every start and new part)
        first = max((number(p.name, stem, suffix) for p in mine), default=0) + 1
        first = max(first, last[1] + 1)
    for candidate in candidates(folder, stem, suffix, first):
        try:
            return mine, order, candidate, open(candidate, "xb", buffering=0)
        except FileExistsError:
            continue
    raise AssertionError("unreachable: the candidates never end")


def prune(mine: Recordings, keep: int | None, current: Path, folder: Path,
          own: list[Path] | None = None) -> list[Path]:
    """Keep at most ``keep`` parts of ``mine`` (None: keep all), so the disk holds at most
    ``keep`` x ``max_mb``. Closed sessions go first, oldest first, each whole with all its
    parts: files without an order first (by modification time), then by their first part's
    order. A session one of whose parts another run is writing (:func:`being_recorded`) is
    left. When the running session alone holds more than ``keep`` parts, its oldest are
    removed down to ``keep``: only ``own`` (the recorder's parts, in order; default
    ``[current]``), never ``current`` nor a part being recorded: a kiosk running for weeks is
    one session, 821 bytes a frame at 60 Hz, about 4 GB a day. Returns the parts of ``own``
    removed."""
    if keep is None:
        return []
    sessions: dict[tuple, list[Path]] = {}
    for p, (order, _, session) in mine.items():
        if order != FOREIGN:
            sessions.setdefault(("s", session) if session is not None else ("p", p), []).append(p)

    def age(key: tuple) -> tuple:
        return min((0, mine[p][1], p.name) if mine[p][0] is None else (1, mine[p][0], p.name)
                   for p in sessions[key])

    def in_order(parts: list[Path]) -> list[Path]:
        return sorted(parts, key=lambda p: (mine[p][0] or 0, p.name))

    own = [p for p in (own or [current]) if p in mine]
    running = next((k for k, parts in sessions.items() if current in parts), None)
    total = sum(len(parts) for parts in sessions.values())
    trimmed: list[Path] = []
    try:
        for key in sorted(sessions, key=age):
            if total <= keep:
                break
            parts = in_order(sessions[key])
            if key == running or any(being_recorded(p) for p in parts):
                continue
            for old in parts:
                old.unlink()
                log.info("removed old recording %s (recorder.keep: %d)", old, keep)
            total -= len(parts)
        if running is not None:
            parts = [p for p in own if p != current]
            for old in parts[:max(0, len(parts) + 1 - keep)]:
                if being_recorded(old):
                    continue
                old.unlink()
                trimmed.append(old)
                log.info("removed part %s of the running recording (recorder.keep: %d)",
                         old, keep)
    except OSError as exc:
        log.warning("old recordings in %s not removed: %s", folder, exc.strerror or exc)
    return trimmed


def hold(f: Any) -> None:
    """Mark the open recording ``f`` as being recorded (a shared lock on it, held until it is
    closed), so that another run's :func:`prune` on the folder leaves it alone."""
    try:
        fcntl.flock(f.fileno(), fcntl.LOCK_SH | fcntl.LOCK_NB)
    except OSError:   # a file system without locks: recorded on, unmarked
        pass


def release(f: Any) -> None:
    """Unmark the finished part ``f`` (:func:`hold`) while it waits to be synced and closed:
    the run's own removal of its oldest parts takes it then, as another run's may."""
    try:
        fcntl.flock(f.fileno(), fcntl.LOCK_UN)
    except OSError:
        pass


def keep_held(f: Any) -> int | None:
    """A second descriptor of the open recording ``f`` that keeps its mark (:func:`hold`) after
    ``f`` is closed, until :func:`let_go`: a part a slow or full disk stopped while its run goes
    on (the session resumes in a new part) is still being recorded. None when none is left."""
    try:
        return os.dup(f.fileno())
    except (OSError, ValueError):
        return None


def let_go(fd: int | None) -> None:
    """Unmark and close what :func:`keep_held` kept (None: nothing)."""
    if fd is None:
        return
    try:
        fcntl.flock(fd, fcntl.LOCK_UN)
    except OSError:
        pass
    try:
        os.close(fd)
    except OSError:
        pass


def being_recorded(path: Path) -> bool:
    """Is ``path`` held by a recorder (:func:`hold`), of this process or another? (Two runs
    may record into one folder with a small ``keep``: one's start must not remove the other's
    recording while it is written.)"""
    try:
        fd = os.open(path, os.O_RDONLY)
    except OSError:
        return False
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        return True
    except OSError:
        return False
    finally:
        os.close(fd)
    return False
