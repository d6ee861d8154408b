"""The kiosk supervisor: runs the installation in a child process and keeps it running.

- A child that exits with an error or a signal (a crash) is logged to the crash log (time,
  exit status, how long it ran, the last lines it wrote to stderr) and started again: at once
  after a first failure, then after a back-off of ``backoff_s[0]`` for the second failure in a
  row, doubled after each one up to ``backoff_s[1]``, and back to at once after a child has run
  ``healthy_s``. The crash log is written once the next child is started.
- A stall is a child whose frame loop stopped: no ``WATCHDOG=1`` for ``stall_s`` after its
  ``READY=1`` (or no ``READY=1`` within ``startup_s``, also after a ``RELOADING=1``: the
  child rebuilds for a config edit, its frame loop paused, as long as a start may take). It is
  killed (SIGKILL: a frozen loop cannot act on SIGTERM), logged as a crash and restarted the
  same way.
- The child speaks systemd's notify protocol to the supervisor's own socket (``$NOTIFY_SOCKET``
  of the child); the supervisor relays ``READY=1`` and the child's ``WATCHDOG=1`` pings to
  systemd, and pings for itself only while a child is restarting (systemd's watchdog runs
  from the first READY). So the service's watchdog follows the frame loop, and
  ``NotifyAccess=main`` is enough.
- SIGTERM, SIGINT or SIGHUP (a closed terminal) stop the child cleanly (SIGTERM, then SIGKILL
  after ``stop_timeout_s``).
- A child that exits 0 ended on purpose (Esc, ``--seconds``): the supervisor ends too, and so
  with ``EXIT_RECORDING_FAILED`` (3: ended on purpose, its recording failed, e.g. a full disk),
  which it passes on (restarted, a ``--seconds`` kiosk on a full disk would never end: each
  new child fails its recording again and exits 3 after its seconds).
- Warm spares (``spares``, 2): the next children are started early (with the first child,
  then once a child is ready) and wait for ``go RESTARTS`` on their stdin (``$TABLETOP_WAIT_GO``)
  with their libraries imported, config validated and engines built
  (:mod:`tabletop.kiosk.spare`); a restart then costs opening the sources and the window and
  drawing a frame. The oldest spare goes first: with two, a crash and then a stall soon after
  both find a spare that finished preparing, even on a loaded machine. A child's exit is seen
  at once (a pidfd in the supervisor's wait).
"""

from __future__ import annotations

import collections
import json
import logging
import os
import select
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Sequence

from tabletop.cli import EXIT_RECORDING_FAILED, catch_stop_signals
from tabletop.kiosk.child import Child, child_env, end_child, start_child
from tabletop.kiosk.crash_log import (append_crash, crash_entry, describe_exit,
                                      restarting_status)
from tabletop.kiosk.health import Heartbeat
from tabletop.kiosk.status_fields import status_text, utc_now, write_status
from tabletop.kiosk.notify import Notifier
from tabletop.kiosk.paths import kiosk_log, kiosk_paths

log = logging.getLogger("tabletop")


@dataclass
class Policy:
    """When the supervisor restarts (seconds)."""

    stall_s: float = 5.0
    backoff_s: tuple[float, float] = (0.1, 30.0)
    healthy_s: float = 60.0
    startup_s: float = 60.0
    stop_timeout_s: float = 10.0

    def delay(self, failures: int) -> float:
        """Wait before the restart after ``failures`` failures in a row (>= 1): none after
        the first, then ``backoff_s[0]`` doubling up to ``backoff_s[1]``."""
        if failures <= 1:
            return 0.0
        lo, hi = self.backoff_s
        return min(hi, lo * 2.0 ** (failures - 2))


class Supervisor:
    """Keeps ``command`` running; see the module docstring."""

    EVENTS_KEPT = 1000

    def __init__(self, command: Sequence[str], policy: Policy, crash_log: Path,
                 env: dict[str, str] | None = None, notifier: Notifier | None = None,
                 echo: bool = True, clock: Callable[[], float] = time.monotonic,
                 spares: int = 2, seconds: float | None = None,
                 crash_log_max_bytes: int = 1_000_000, crash_log_backups: int = 5,
                 keep_fds: Sequence[int] = (), status_file: Path | None = None,
                 name: str = "", config: Path | None = None,
                 heartbeat: Heartbeat | None = None) -> None:
        # the status file, "restarting" after a crash until the next child writes its own, also
        # sent as a heartbeat; ``config``, the one field of the installation's parts it knows
        self.status_file, self.name, self.heartbeat = status_file, name, heartbeat
        self._known = {} if config is None else {"config": str(config)}
        self._restarting: dict[str, Any] | None = None   # the last "restarting" written
        # open files every child holds too: the kiosk's folder lock (tabletop.kiosk.lock)
        self.keep_fds = tuple(keep_fds)
        self.command, self.policy, self.crash_log = list(command), policy, Path(crash_log)
        # the crash log rotates as the kiosk's log does (tabletop.kiosk.crash_log)
        self.crash_log_max_bytes, self.crash_log_backups = crash_log_max_bytes, crash_log_backups
        # ``--seconds``: the kiosk stops that long after its first READY, restarts included,
        # counted here and not by the child (a child given ``--seconds`` runs them again after
        # each restart: a 40 s drill ran 70 s)
        self.seconds = seconds
        self._end_at: float | None = None
        self._timed_out = False       # stopped by the end of ``seconds``, not by a signal
        self.env = dict(os.environ if env is None else env)
        self.notifier = notifier or Notifier()
        self.echo, self.clock = echo, clock
        self.stop = threading.Event()
        self.starts = 0
        self.crashes = 0
        # ("ready" | "crash" | "stall", clock time) and, per start, was it a prepared spare:
        # the last EVENTS_KEPT (all of them, for a table crashing every half minute for two
        # weeks, would be 40,000)
        self.events: collections.deque[tuple[str, float]] = collections.deque(
            maxlen=self.EVENTS_KEPT)
        self.warm: collections.deque[bool] = collections.deque(maxlen=self.EVENTS_KEPT)
        self._dir = Path(tempfile.mkdtemp(prefix="tabletop-supervisor-"))
        self.socket_path = self._dir / "notify.sock"
        self._sock = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
        self._sock.bind(str(self.socket_path))
        self._announced = False
        self.spares = max(0, int(spares))
        self._spares: list[Child] = []             # oldest first

    # --- one child --------------------------------------------------------------------------

    def _process(self, spare: bool) -> Child:
        env = child_env(self.env, self.socket_path, self.starts, spare)
        return start_child(self.command, env, spare, self.keep_fds, self.clock, self.echo)

    def _spawn(self) -> Child:
        spare = None
        while self._spares and spare is None:
            spare = self._spares.pop(0)
            if spare.process.poll() is not None:  # a spare that died waiting
                end_child(spare)
                spare = None
        if spare is not None:
            try:
                assert spare.process.stdin is not None
                spare.process.stdin.write(f"go {self.starts}\n")
                spare.process.stdin.flush()
                spare.process.stdin.close()
                child = spare
                child.started, child.warm = self.clock(), True
            except (OSError, ValueError):
                end_child(spare)
                child = self._process(False)
        else:
            child = self._process(False)
        self.starts += 1
        child.number = self.starts
        self.warm.append(child.warm)
        log.info("supervisor: started the installation (pid %d, start %d%s)", child.process.pid,
                 self.starts, ", warm spare" if child.warm else "")
        if not child.warm:            # a cold start: its spares start with it
            self._top_up()
        return child

    def _top_up(self) -> None:
        while len(self._spares) < self.spares:
            self._spares.append(self._process(True))

    def _kill_spares(self) -> None:
        for spare in self._spares:
            end_child(spare)
        self._spares = []

    def _messages(self, timeout: float, child: Child | None = None) -> list[str]:
        """Notify messages waiting or arriving within ``timeout`` s; returns early when
        ``child`` ends."""
        out = []
        fds: list = [self._sock]
        if child is not None and child.exit_fd is not None:
            fds.append(child.exit_fd)
        ready, _, _ = select.select(fds, [], [], timeout)
        ready = [r for r in ready if r is self._sock]
        while ready:
            try:
                data = self._sock.recv(4096, socket.MSG_DONTWAIT)
            except BlockingIOError:
                break
            out.extend(data.decode(errors="replace").splitlines())
        return out

    def _on_message(self, child: Child, msg: str) -> None:
        now = self.clock()
        if msg == "RELOADING=1" and child.ready_at is not None:
            child.ready_at, child.reloading_at = None, now
        elif msg == "READY=1" and child.reloading_at is not None:
            log.info("supervisor: installation rebuilt after %.2f s", now - child.reloading_at)
            child.ready_at, child.last_ping, child.reloading_at = now, now, None
        elif msg == "READY=1" and child.ready_at is None:
            child.ready_at = child.last_ping = now
            self.events.append(("ready", now))
            if self.seconds is not None and self._end_at is None:
                self._end_at = now + self.seconds
            log.info("supervisor: installation ready after %.2f s", now - child.started)
            if not self._announced:
                self._announced = self.notifier.send("READY=1")
            self._top_up()
        elif msg == "WATCHDOG=1":
            child.last_ping = now
            self.notifier.send("WATCHDOG=1")
        elif msg.startswith("STATUS="):
            self.notifier.send(msg)

    def _stalled(self, child: Child) -> str | None:
        now = self.clock()
        if child.ready_at is None:
            if child.reloading_at is not None:   # (the log adds how long it ran)
                if now - child.reloading_at > self.policy.startup_s:
                    return (f"not rebuilt (a config edit's rebuild began "
                            f"{now - child.reloading_at:.1f} s before)")
            elif now - child.started > self.policy.startup_s:
                return "not ready"   # (the log and the crash entry add how long it ran)
            return None
        assert child.last_ping is not None
        if now - child.last_ping > self.policy.stall_s:
            return f"stalled: no frame for {now - child.last_ping:.1f} s"
        return None

    def _crashed(self, child: Child) -> None:
        """Count the crash of ``child``, log it and write the status file's "restarting": before
        the next start (a warm spare's first "live" would otherwise be overwritten by it)."""
        self.crashes += 1
        child.ran_s = (child.ended or self.clock()) - child.started
        if child.reader is not None:
            child.reader.join(timeout=1.0)
        log.error("supervisor: the installation %s after %.1f s; restarting", child.why,
                  child.ran_s)
        if self.status_file is None and self.heartbeat is None:
            return
        self._restarting = restarting_status(self.name, self.crashes, child.why,
                                             child.ran_s, child.tail, **self._known)
        text = status_text(self._restarting)
        if self.heartbeat is not None:
            self.heartbeat.send(self._restarting["name"], 0.0, 0.0, 0, text.rstrip("\n"))
        if self.status_file is not None:
            write_status(self.status_file, text)

    def _log_crash(self, child: Child) -> None:
        """Append the crash of ``child`` to the crash log (fsynced)."""
        lines = crash_entry(self.crashes, child.why, child.ran_s, child.process.pid,
                            child.number, child.tail)
        try:
            append_crash(self.crash_log, lines, self.crash_log_max_bytes, self.crash_log_backups)
        except OSError as exc:
            log.error("supervisor: crash log %s not written: %s", self.crash_log, exc)

    def _stopped(self) -> None:
        """When the supervisor stops: a status file still holding its own "restarting" (a stop
        during the back-off, or before the next installation wrote its first status) says
        "stopped" instead, with the last crash; left as it was, it would tell a stopped kiosk
        from one restarting no more."""
        if self._restarting is None or self.status_file is None:
            return
        try:
            now = json.loads(self.status_file.read_text())
        except (OSError, ValueError):
            now = None
        if now == self._restarting:
            write_status(self.status_file, status_text(dict(now, mode="stopped", time=utc_now())))

    def _terminate(self, child: Child) -> None:
        p = child.process
        if p.poll() is None:
            p.send_signal(signal.SIGTERM)
            try:
                p.wait(self.policy.stop_timeout_s)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()

    def _check_end(self) -> bool:
        """Stop once ``seconds`` have passed since the first READY; is the supervisor stopped?"""
        if self._end_at is not None and self.clock() >= self._end_at and not self._timed_out:
            # said before the installation's own "SIGTERM received: stopping", which alone
            # reads as if someone had stopped the kiosk
            log.info("supervisor: --seconds %g reached: stopping the installation", self.seconds)
            self._timed_out = True
            self.stop.set()
        return self.stop.is_set()

    def _watch(self, child: Child) -> tuple[str, int | None]:
        """Until the child ends: ("exit", code), ("stall", None) or ("stop", None)."""
        last_own_ping = -1e9
        while True:
            self._check_end()
            if self.stop.is_set():
                # the end of ``--seconds`` while a restart is still starting is the timed end,
                # not an interruption: the child's "tabletop run: interrupted" (its SIGTERM
                # during its imports) is not echoed
                child.muted = self._timed_out and child.ready_at is None
                self._terminate(child)
                return "stop", child.process.returncode
            for msg in self._messages(0.05, child):
                self._on_message(child, msg)
            code = child.process.poll()
            if code is not None:
                for msg in self._messages(0.0):
                    self._on_message(child, msg)
                child.close()
                child.ended = self.clock()
                return "exit", code
            why = self._stalled(child)
            if why is not None:
                child.ended = self.clock()
                self.events.append(("stall", child.ended))
                child.process.kill()          # at once: a frozen loop cannot act on SIGTERM
                child.process.wait()
                child.close()
                child.why = why
                return "stall", None
            now = self.clock()
            if child.ready_at is None and self._announced and now - last_own_ping >= 1.0:
                self.notifier.send("WATCHDOG=1")      # restarting: the supervisor vouches
                last_own_ping = now

    # --- the supervisor's loop ----------------------------------------------------------------

    def run(self) -> int:
        """Run until stopped or a child ends on purpose; returns the exit status to use."""
        failures = 0
        try:
            child = self._spawn()
            while not self.stop.is_set():
                how, code = self._watch(child)
                if how == "stop":
                    return EXIT_RECORDING_FAILED if code == EXIT_RECORDING_FAILED else 0
                if how == "exit":
                    if code in (0, EXIT_RECORDING_FAILED):
                        log.info("supervisor: the installation ended; stopping")
                        return code
                    self.events.append(("crash", child.ended))
                    child.why = describe_exit(code)
                ran = (child.ended or self.clock()) - child.started
                failures = 1 if ran >= self.policy.healthy_s else failures + 1
                delay = self.policy.delay(failures)
                failed = child
                self._crashed(failed)
                if delay <= 0:            # back at once; the crash log is written after
                    child = self._spawn()
                    self._log_crash(failed)
                    continue
                self._log_crash(failed)
                end = self.clock() + delay
                while not self._check_end() and self.clock() < end:
                    if self._announced:               # waiting to restart: still in control
                        self.notifier.send("WATCHDOG=1")
                    self.stop.wait(min(1.0, max(0.0, end - self.clock())))
                if self.stop.is_set():
                    return 0
                child = self._spawn()
            self._terminate(child)
            return 0
        finally:
            self._kill_spares()
            self._stopped()
            if self.heartbeat is not None:
                self.heartbeat.close()
            self.notifier.send("STOPPING=1")
            self._sock.close()
            try:
                self.socket_path.unlink()
                self._dir.rmdir()
            except OSError:
                pass


def supervise(config_path: Path, cfg: dict[str, Any], argv: list[str],
              seconds: float | None = None, lock_fd: int | None = None) -> int:
    """Run ``tabletop run ARGV`` under the kiosk supervisor until SIGTERM, SIGINT or SIGHUP, or
    ``seconds`` after the installation was first ready. ``lock_fd``, the folder's kiosk lock,
    is held by every child too."""
    k, hb = cfg["kiosk"], cfg["kiosk"]["heartbeat"]
    paths = kiosk_paths(cfg, config_path.resolve().parent)
    kiosk_log(cfg, paths["log_file"])
    policy = Policy(stall_s=k["stall_s"], backoff_s=tuple(k["backoff_s"]))
    sup = Supervisor([sys.executable, "-m", "tabletop", "run", *argv], policy, paths["crash_log"],
                     spares=k["spares"], seconds=seconds, crash_log_max_bytes=k["log_max_bytes"],
                     crash_log_backups=k["log_backups"],
                     keep_fds=() if lock_fd is None else (lock_fd,),
                     status_file=paths["status_file"], name=k["name"], config=config_path,
                     heartbeat=Heartbeat(hb["host"], hb["port"]) if hb["enabled"] else None)

    def handler(signum: int, _frame: Any) -> None:
        sup.stop.set()

    with catch_stop_signals(handler):
        return sup.run()
