"""The status file's fields (listed in :mod:`tabletop.kiosk.health`), built by one function for
both of its writers: the installation's :class:`~tabletop.kiosk.health.HealthReporter` and the
supervisor's "restarting" after a crash (:func:`tabletop.kiosk.crash_log.restarting_status`).

Imports nothing of the project at import time: the supervisor loads none of the installation's
modules (it starts sooner at boot and holds less memory for weeks; bench/cold_start.py)."""

from __future__ import annotations

import datetime as _dt
import json
import logging
import os
import socket
from pathlib import Path
from typing import Any

from tabletop import __version__

log = logging.getLogger("tabletop")

#: The fields of the installation's parts, with their value where the writer does not know
#: them (a part that is off, or the supervisor between two installations): every status holds
#: every field the README promises, so a script reading ``status["studio"]`` never fails.
PART_FIELDS: dict[str, Any] = {
    "idle_s": None, "config": None, "config_error": None, "config_pending": None,
    "studio": None, "recording": None, "snapshots": None, "behavior_errors": []}


def utc_now() -> str:
    """The time now, UTC, ISO 8601 to the second."""
    return _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds")


def supervisor_pid() -> int | None:
    """The pid of the supervisor this process runs under (``TABLETOP_SUPERVISOR_PID``, which
    it sets for its installations), None when unsupervised or unreadable."""
    named = os.environ.get("TABLETOP_SUPERVISOR_PID", "")
    return int(named) if named.isdigit() else None


def own_status(name: str, mode: str, uptime_s: float = 0.0, ticks: int = 0, errors: int = 0,
               restarts: int = 0, pid: int | None = -1, supervisor: int | None = -1,
               **known: Any) -> dict[str, Any]:
    """A status told without a frame (no sources, 0 fps): ``name`` (the host's name when
    empty), ``mode``, ``uptime_s`` (seconds), ``ticks``, engine/sink ``errors``, ``restarts``
    by the supervisor, ``pid`` (the installation's; -1: this process's, None: none runs),
    ``supervisor`` (``supervisor_pid``: -1: :func:`supervisor_pid`), the ``known`` fields
    (e.g. ``config``, ``crash``) and :data:`PART_FIELDS` for the rest."""
    host = socket.gethostname()
    status = {"name": name or host, "host": host,
              "pid": os.getpid() if pid == -1 else pid,
              "supervisor_pid": supervisor_pid() if supervisor == -1 else supervisor,
              "version": __version__,
              "time": utc_now(), "uptime_s": uptime_s, "fps": 0.0, "ticks": ticks,
              "mode": mode, "unhealthy_sources": 0, "sources": [], "errors": errors,
              "restarts": restarts}
    status.update({k: list(v) if isinstance(v, list) else v for k, v in PART_FIELDS.items()})
    status.update(known)
    return status


def status_text(status: dict[str, Any]) -> str:
    """The status as the file and the heartbeat carry it: one line of compact JSON."""
    return json.dumps(status, separators=(",", ":"), allow_nan=False) + "\n"


def write_status(path: Path, text: str) -> bool:
    """Write the status ``text`` to the status file ``path`` atomically, its folder made; a
    file that cannot be written (a full disk) is one log line and False."""
    from tabletop.files import atomic_write_text   # (numpy: loaded only once it writes)
    from tabletop.frames import InputError
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        atomic_write_text(path, text)
    except (OSError, InputError) as exc:
        log.warning("status file %s not written: %s", path, getattr(exc, "strerror", None) or exc)
        return False
    return True
