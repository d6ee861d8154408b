"""The kiosk's rotating log, written by several processes at once: the supervisor, its
installation and the warm spares each log into the same ``logs/tabletop.log``.

logging's ``RotatingFileHandler`` assumes it is the file's only writer: the process that rotates
renames the file under the others, which write on into the renamed file, and a later rotation
deletes it. Measured with the supervisor logging a line every 0.15 s beside an installation
logging 1,500 lines (10 kB files, 3 backups): none of the supervisor's 60 lines was left in
any file, not even those written after the installation had stopped: every restart and crash
line the supervisor writes after the installation's log has rotated ``log_backups`` times would
go into a deleted file. :class:`SharedRotatingFileHandler` writes each record
under an exclusive ``flock`` of a lock file beside the log (``.tabletop.log.lock``, shared by
every process that logs there), first reopening the log when the path names another file than
the one it holds (another process rotated it), so every process writes to the current file and
only one rotates it.

The lock is a regular file opened for writing, not the folder: on NFS flock is emulated by
POSIX locks, which need a file open for writing (man 2 flock), so a folder's LOCK_EX fails there
with EBADF. The lock file is reopened when its path names another file (the folder was removed
and recreated), so old and new processes keep locking the same file. The lock is taken
non-blocking, retried for up to :data:`LOCK_WAIT_S`: a holder frozen inside its write (SIGSTOP,
a debugger, a cgroup freeze, a hung disk) would otherwise hold every process's logging without
bound, the supervisor's stall restart included; past the wait the record is written without the
lock (counted in ``unlocked``), still following rotations. Where no lock can be taken at all the
handler says so once on stderr and writes the same way. A closed handler writes as a lone
writer would, and never raises out of the logger.

A log that cannot be written (its disk full, a read-only remount) is said once on stderr, where
every line still goes (the journal under systemd), and once more when it is written again, with
the count of lines that failed; logging's own handling prints a 35-line traceback to stderr for
every line (a kiosk's start on a full disk: 349 lines of stderr for 8 log lines, 11 here).
"""

from __future__ import annotations

import fcntl
import logging
import logging.handlers
import os
import sys
import time
from pathlib import Path
from typing import IO, Any

LOCK_WAIT_S = 0.08
"""Seconds a record waits for the lock before it is written without it."""


class SharedRotatingFileHandler(logging.handlers.RotatingFileHandler):
    """A ``RotatingFileHandler`` that processes writing the same file share (module docstring).
    ``unlocked``: records written without the lock because its holder kept it past the wait."""

    def __init__(self, path: Path, max_bytes: int, backups: int) -> None:
        super().__init__(path, maxBytes=max_bytes, backupCount=backups, encoding="utf-8")
        folder, name = os.path.split(self.baseFilename)
        self.lock_path = os.path.join(folder, f".{name}.lock")
        self._lock_fd = -1
        self._warned = False
        self.unlocked = 0
        self.missed = 0          # lines whose write failed (OSError) since the log last worked
        self._failed_now = False

    def emit(self, record: logging.LogRecord) -> None:
        fd = self._lock_file()
        locked = fd >= 0 and self._take(fd)
        try:
            self._follow()
            self._failed_now = False
            super().emit(record)          # an error comes back through handleError
            if self.missed and not self._failed_now:
                print(f"tabletop log: {self.baseFilename} written again ({self.missed} lines "
                      "failed meanwhile)", file=sys.stderr)
                self.missed = 0
        finally:
            if locked:
                try:
                    fcntl.flock(fd, fcntl.LOCK_UN)
                except (OSError, ValueError):
                    pass

    def handleError(self, record: logging.LogRecord) -> None:
        """A write that failed with an OSError: said once (module docstring), counted."""
        exc = sys.exc_info()[1]
        if not isinstance(exc, OSError):
            super().handleError(record)
            return
        self._failed_now = True
        if not self.missed:
            print(f"tabletop log: cannot write {self.baseFilename}: {exc.strerror or exc}; "
                  "its lines go to stderr only until it can be written again", file=sys.stderr)
        self.missed += 1

    def _lock_file(self) -> int:
        """The open lock file's descriptor, reopened when its path names another file; -1 when
        the handler is closed or the file cannot be opened."""
        if self._closed:
            return -1
        if _same_file(self.lock_path, self._lock_fd):
            return self._lock_fd
        try:
            os.makedirs(os.path.dirname(self.lock_path), exist_ok=True)
            fd = os.open(self.lock_path, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC, 0o644)
        except OSError as exc:
            self._warn(f"cannot open {self.lock_path} ({exc.strerror})")
            return -1
        self._drop_lock_file()
        self._lock_fd = fd
        return fd

    def _take(self, fd: int) -> bool:
        """Whether the exclusive lock was taken within :data:`LOCK_WAIT_S`."""
        deadline = time.monotonic() + LOCK_WAIT_S
        while True:
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
                return True
            except BlockingIOError:
                if time.monotonic() >= deadline:
                    self.unlocked += 1
                    return False
                time.sleep(0.002)
            except (OSError, ValueError) as exc:
                self._warn(f"cannot lock {self.lock_path} ({exc})")
                return False

    def _warn(self, why: str) -> None:
        if not self._warned:
            self._warned = True
            print(f"tabletop log: {why}; writing without the shared lock, so lines of "
                  f"processes rotating the log at the same moment may be lost", file=sys.stderr)

    def _follow(self) -> None:
        """Reopen the log when its path names another file than the open one (rotated by
        another process, or removed); a path that cannot be opened keeps the open file."""
        if self.stream is None:
            return
        if _same_file(self.baseFilename, self.stream):
            return
        try:
            os.makedirs(os.path.dirname(self.baseFilename), exist_ok=True)
            stream = self._open()
        except OSError:
            return
        self.stream.close()
        self.stream = stream

    def _drop_lock_file(self) -> None:
        if self._lock_fd >= 0:
            try:
                os.close(self._lock_fd)
            except OSError:
                pass
            self._lock_fd = -1

    def close(self) -> None:
        self.acquire()
        try:
            super().close()
            self._drop_lock_file()
        finally:
            self.release()


def _same_file(path: str, f: int | IO[Any]) -> bool:
    """Whether ``path`` names the file open as ``f`` (a descriptor or a file object); a path or
    file that cannot be read (missing, closed, -1) counts as another file."""
    try:
        return os.path.samestat(os.stat(path), os.fstat(f if isinstance(f, int) else f.fileno()))
    except (OSError, ValueError):
        return False
