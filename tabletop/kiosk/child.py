"""One run of the installation as the kiosk supervisor (:mod:`tabletop.kiosk.supervisor`) sees
it: the child process started with the supervisor's environment, a warm spare waiting for its
``go`` on stdin, the last lines it wrote to stderr (for the crash log) and a pidfd readable
when it ends."""

from __future__ import annotations

import collections
import os
import subprocess
import sys
import threading
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Sequence


@dataclass
class Child:
    """One run of the installation as seen by the supervisor (clock times in seconds)."""

    process: subprocess.Popen
    started: float
    tail: collections.deque = field(default_factory=lambda: collections.deque(maxlen=40))
    ready_at: float | None = None
    reloading_at: float | None = None  # its RELOADING=1 (a config edit's rebuild), until READY=1
    last_ping: float | None = None
    reader: threading.Thread | None = None
    exit_fd: int | None = None        # a pidfd, readable when the process ends (Linux >= 5.3)
    warm: bool = False                # a spare that was prepared before its start
    why: str = ""                     # how it failed, for the crash log
    number: int = 0                   # which start of the supervisor (1, 2, ...)
    ended: float | None = None
    ran_s: float = 0.0                # seconds from its start to its end
    muted: bool = False               # its stderr is no longer echoed (see Supervisor._watch)

    def close(self) -> None:
        if self.exit_fd is not None:
            os.close(self.exit_fd)
            self.exit_fd = None


def child_env(base: dict[str, str], notify_socket: Path, restarts: int,
              spare: bool) -> dict[str, str]:
    """The environment of a child of the supervisor: ``base`` with the supervisor's notify
    socket, its restarts so far, and (``spare``) the wait for ``go`` on stdin."""
    # TABLETOP_DEBUG: an escaping exception prints its traceback, for the crash log
    # TABLETOP_SUPERVISOR_PID: the installation follows this process (follow_supervisor)
    # PYTHONSAFEPATH (Python 3.11+): ``python -m tabletop`` puts the current folder first
    # on the import path, so a gallery folder holding a copy of ``behaviors/`` (for its
    # library) or ``tracking/`` ran that copy's code instead of the installed one's
    env = dict(base, NOTIFY_SOCKET=str(notify_socket), TABLETOP_SUPERVISED="1",
               TABLETOP_SUPERVISOR_PID=str(os.getpid()),
               TABLETOP_RESTARTS=str(restarts), TABLETOP_DEBUG="1", PYTHONSAFEPATH="1")
    env.pop("WATCHDOG_USEC", None)
    env.pop("WATCHDOG_PID", None)
    if spare:
        env["TABLETOP_WAIT_GO"] = "1"
    return env


def start_child(command: Sequence[str], env: dict[str, str], spare: bool,
                keep_fds: Sequence[int], clock: Callable[[], float], echo: bool) -> Child:
    """Start ``command`` (a spare: its stdin a pipe for ``go``), holding ``keep_fds`` too; its
    stderr is kept in the child's tail and (``echo``) written to ours."""
    p = subprocess.Popen(list(command), env=env,
                         stdin=subprocess.PIPE if spare else subprocess.DEVNULL,
                         stderr=subprocess.PIPE, text=True, errors="replace",
                         pass_fds=tuple(keep_fds))
    child = Child(p, clock())
    try:
        child.exit_fd = os.pidfd_open(p.pid)
    except (AttributeError, OSError):          # older kernels: polled every 50 ms
        child.exit_fd = None
    child.reader = threading.Thread(target=_read_stderr, args=(child, echo), daemon=True)
    child.reader.start()
    return child


def _read_stderr(child: Child, echo: bool) -> None:
    assert child.process.stderr is not None
    for line in child.process.stderr:
        child.tail.append(line.rstrip("\n"))
        if echo and not child.muted:
            sys.stderr.write(line)
            sys.stderr.flush()


def end_child(child: Child) -> None:
    """Kill ``child`` if it still runs, wait for it and close its pidfd."""
    if child.process.poll() is None:
        child.process.kill()
    child.process.wait()
    child.close()
