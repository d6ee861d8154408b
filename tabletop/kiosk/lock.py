"""One kiosk per installation folder: an advisory lock on ``.kiosk.tabletop-lock`` beside the
config file, held for the kiosk's life.

Two kiosks on one folder (the systemd service and a technician's ``tabletop run --kiosk``)
would share the status file, the logs and the recordings with nothing between them, fight over
the camera and the ports, and ``status.json`` would tell a mix of both: the second start is
refused in one line naming the folder and the running kiosk's process id (exit status 2).

The lock is ``fcntl.flock`` on the file's open description: the kernel drops it when the last
process holding it ends, however it ends, so a kill -9 or a power cut never leaves a stale lock
that blocks the next start. The supervisor hands the description to the installation and its
warm spares (they are the same kiosk, never refused), so a supervisor killed outright keeps
the folder locked until its installation has ended too (within a second, see
:func:`tabletop.kiosk.supervised.follow_supervisor`). The file holds the locking process's pid,
for the refusal's line only; its presence means nothing.
"""

from __future__ import annotations

import errno
import fcntl
import logging
import os
from pathlib import Path

from tabletop.errors import InputError
from tabletop.file_io import alive

log = logging.getLogger("tabletop")

LOCK_NAME = ".kiosk.tabletop-lock"


class KioskBusy(InputError):
    """Another kiosk holds the folder's lock."""


def lock_folder(folder: Path) -> int | None:
    """Take ``folder``'s kiosk lock and return its file descriptor (keep it open for the
    kiosk's life); KioskBusy naming the folder and the holder's pid when another kiosk has it.
    A lock file this account cannot write (the service's, 0644, for a technician's start; a
    read-only remount) is locked read-only, without the pid: flock needs no write access,
    and a technician's kiosk ran unlocked beside the service. A folder where the lock file
    cannot be made at all is logged and run unlocked (None): a kiosk that does not start is
    worse than one unguarded."""
    folder = Path(folder).resolve()
    path = folder / LOCK_NAME
    writable = True
    try:
        try:
            fd = os.open(path, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC, 0o644)
        except OSError as exc:
            if not isinstance(exc, PermissionError) and exc.errno != errno.EROFS:
                raise
            try:
                fd, writable = os.open(path, os.O_RDONLY | os.O_CLOEXEC), False
            except FileNotFoundError:   # no lock file to lock read-only: why it was not made
                raise exc from None
    except OSError as exc:
        return _unguarded("made", path, exc)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        holder = _read_pid(fd)
        os.close(fd)
        if holder and not alive(holder):   # a supervisor gone, its installation ending,
            # or a holder that could not write its own pid (a read-only lock file)
            raise KioskBusy(f"another kiosk is running on {folder} (lock {LOCK_NAME}; the pid "
                            f"written there, {holder}, has ended: a kiosk still ending, or one "
                            f"that could not write its pid); try again in a few seconds, or "
                            f"stop it first") from None
        who = f"pid {holder}" if holder else "its pid not yet written"
        raise KioskBusy(f"another kiosk is running on {folder} ({who}, lock {LOCK_NAME}); "
                        f"stop it first, or start this one from another folder") from None
    except OSError as exc:      # a file system without flock (some network mounts)
        os.close(fd)
        return _unguarded("taken", path, exc)
    if writable:
        _write_pid(fd, path)
    return fd


def _unguarded(what: str, path: Path, exc: OSError) -> None:
    """The lock file ``path`` cannot be made or ``what`` ("taken"): logged; the kiosk runs
    unlocked (None)."""
    log.warning("kiosk lock %s cannot be %s (%s): a second kiosk on %s would not be refused",
                path, what, exc.strerror or exc, path.parent)
    return None


def _write_pid(fd: int, path: Path) -> None:
    """Write this process's pid in the held lock file ``path``, for a refused start's line. A
    write that fails (a full disk, a quota, EIO) is logged and skipped, so a full disk never
    stops a kiosk start ("No space left on device") where the table can play on; the lock is
    held all the same, and a refusal then says the pid is not written."""
    try:
        os.ftruncate(fd, 0)
        os.pwrite(fd, f"{os.getpid()}\n".encode(), 0)
    except OSError as exc:
        log.warning("kiosk lock %s: held, but this kiosk's pid cannot be written in it (%s)",
                    path, exc.strerror or exc)


def _read_pid(fd: int) -> int | None:
    """The pid written in the lock file, or None (empty: its holder is just starting)."""
    try:
        text = os.pread(fd, 32, 0).decode("ascii", "replace").strip()
        return int(text) if text.isdigit() else None
    except OSError:
        return None
