"""The supervised installation's side of the kiosk supervisor (:mod:`tabletop.kiosk.supervisor`):
knowing it runs supervised, and ending when its supervisor is gone."""

from __future__ import annotations

import logging
import os
import threading

log = logging.getLogger("tabletop")


def supervised() -> bool:
    """True in the child process the kiosk supervisor started."""
    return os.environ.get("TABLETOP_SUPERVISED") == "1"


def follow_supervisor(stop: threading.Event, every_s: float = 0.5) -> threading.Thread:
    """In the supervised installation: set ``stop`` when the supervisor that started it is gone
    (this process handed to another parent), so the installation ends cleanly (its recording
    closed, its status "stopped") instead of running on unsupervised. Without it a supervisor
    killed outright (``kill -9``, an out-of-memory kill) would leave the table running for good
    without stall or crash restarts, holding its ports and camera against the next kiosk start
    and writing the status file beside it (systemd's unit kills it; a start from a shell
    script, a desktop's autostart or a terminal does not). Polls ``os.getppid`` every
    ``every_s`` against the pid the supervisor put in ``TABLETOP_SUPERVISOR_PID``, first at
    once; the parent is named by the supervisor, not read here, because here is after the
    runtime's imports (0.5-2 s after the start): a supervisor that died in between would leave
    the new parent read as the supervisor, and the installation running on for good."""
    named = os.environ.get("TABLETOP_SUPERVISOR_PID", "")
    parent = int(named) if named.isdigit() else os.getppid()

    def watch() -> None:
        while True:
            if os.getppid() != parent:
                log.error("the kiosk supervisor (pid %d) is gone: the installation stops (the "
                          "next kiosk start runs it again)", parent)
                stop.set()
                return
            if stop.wait(every_s):
                return

    th = threading.Thread(target=watch, name="follow-supervisor", daemon=True)
    th.start()
    return th
