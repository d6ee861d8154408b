"""The kiosk's crash log (``logs/crashes.log``): one entry per crash or stall of the supervised
installation (UTC time, what happened, how long it ran in seconds, the last lines it wrote to
stderr), appended and fsynced by the supervisor (:mod:`tabletop.kiosk.supervisor`), rotated
as the kiosk's log is: unrotated, a table crashing every half minute for weeks (the longest
back-off) grows it ~9 MB a day (3.3 KB a crash). With each entry the supervisor writes the
status file's "restarting" (:func:`restarting_status`)."""

from __future__ import annotations

import logging
import os
import re
import signal
from pathlib import Path
from typing import Any, Iterable, Sequence

from tabletop.kiosk.status_fields import own_status, utc_now

log = logging.getLogger("tabletop")

#: A line saying why an installation ended: its one error line (``tabletop run: error: ...``,
#: ``... internal error: ...``), an ERROR or CRITICAL log line, or a native crash's first line.
ERROR_LINE = re.compile(r"tabletop[^:]*: (internal )?error: |tabletop: (ERROR|CRITICAL): "
                        r"|Fatal Python error: ")
#: A log line of no error (every line logged to stderr begins "tabletop: LEVEL: ").
CALM_LINE = re.compile(r"tabletop: (DEBUG|INFO|WARNING): ")


def crash_entry(crash: int, what: str, ran_s: float, pid: int, start: int,
                tail: Iterable[str]) -> list[str]:
    """The lines of crash number ``crash``: a header stamped now (UTC) naming ``what`` befell
    the child ``pid`` (the supervisor's ``start``-th) after ``ran_s`` seconds, then its
    stderr ``tail`` indented."""
    lines = [f"=== {utc_now()} crash {crash}: {what}, after {ran_s:.1f} s "
             f"(pid {pid}, start {start})"]
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


def restarting_status(name: str, crashes: int, what: str, ran_s: float,
                      tail: Sequence[str], **known: Any) -> dict[str, Any]:
    """The status the supervisor writes after a crash, until the next installation writes its
    own: ``mode`` "restarting" and ``crash`` naming what befell it after ``ran_s`` seconds with
    its last error line (:func:`last_error` of its stderr ``tail``); the ``known`` fields (the
    ``config`` file) and every other field the status promises, null where only the
    installation knows it (:func:`tabletop.kiosk.status_fields.own_status`). Without it the
    status file would hold the last installation's own words ("live", or "stopped" from a
    kiosk that ended on purpose) while a kiosk whose every start fails restarts for ever, its
    heartbeat silent. No installation runs meanwhile: ``pid`` is null and ``supervisor_pid``
    the writer's own (the supervisor's), never a pid that could be taken for the table's."""
    last = last_error(tail)
    return own_status(name, "restarting", restarts=crashes, pid=None, supervisor=os.getpid(),
                      crash=f"{what} after {ran_s:.1f} s" + (f": {last}" if last else ""),
                      **known)


def last_error(tail: Sequence[str]) -> str:
    """The line of stderr ``tail`` that says why the installation ended: the last one that is
    an error (a traceback's closing exception line, or an :data:`ERROR_LINE`), else the last
    unindented line that is not a :data:`CALM_LINE`, else the last line ("" for none). Every
    line logged to stderr begins "tabletop", so the last such line was most often an INFO."""
    lines = [t.rstrip() for t in tail if t.strip()]
    found, in_traceback = "", False
    for t in lines:
        if t.startswith("Traceback (most recent call last):"):
            in_traceback = True
        elif in_traceback and not t[:1].isspace():
            found, in_traceback = t, False        # the exception that ends the traceback
        elif ERROR_LINE.match(t):
            found = t
    if found:
        return found.strip()
    plain = [t for t in lines if not t[:1].isspace() and not CALM_LINE.match(t)]
    return (plain or lines or [""])[-1].strip()


def describe_exit(code: int) -> str:
    """What ended a child, as an entry says it: its exit status, or the signal (a negative
    ``code``, as :class:`subprocess.Popen` gives it)."""
    if code < 0:
        try:
            return f"killed by {signal.Signals(-code).name}"
        except ValueError:
            return f"killed by signal {-code}"
    return f"exit status {code}"
