"""Health of a running table: status JSON file, OSC heartbeat, watchdog pings, rotating log.

The status (DESIGN.md, "Network and serial contracts") is one JSON object::

    {"name", "host", "pid" (the installation's; null in the supervisor's "restarting" and
     "stopped"), "supervisor_pid" (the kiosk supervisor's, null when unsupervised), "version",
     "time" (UTC ISO 8601), "uptime_s", "fps", "ticks", "mode" ("live" | "attract" | "one_moment";
     "stopped" in the file and last heartbeat of a kiosk that ended on purpose; "restarting",
     with "crash", written and sent as a heartbeat by the supervisor after a crash:
     :func:`tabletop.kiosk.crash_log.restarting_status`),
     "unhealthy_sources", "sources": [{"name", "ok", "message", "age_s"}], "errors" (engine/sink
     failures so far), "behavior_errors" (["ENGINE: FILE: why"] of behaviour files that went bad,
     of actions' files a character started without and of those that went bad while their action
     plays), "restarts" (by the supervisor), "idle_s" (seconds since a visitor was last seen),
     "config" (file), "config_error" (the last refused edit, or null), "studio" (or null),
     "recording" and "snapshots" (what they write, why they stopped; or null)}

Every ``every_s`` it is written atomically to the status file (in a writer thread: the frame loop
never waits for a disk) and sent as OSC ``/tabletop/heartbeat`` with the installation name
(string), uptime s (float), fps (float), unhealthy sources (int) and the status JSON (string).
The first goes once the loop has a rate (a second of ticks), not with "0 fps" from its first.
"""

from __future__ import annotations

import logging
import math
import os
import socket
import threading
import time
from pathlib import Path
from typing import Any, Callable

from tabletop.files import atomic_write_text
from tabletop.frames import Frame, InputError
from tabletop.kiosk.logfile import SharedRotatingFileHandler
from tabletop.kiosk.notify import Notifier
from tabletop.kiosk.status_fields import own_status, status_text, utc_now, write_status
from tabletop.resolve import Destination

log = logging.getLogger("tabletop")

HEARTBEAT_ADDRESS = "/tabletop/heartbeat"


def setup_log_file(path: Path, max_bytes: int = 1_000_000, backups: int = 5) -> logging.Handler:
    """Add a rotating log file (``max_bytes`` each, ``backups`` kept) to the tabletop logger;
    the kiosk's processes share it (:mod:`tabletop.kiosk.logfile`)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    handler = SharedRotatingFileHandler(path, max_bytes, backups)
    handler.setFormatter(logging.Formatter("%(asctime)s %(process)d %(levelname)s %(message)s"))
    logger = logging.getLogger("tabletop")
    logger.addHandler(handler)
    if logger.level == logging.NOTSET or logger.level > logging.INFO:
        logger.setLevel(logging.INFO)
    return handler


class LatestWriter:
    """Writes the newest text given to a file atomically, in its own thread; an older text not
    yet written is replaced, never queued. :meth:`close` waits at most ``close_wait_s``
    (seconds) for a write in progress."""

    close_wait_s = 5.0

    def __init__(self, path: Path) -> None:
        self.path = path
        self._text: str | None = None
        self._cv = threading.Condition()
        self._closed = False
        self._ended = False      # the thread has left (under _cv): a last text is the caller's
        self.written = 0
        self.failed = 0  # writes failed in a row
        self._thread = threading.Thread(target=self._run, name="status-writer", daemon=True)
        self._thread.start()

    def put(self, text: str) -> None:
        with self._cv:
            self._text = text
            self._cv.notify()

    def _run(self) -> None:
        try:
            self._serve()
        finally:
            with self._cv:
                self._ended = True

    def _serve(self) -> None:
        while True:
            with self._cv:
                while self._text is None and not self._closed:
                    self._cv.wait()
                text, self._text = self._text, None
                if text is None:
                    self._ended = True
                    return
            try:
                self.path.parent.mkdir(parents=True, exist_ok=True)
                atomic_write_text(self.path, text)
            except (OSError, InputError) as exc:  # said once, not every second for weeks
                self.failed += 1
                if self.failed == 1:
                    log.warning("status file %s not written: %s; retrying at every heartbeat",
                                self.path, getattr(exc, "strerror", None) or exc)
                continue
            if self.failed:
                log.info("status file %s written again", self.path)
            self.written, self.failed = self.written + 1, 0

    def close(self) -> None:
        """Write what is pending and end the thread, waiting at most :attr:`close_wait_s`
        seconds for it."""
        with self._cv:
            self._closed = True
            self._cv.notify()
        self._thread.join(timeout=self.close_wait_s)

    def last(self, text: str) -> bool:
        """Have the thread write ``text`` as the file's last text, after the write it is in
        (a slow fsync outlasting :meth:`close`'s wait) and instead of any text still pending;
        False when the thread has ended and the caller writes it. Written beside a thread
        still busy, a "stopped" was overwritten by the thread's late "live"."""
        with self._cv:
            if self._ended:
                return False
            self._text = text
            self._cv.notify()
            return True


class Heartbeat:
    """OSC heartbeat sender (UDP; a broadcast address is allowed). Never raises."""

    def __init__(self, host: str, port: int) -> None:
        from pythonosc.osc_message_builder import OscMessageBuilder
        self._builder = OscMessageBuilder
        self.address = (host, int(port))
        # a host name is looked up away from the frame loop (see tabletop.resolve); sent from
        # the frame loop, so non-blocking as the tuio sink's: a full send buffer drops the
        # heartbeat (an OSError, counted and said once) instead of holding the loop
        self.destination = Destination("heartbeat", host, port, log, blocking=False)
        self.sent = 0
        self.failing = 0   # sends failed in a row: the first is said, and the return

    def send(self, name: str, uptime_s: float, fps: float, unhealthy: int, status: str) -> None:
        b = self._builder(HEARTBEAT_ADDRESS)
        b.add_arg(name, "s")
        b.add_arg(float(uptime_s), "f")
        b.add_arg(float(fps), "f")
        b.add_arg(int(unhealthy), "i")
        b.add_arg(status, "s")
        try:
            if not self.destination.sendto(b.build().dgram):
                return   # the name is being looked up, or did not resolve (logged there)
        except OSError as exc:  # no route, network down, a name not found: the table runs on
            self.failing += 1
            if self.failing == 1:
                log.warning("heartbeat to %s:%s not sent: %s; trying at every heartbeat",
                            *self.address, getattr(exc, "strerror", None) or exc)
            return
        if self.failing:
            log.info("heartbeat to %s:%s sent again after %d failed", *self.address,
                     self.failing)
        self.sent, self.failing = self.sent + 1, 0

    def close(self) -> None:
        self.destination.close()


class HealthReporter:
    """Frame-loop hook: every ``every_s`` of frame time, builds the status, writes it and sends
    the heartbeat. ``extra()`` adds fields (attract mode, config watcher, studio).

    It also logs when the table starts showing "one moment" (with every unhealthy source's
    own words, which the visitors' screen leaves out) and when it is live again: otherwise a
    source that logs nothing of its own (an ``osc`` source whose tracker stopped) left the
    table calm for visitors and the log silent. Episodes shorter than ``MOMENT_GRACE_S`` (a
    source still starting) are not logged; at most one line every ``MOMENT_LOG_S`` (a flapping
    source), the next line counting the episodes not logged."""

    MOMENT_LOG_S = 60.0   # seconds between two "one moment" lines at least
    # an episode shorter than this is not logged (a source still starting, a blip), seconds
    MOMENT_GRACE_S = 2.0

    def __init__(self, name: str, stats: Any, every_s: float = 1.0,
                 status_file: Path | None = None, heartbeat: Heartbeat | None = None,
                 extra: Callable[[], dict[str, Any]] | None = None,
                 clock: Callable[[], float] = time.monotonic, started: float | None = None) -> None:
        self.name = name or socket.gethostname()
        self.stats, self.every_s, self.clock = stats, every_s, clock
        self.writer = LatestWriter(status_file) if status_file is not None else None
        self.heartbeat = heartbeat
        self.extra = extra
        self.started = clock() if started is None else started
        self._next = -math.inf
        self.last: dict[str, Any] | None = None
        self._moment_since: float | None = None   # clock time "one moment" began showing
        self._moment_said = -math.inf             # ... and when it was last logged
        self._unsaid = 0                          # episodes since then, not logged
        self._said_this = False                   # the present episode was logged
        self._judged = False                      # ... or counted as not logged

    def _own(self) -> dict[str, Any]:
        """The fields a kiosk tells of itself without a frame (no sources, 0 fps); the parts'
        fields null until ``extra`` gives them (:func:`~tabletop.kiosk.status_fields.own_status`,
        shared with the supervisor's "restarting")."""
        st = self.stats
        return own_status(self.name, "stopped", uptime_s=round(self.clock() - self.started, 3),
                          ticks=int(st.ticks) if st is not None else 0,
                          errors=int(sum(st.errors.values())) if st is not None else 0,
                          restarts=int(os.environ.get("TABLETOP_RESTARTS", "0") or 0))

    def status(self, frame: Frame) -> dict[str, Any]:
        from tabletop.renderer import cameras_down   # the view's rule for its calm screen
        sources = [{"name": h.name, "ok": bool(h.ok), "message": h.message,
                    "age_s": None if math.isinf(h.age) else round(float(h.age), 3)}
                   for h in frame.health]
        st = self.stats
        out = self._own()
        out.update({
            "fps": round(float(st.fps() or 0.0), 2) if st is not None else 0.0,
            "ticks": int(st.ticks) if st is not None else frame.seq,
            # what the table shows: "one_moment" also while every source is down without
            # ever having worked (a camera not plugged in at boot), as the view then shows it
            "mode": "one_moment" if cameras_down(frame) else frame.status or "live",
            "unhealthy_sources": sum(1 for s in sources if not s["ok"]),
            "sources": sources,
        })
        if self.extra is not None:
            out.update(self.extra())
        return out

    def __call__(self, frame: Frame) -> None:
        now = self.clock()
        if now < self._next:
            return
        if self.stats is not None and self.stats.fps() is None:
            return   # the loop's first ticks: the first status waits for a rate (not "0 fps")
        self._next = now + self.every_s
        status = self.status(frame)
        self.last = status
        self._say_mode(status, now)
        text = status_text(status)
        if self.writer is not None:
            self.writer.put(text)
        if self.heartbeat is not None:
            self.heartbeat.send(self.name, status["uptime_s"], status["fps"],
                                status["unhealthy_sources"], text.rstrip("\n"))

    def _say_mode(self, status: dict[str, Any], now: float) -> None:
        """Log an episode of "one moment" that lasted ``MOMENT_GRACE_S`` (warning, with why)
        and its end (with its length, seconds); see the class docstring for how often."""
        down = status["mode"] == "one_moment"
        if down and self._moment_since is None:
            self._moment_since, self._judged, self._said_this = now, False, False
        elif down and not self._judged and now - self._moment_since >= self.MOMENT_GRACE_S:
            self._judged = True
            if now - self._moment_said < self.MOMENT_LOG_S:
                self._unsaid += 1
                return
            why = "; ".join(f"source {s['name']}: {s['message']}" for s in status["sources"]
                            if not s["ok"]) or "no source is ok"
            more = (f", {self._unsaid} more time{'s' if self._unsaid > 1 else ''} since the "
                    "last such line" if self._unsaid else "")
            log.warning('the table shows "one moment" (for %.0f s%s): %s',
                        now - self._moment_since, more, why)
            self._moment_said, self._unsaid, self._said_this = now, 0, True
        elif not down and self._moment_since is not None:
            if self._said_this:
                log.info('the table is live again after %.0f s of "one moment"',
                         now - self._moment_since)
            self._moment_since = None

    def close(self) -> None:
        if self.writer is not None:
            self.writer.close()
        if self.heartbeat is not None:
            self.heartbeat.close()

    def stopped(self) -> None:
        """After :meth:`close`, when the kiosk ends on purpose: the status file says so, its
        last status again with ``mode`` "stopped", ``fps`` 0 and the time of the stop; a file
        still saying "live" (or "one_moment") with its pid gone would not tell a table stopped
        an hour ago from one running. A kiosk that ends before its first status
        (within its first second) writes one of its own, without sources: the file would
        otherwise go on telling the status of the kiosk that ran before it. The heartbeat
        sends that status once more: a watcher (``tabletop status``) tells a kiosk stopped on
        purpose from one gone silent (a crash, a power cut)."""
        if self.writer is None and self.heartbeat is None:
            return
        last = self.last
        if last is None:
            last = self._own()
            if self.extra is not None:
                try:
                    last.update(self.extra())
                except Exception as exc:  # (its parts may be closed by now): said without
                    log.debug("status fields at the stop not read: %s", exc)
        status = dict(last, mode="stopped", fps=0.0, time=utc_now(),
                      uptime_s=round(self.clock() - self.started, 3))
        text = status_text(status)
        if self.heartbeat is not None:   # (closed with the loop: a send opens it again)
            self.heartbeat.send(self.name, status["uptime_s"], 0.0,
                                int(status.get("unhealthy_sources") or 0), text.rstrip("\n"))
            self.heartbeat.close()
        if self.writer is None:
            return
        if self.writer.last(text):       # its thread still writing: after that, in order
            self.writer.close()
            return
        write_status(self.writer.path, text)   # (its folder made: a kiosk stopped before its first)


def snapshot_status(view: Any) -> Callable[[], dict[str, Any]]:
    """The status's ``snapshots`` field: null when none are taken, else the folder, the last
    snapshot written (null before the first) and why the last one failed (``failed``, null
    when it was written). Without it a full disk stopped the snapshots with one log line,
    written on that disk, while the heartbeat read as a healthy table."""
    def status() -> dict[str, Any]:
        snaps = getattr(view, "snapshots", None)
        if snaps is None:
            return {"snapshots": None}
        return {"snapshots": {"folder": str(snaps.folder),
                              "last": str(snaps.saved) if snaps.saved else None,
                              "failed": snaps.failed}}
    return status


def recording_status(recorder: Any) -> Callable[[], dict[str, Any]]:
    """The status's ``recording`` field: null without a recorder, else the file being written (null
    when none could be opened), its frames, why it stopped (``failed``, null while it records) and
    how often it resumed after a full disk or a disk that could not keep up (``resumed``).
    Without it a full disk stopped the recording with one log line (on that disk too, often)
    while the status and the heartbeat went on reading as a healthy table."""
    def status() -> dict[str, Any]:
        if recorder is None:
            return {"recording": None}
        return {"recording": {"file": str(recorder.paths[-1]) if recorder.paths else None,
                              "frames": int(recorder.frames), "failed": recorder.failed,
                              "resumed": len(recorder.gaps)}}
    return status


class WatchdogPing:
    """Frame-loop hook: ``READY=1`` after the first completed frame, then ``WATCHDOG=1`` at most
    every ``every_s``. Sent from the frame loop itself, so a frozen loop stops the pings."""

    def __init__(self, notifier: Notifier, every_s: float = 0.25,
                 clock: Callable[[], float] = time.monotonic) -> None:
        self.notifier, self.every_s, self.clock = notifier, every_s, clock
        self.ready = False
        self._last = -math.inf

    def __call__(self, frame: Frame) -> None:
        if not self.notifier.enabled:
            return
        now = self.clock()
        if not self.ready:
            self.ready = self.notifier.send(f"READY=1\nSTATUS=running, tick {frame.seq}")
            self._last = now
        elif now - self._last >= self.every_s:
            self.notifier.send("WATCHDOG=1")
            self._last = now

    def close(self) -> None:
        self.notifier.send("STOPPING=1")
        self.notifier.close()
