"""The kiosk's rotating log, written by several processes at once: the supervisor, its
installation and the warm spares each log into the same ``logs/tabletop.log``.

logging's ``RotatingFileHandler`` assumes it is the file's only writer: the process that rotates
renames the file under the others, which write on into the renamed file, and a later rotation
deletes it. Measured with the supervisor logging a line every 0.15 s beside an installation
logging 1,500 lines (10 kB files, 3 backups): none of the supervisor's 60 lines was left in
any file, not even those written after the installation had stopped; in a gallery, every restart
and crash line the supervisor wrote after the installation's log had rotated ``log_backups``
times went into a deleted file, for weeks. :class:`SharedRotatingFileHandler` writes each record
under an exclusive ``flock`` of the log's folder (shared by every process that logs there),
first reopening the log when the path names another file than the one it holds (another process
rotated it), so every process writes to the current file and only one rotates it.
"""

from __future__ import annotations

import fcntl
import logging
import logging.handlers
import os
from pathlib import Path


class SharedRotatingFileHandler(logging.handlers.RotatingFileHandler):
    """A ``RotatingFileHandler`` that processes writing the same file share (module docstring)."""

    def __init__(self, path: Path, max_bytes: int, backups: int) -> None:
        super().__init__(path, maxBytes=max_bytes, backupCount=backups, encoding="utf-8")
        self._folder = os.open(os.path.dirname(self.baseFilename), os.O_RDONLY)

    def emit(self, record: logging.LogRecord) -> None:
        try:
            fcntl.flock(self._folder, fcntl.LOCK_EX)
        except OSError:   # no lock (a closed handler): written as a lone writer would
            super().emit(record)
            return
        try:
            self._follow()
            super().emit(record)
        finally:
            fcntl.flock(self._folder, fcntl.LOCK_UN)

    def _follow(self) -> None:
        """Reopen the log when its path names another file than the open one (rotated by
        another process, or removed); a path that cannot be opened keeps the open file."""
        if self.stream is None:
            return
        try:
            st = os.stat(self.baseFilename)
            same = os.path.samestat(st, os.fstat(self.stream.fileno()))
        except OSError:
            same = False
        if same:
            return
        try:
            os.makedirs(os.path.dirname(self.baseFilename), exist_ok=True)
            stream = self._open()
        except OSError:
            return
        self.stream.close()
        self.stream = stream

    def close(self) -> None:
        super().close()
        if self._folder >= 0:
            os.close(self._folder)
            self._folder = -1
