"""Counting bad input from the outside world (packets, serial lines) without being hurt by it.

Every rejected thing is counted under a short kind name (``malformed``, ``wrong_arguments``,
``not_allowed``, ...) and logged with the count so far: at once, then, while that kind keeps
coming, after ``log_every_s``, twice that, ... up to every ``max_every_s``; a kind not seen for
``max_every_s`` starts again at once. So a flood costs a counter increment, never a log storm.
The counters are few and fixed in size (kinds come from the code, not from the input).
"""

from __future__ import annotations

import logging
import math
import threading
import time
from typing import Callable

from tabletop.frames import SourceHealth

log = logging.getLogger("tabletop.input")


class BadInput:
    """Per-kind counters of rejected input for one source, with rate-limited logging."""

    # The gap between two lines of one kind grows while it keeps coming. With a fixed 10 s, a
    # sender that never stops sending something refused (another program's OSC on the port)
    # wrote 8,640 lines a day, 60,480 a week: at about 200 bytes each the kiosk's rotating log
    # (1 MB x 5) then held under four days, every other line older than that rotated away.
    # Doubling up to 600 s: 1,015 lines a week (the RetryLog of a lost device repeats at 600 s).

    def __init__(self, source: str, log_every_s: float = 10.0, max_every_s: float = 600.0,
                 clock: Callable[[], float] = time.monotonic) -> None:
        self.source, self.log_every_s, self.clock = source, log_every_s, clock
        self.max_every_s = max(max_every_s, log_every_s)
        self._counts: dict[str, int] = {}
        self._logged: dict[str, float] = {}    # kind -> when it was last logged
        self._gap: dict[str, float] = {}       # kind -> seconds from that line to the next
        self._seen: dict[str, float] = {}      # kind -> when it was last counted
        self._lock = threading.Lock()

    def count(self, kind: str, detail: str = "", n: int = 1) -> None:
        """Count ``n`` rejected items of ``kind``; log one line when this kind's gap since its
        last line has passed (see the module docstring; ``detail`` says what was wrong and
        where)."""
        now = self.clock()
        with self._lock:
            total = self._counts.get(kind, 0) + n
            self._counts[kind] = total
            if now - self._seen.get(kind, -math.inf) > self.max_every_s:
                self._gap[kind] = 0.0           # a new episode: said at once
            self._seen[kind] = now
            due = now - self._logged.get(kind, -math.inf) >= self._gap[kind]
            if due:
                self._logged[kind] = now
                self._gap[kind] = min(max(2.0 * self._gap[kind], self.log_every_s),
                                      self.max_every_s)
        if due:
            log.warning("%s: ignored %s input (%d so far)%s", self.source,
                        kind.replace("_", " "), total, f": {detail[:200]}" if detail else "")

    def counts(self) -> dict[str, int]:
        """A copy of the counters, kind -> count."""
        with self._lock:
            return dict(self._counts)

    def total(self) -> int:
        with self._lock:
            return sum(self._counts.values())

    def summary(self) -> str:
        """``"ignored: 3 malformed, 1 not allowed"`` for the overlay and status, or ``""``."""
        c = self.counts()
        if not c:
            return ""
        parts = [f"{n} {k.replace('_', ' ')}" for k, n in sorted(c.items(), key=lambda kv: -kv[1])]
        return "ignored: " + ", ".join(parts)

    def health(self, ok: bool, message: str, age: float) -> SourceHealth:
        """A source's health with these counts appended to its message."""
        bad = self.summary()
        return SourceHealth(self.source, ok, f"{message} ({bad})" if bad else message, age)


class RetryLog:
    """The log lines of a device that reconnects (a camera, a serial port): a failure is said
    when its reason is new, and again at most every ``repeat_s`` while it lasts, and the
    device's return once, so a camera left unplugged for a week writes a few lines, not one per
    retry (8 s apart: 75,000 lines, rotating the kiosk's log away). The health keeps the
    current reason and countdown meanwhile."""

    def __init__(self, name: str, logger: logging.Logger, repeat_s: float = 600.0,
                 clock: Callable[[], float] = time.monotonic) -> None:
        self.name, self.log, self.repeat_s, self.clock = name, logger, repeat_s, clock
        self._reason = ""
        self._said_t = -math.inf
        self.failures = 0            # since the device last worked

    def failed(self, reason: str, delay: float) -> None:
        now = self.clock()
        self.failures += 1
        if reason != self._reason or now - self._said_t >= self.repeat_s:
            again = f" (failed {self.failures} times)" if reason == self._reason else ""
            self.log.warning("%s: %s; retrying in %.1f s%s", self.name, reason, delay, again)
            self._reason, self._said_t = reason, now

    def worked(self, what: str) -> None:
        if self.failures:
            self.log.info("%s: %s back after %d failed attempts", self.name, what,
                          self.failures)
        self._reason, self._said_t, self.failures = "", -math.inf, 0


class BackgroundSource:
    """``open``/``close`` for a source whose work runs in one daemon thread: ``_run`` until
    ``_stop`` is set. Subclasses call ``_init_thread()`` in their constructor."""

    name: str

    def _init_thread(self) -> None:
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None

    def _run(self) -> None:
        raise NotImplementedError

    def open(self) -> None:
        if self._thread is None:
            self._stop.clear()
            self._thread = threading.Thread(target=self._run, name=f"{type(self).__name__}:"
                                            f"{self.name}", daemon=True)
            self._thread.start()

    def close(self) -> None:
        self._stop.set()
        if self._thread is not None:
            self._thread.join(timeout=5.0)
            self._thread = None
