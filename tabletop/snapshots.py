"""Snapshots of the projector view for a remote technician: a PNG every ``every_s`` seconds.

- On the wall clock (monotonic), not on frame times: while a camera is down the frames' times
  stand still, and the snapshots must go on showing it.
- With or without a window.
- Numbered ``snapshot-00000.png``...: the numbering continues from the highest snapshot already
  in the folder (nothing is overwritten), or each run writes into its own subfolder
  ``run-DATE-TIME`` (``per_run``). Each number is claimed by making its file (O_EXCL) before
  the write (unclaimed, two runs sharing a folder would both number on from its highest and
  overwrite each other's snapshots); a number another run took sends this one past the highest.
- Bounded: beyond ``keep`` snapshots or ``max_mb`` megabytes in the folder (its run subfolders
  included), the oldest are removed: oldest by number and run folder, the current run's last,
  never by a file's time (after the clock is set back each new snapshot would have the oldest
  time, and a full folder would remove it at once: a technician would see the old ones only).
  Other runs' folders are ordered by their names, the wall-clock time each run began: after a
  clock step one of them may outlive a newer run, never the current one.

Encoding a PNG takes tens of milliseconds, so the pixels are copied at once and written by a
thread, atomically; a snapshot still being written makes the next one wait, never queue.
"""

from __future__ import annotations

import datetime as _dt
import errno
import logging
import os
import re
import tempfile
import threading
import time
from pathlib import Path
from typing import TYPE_CHECKING, Callable

if TYPE_CHECKING:
    import pygame

log = logging.getLogger("tabletop")

NAME = re.compile(r"^snapshot-(\d+)\.png$")
FIRST_AFTER_S = 5.0   # the first snapshot comes this soon (or after every_s, if sooner)
CLAIM_TRIES = 100     # numbers tried for one snapshot while other runs take them


def numbered(folder: Path) -> list[Path]:
    """The snapshots in ``folder`` and its run subfolders."""
    if not folder.is_dir():
        return []
    found = [p for p in folder.iterdir() if NAME.match(p.name)]
    for sub in folder.iterdir():
        if sub.is_dir() and sub.name.startswith("run-"):
            found.extend(p for p in sub.iterdir() if NAME.match(p.name))
    return found


def next_number(folder: Path) -> int:
    """One more than the highest snapshot number directly in ``folder`` (0 when none)."""
    if not folder.is_dir():
        return 0
    numbers = [int(m.group(1)) for p in folder.iterdir() if (m := NAME.match(p.name))]
    return max(numbers, default=-1) + 1


def run_folder(root: Path) -> Path:
    """A new ``run-DATE-TIME`` subfolder of ``root``, made now (so two runs never share one)."""
    stamp = _dt.datetime.now().strftime("%Y%m%d-%H%M%S")
    root.mkdir(parents=True, exist_ok=True)
    candidate, n = root / f"run-{stamp}", 2
    while True:
        try:
            candidate.mkdir()
            return candidate
        except FileExistsError:
            candidate, n = root / f"run-{stamp}-{n}", n + 1


def prune(root: Path, keep: int, max_bytes: float, current: Path | None = None) -> list[Path]:
    """Remove the oldest snapshots under ``root`` beyond ``keep`` files or ``max_bytes``;
    returns the removed ones. Empty run subfolders go too. Oldest first: those directly in
    ``root`` while a run folder is ``current`` (the folder being written, by default ``root``),
    those of other run folders (by the folder's name), then those of ``current``; each
    folder's by number."""
    current = root if current is None else current
    entries = []
    for p in numbered(root):
        try:
            st = p.stat()
        except OSError:
            continue
        rank = (2, "") if p.parent == current else (1, p.parent.name) if p.parent != root \
            else (0, "")
        entries.append((rank, int(NAME.match(p.name).group(1)), str(p), st.st_size, p))
    entries.sort()
    total = sum(e[3] for e in entries)
    removed = []
    for _, _, _, size, p in entries:
        if len(entries) - len(removed) <= keep and total <= max_bytes:
            break
        try:
            p.unlink()
        except OSError as exc:
            log.warning("old snapshot %s not removed: %s", p, exc.strerror or exc)
            continue
        removed.append(p)
        total -= size
        parent = p.parent
        if parent != root and parent.name.startswith("run-") and not any(parent.iterdir()):
            parent.rmdir()
    return removed


def _check_writable(folder: Path) -> None:
    """OSError when ``folder`` takes no new file (a read-only disk, no permission): refused at
    start as a folder that cannot be made is, since no snapshot would ever be written. A full
    disk is no such folder: the snapshots resume once it has room."""
    try:
        fd, probe = tempfile.mkstemp(prefix=".snapshot-probe-", dir=folder)
    except OSError as exc:
        if exc.errno in (errno.ENOSPC, errno.EDQUOT):
            return
        raise
    os.close(fd)
    os.unlink(probe)


class Snapshots:
    """When to take a snapshot and where it goes; :meth:`save` writes one (see the module)."""

    def __init__(self, folder: str | Path, every_s: float, keep: int = 2000,
                 max_mb: float = 500.0, per_run: bool = False,
                 clock: Callable[[], float] = time.monotonic) -> None:
        self.root = Path(folder)
        self.root.mkdir(parents=True, exist_ok=True)  # OSError: a folder that cannot be made
        self.folder = run_folder(self.root) if per_run else self.root
        _check_writable(self.folder)
        self.every_s, self.keep, self.max_bytes = float(every_s), int(keep), max_mb * 2**20
        self.clock = clock
        self.number: int | None = None   # found when the first snapshot is written
        self.taken = 0
        self.failing = False  # the last snapshot could not be written
        self.failed: str | None = None   # ... "FILE: why" (the status's snapshots.failed)
        self.saved: Path | None = None   # the last snapshot written
        self._next = clock() + min(self.every_s, FIRST_AFTER_S)
        self._saver: threading.Thread | None = None

    def due(self) -> bool:
        """True when a snapshot is due now (and the previous one has been written)."""
        now = self.clock()
        if now < self._next:
            return False
        if self._saver is not None and self._saver.is_alive():
            return False
        self._next += self.every_s * max(1, int((now - self._next) // self.every_s) + 1)
        return True

    def save(self, surface: pygame.Surface) -> Path:
        """Write a copy of ``surface`` (a pygame Surface) as the next snapshot, in a thread."""
        path, claimed = self._claim()
        self.taken += 1
        self._saver = threading.Thread(target=self._write, args=(surface.copy(), path, claimed),
                                       name="snapshot", daemon=True)
        self._saver.start()
        return path

    def _claim(self) -> tuple[Path, bool]:
        """The next snapshot's path, its file made empty at once (O_EXCL) so that no other run
        writes it, and whether it was; one another run made sends the number past the folder's
        highest. Not claimed (the folder cannot be written): the writer says why."""
        if self.number is None:
            self.number = next_number(self.folder)
        for _ in range(CLAIM_TRIES):
            path = self.folder / f"snapshot-{self.number:05d}.png"
            self.number += 1
            try:
                os.close(os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o644))
                return path, True
            except FileExistsError:
                self.number = max(self.number, next_number(self.folder))
            except OSError:
                break
        return path, False

    def _write(self, surface: pygame.Surface, path: Path, claimed: bool = False) -> None:
        error = save_png(surface, path)
        if error and claimed:            # no empty snapshot left where the write failed
            try:
                if path.stat().st_size == 0:
                    path.unlink()
            except OSError:
                pass
        if error and not self.failing:  # said once, not at every snapshot (a full disk)
            log.warning("snapshot %s not saved: %s; retrying at the next one", path, error)
        elif not error and self.failing:
            log.info("snapshots are saved again (%s)", path)
        self.failing = bool(error)
        if error:
            self.failed = f"{path}: {error}"
        else:
            self.failed, self.saved = None, path
        prune(self.root, self.keep, self.max_bytes, self.folder)

    def close(self) -> None:
        if self._saver is not None:
            self._saver.join(timeout=5.0)


def save_png(surface: pygame.Surface, path: Path) -> str:
    """Write ``surface`` to ``path`` as PNG atomically (:func:`tabletop.file_io.atomic_write_bytes`:
    temporary file, fsync, rename); returns what went wrong, or "" when it was written.

    Encoded by OpenCV, which lets go of the interpreter while it compresses: pygame's own PNG
    writer holds it for the whole encode (60-170 ms at 1280x720), and with it the loop's
    thread stood still that long at every snapshot (capture-to-render p99 61-70 ms in a 14 s
    window run with a snapshot every 2 s, against 6 ms without); with OpenCV the longest
    pause is the pixels' copy, 3-5 ms."""
    import cv2
    import numpy as np
    import pygame

    from tabletop.files import FileFormatError, atomic_write_bytes
    try:
        w, h = surface.get_size()
        rgb = np.frombuffer(pygame.image.tobytes(surface, "RGB"), np.uint8).reshape(h, w, 3)
        ok, png = cv2.imencode(".png", cv2.cvtColor(rgb, cv2.COLOR_RGB2BGR),
                               [cv2.IMWRITE_PNG_COMPRESSION, 3])
        if not ok:
            return "the PNG encoder refused the image"
        atomic_write_bytes(path, png.tobytes())
    except (OSError, pygame.error, cv2.error, FileFormatError) as exc:
        return str(getattr(exc, "strerror", None) or exc)
    return ""
