"""The recorder's syncer thread: every line :class:`~tabletop.recorder.Recorder` writes is made
durable without the frame loop waiting on the disk.

The frame loop writes each line to the operating system at once (a ``kill -9`` loses at most
the line being written); the syncer fdatasyncs the file as soon as a line is written and again
after each sync while lines keep coming, so a power cut loses at most the lines written during
the sync in progress (one line at 60 Hz while the disk syncs within a frame). It also syncs and
closes finished parts and syncs the folder after a part was created. When a sync covers several
lines the disk is slower than the frames: logged when a line waited ``SLOW_S``, sparingly (at
once, then after 10 s, 20 s, ... up to every 600 s while the disk stays slow,
:class:`~tracking.badinput.LogGaps`). :attr:`Syncer.durability` counts lines and syncs and
keeps the latest durability latencies (line written -> its sync returned).
"""

from __future__ import annotations

import collections
import logging
import os
import threading
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

from tabletop.files import fsync_folder
from tracking.badinput import LogGaps

log = logging.getLogger("tabletop")


@dataclass
class Durability:
    """What the syncer thread has made durable: lines, fdatasyncs, and the latest latencies
    (seconds from :meth:`Recorder.consume` writing a line to its sync returning)."""

    lines: int = 0
    syncs: int = 0
    waited_max: int = 0               # most lines written by one sync
    latencies_s: collections.deque = field(
        default_factory=lambda: collections.deque(maxlen=4096))


class Syncer:
    """The syncer thread's side of :class:`~tabletop.recorder.Recorder` (its base class): the
    lines waiting for a sync, the parts to close, and the condition both sides share."""

    SLOW_S = 0.5                      # a line waiting this long for the disk is logged
    SLOW_LOG_EVERY_S = 10.0           # first gap between slow-disk lines, doubling ...
    SLOW_LOG_MAX_S = 600.0            # ... up to this (LogGaps). Every 10 s, a disk that stayed
    # slow (a worn SD card) wrote 8,640 lines a day and rotated the kiosk's log (1 MB x 5) away
    # in days; doubling: 11 lines in its first hour, then 6 an hour.

    # the recorder's, read by the syncer
    folder: Path
    failed: str | None
    clock: Callable[[], float]
    _f: Any
    path: Path
    _fail: Callable[..., None]

    def _init_syncer(self) -> None:
        """The syncer's state, before the recorder's first part is opened."""
        self.durability = Durability()
        self._unsynced: list[float] = []   # when each line not yet synced was written
        self._retired: list[Any] = []      # finished parts, for the syncer to sync and close
        self._folder_dirty = False         # a part was created since the last folder sync
        self._cv = threading.Condition()
        self._closing = False
        self._syncing = False              # the syncer is working on a batch
        self._slow_log = LogGaps(self.SLOW_LOG_EVERY_S, self.SLOW_LOG_MAX_S)   # syncer only

    def _start_syncer(self) -> None:
        self._syncer = threading.Thread(target=self._sync_lines, name="recorder-sync",
                                        daemon=True)
        self._syncer.start()

    def _sync_lines(self) -> None:
        """fdatasync whenever lines were written since the last sync; sync and close finished
        parts; until closed and nothing is left to sync."""
        while True:
            with self._cv:
                self._syncing = False
                while not (self._unsynced or self._retired or self._folder_dirty) \
                        and not self._closing:
                    self._cv.wait()
                if not (self._unsynced or self._retired or self._folder_dirty):
                    return
                self._syncing = True
                batch, self._unsynced = self._unsynced, []
                retired, self._retired = self._retired, []
                folder, self._folder_dirty = self._folder_dirty, False
                f = self._f
            for old in retired:
                try:
                    old.flush()
                    os.fsync(old.fileno())
                except (OSError, ValueError):
                    pass                           # a failed part: what the disk took stays
                finally:
                    try:
                        old.close()
                    except OSError:
                        pass
            try:
                if folder:
                    fsync_folder(self.folder)
                if batch and f is not None:
                    os.fdatasync(f.fileno())
            except (OSError, ValueError) as exc:   # ValueError: closed by a failed write
                with self._cv:
                    if self.failed is None and isinstance(exc, OSError):
                        self._fail(exc)
                continue
            if batch:                              # in f, or in a part just synced above
                self._synced(batch)

    def _synced(self, batch: list[float]) -> None:
        now = self.clock()
        dur = self.durability
        dur.lines += len(batch)
        dur.syncs += 1
        dur.waited_max = max(dur.waited_max, len(batch))
        dur.latencies_s.extend(now - t for t in batch)
        waited = now - batch[0]
        if len(batch) > 1 and waited >= self.SLOW_S and self._slow_log.due("slow", now):
            log.warning("recording %s: the disk is slower than the frames: %d lines waited "
                        "%.0f ms for one sync", self.path, len(batch), waited * 1e3)

    @property
    def caught_up(self) -> bool:
        """Has the syncer synced and closed everything written (it waits for more)?"""
        with self._cv:
            return not (self._syncing or self._unsynced or self._retired or self._folder_dirty)

    def _stop_syncer(self, timeout_s: float = 30.0) -> bool:
        """Let the syncer finish what is left; False when the disk did not let it."""
        with self._cv:
            self._closing = True
            self._cv.notify()
        self._syncer.join(timeout_s)
        return not self._syncer.is_alive()
