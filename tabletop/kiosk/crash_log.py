"""The kiosk's crash log (``logs/crashes.log``): one entry per crash or stall of the supervised
installation (UTC time, what happened, how long it ran in seconds, the last lines it wrote to
stderr), appended and fsynced by the supervisor (:mod:`tabletop.kiosk.supervisor`), rotated
as the kiosk's log is: unrotated, a table crashing every half minute for weeks (the longest
back-off) grows it ~9 MB a day (3.3 KB a crash)."""

from __future__ import annotations

import datetime as _dt
import os
from pathlib import Path
from typing import Iterable


def crash_entry(crash: int, what: str, ran_s: float, pid: int, start: int,
                tail: Iterable[str]) -> list[str]:
    """The lines of crash number ``crash``: a header stamped now (UTC) naming ``what`` befell
    the child ``pid`` (the supervisor's ``start``-th) after ``ran_s`` seconds, then its
    stderr ``tail`` indented."""
    stamp = _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds")
    lines = [f"=== {stamp} crash {crash}: {what}, after {ran_s:.1f} s (pid {pid}, start {start})"]
    return lines + [f"  {t}" for t in tail]


def append_crash(path: Path, lines: list[str], max_bytes: int, backups: int) -> None:
    """Append ``lines`` to the crash log at ``path`` (its folder made, rotated first when it has
    reached ``max_bytes``), fsynced; OSError when it cannot be written."""
    path.parent.mkdir(parents=True, exist_ok=True)
    rotate(path, max_bytes, backups)
    with open(path, "a", encoding="utf-8") as f:
        f.write("\n".join(lines) + "\n")
        f.flush()
        os.fsync(f.fileno())


def rotate(path: Path, max_bytes: int, backups: int) -> None:
    """``crashes.log`` -> ``crashes.log.1`` -> ... ``.N`` (``backups``) once it has reached
    ``max_bytes``, as logging's RotatingFileHandler does."""
    if not path.exists() or path.stat().st_size < max_bytes:
        return
    for i in range(backups - 1, 0, -1):
        older = path.with_name(f"{path.name}.{i}")
        if older.exists():
            os.replace(older, path.with_name(f"{path.name}.{i + 1}"))
    os.replace(path, path.with_name(f"{path.name}.1"))
