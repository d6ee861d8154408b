"""Counting bad input from the outside world (packets, serial lines) without being hurt by it.

Every rejected thing is counted under a short kind name (``malformed``, ``wrong_arguments``,
``not_allowed``, ...) and logged with the count so far, sparingly (:class:`LogGaps`: at once,
then after 10 s, 20 s, ... up to every 600 s while it keeps coming), so a flood costs a counter
increment, never a log storm.
The counters are few and fixed in size (kinds come from the code, not from the input).
"""

from __future__ import annotations

import logging
import math
import threading
import time
from typing import Callable

from tabletop.frames import InputError, SourceHealth

log = logging.getLogger("tabletop.input")


class CountedError(InputError):
    """Bad input of one ``kind``: the name of the :class:`BadInput` counter it is counted in."""

    def __init__(self, kind: str, message: str) -> None:
        super().__init__(message)
        self.kind = kind


class LogGaps:
    """When to log a repeating failure, per key: at once, then, while it keeps coming, after
    ``first_s``, twice that, ... up to every ``max_s``; a key not seen for ``max_s`` starts
    again at once (times in seconds of the caller's clock). Not thread-safe: callers lock.

    A fixed 10 s gap wrote 8,640 lines a day for a failure that never stops (another program's
    OSC sent to the port, an engine raising on every tick, with its stack): at about 200 bytes
    a line (750 with the stack of a numpy error one call inside an engine) the kiosk's rotating
    log (1 MB x 5) held under four days (under one), every line older than that rotated away.
    Doubling up to 600 s: 1,013 lines a week (the RetryLog of a lost device repeats at 600 s)."""

    def __init__(self, first_s: float = 10.0, max_s: float = 600.0) -> None:
        self.first_s, self.max_s = first_s, max(max_s, first_s)
        self._logged: dict[str, float] = {}    # key -> when it was last logged
        self._gap: dict[str, float] = {}       # key -> seconds from that line to the next
        self._seen: dict[str, float] = {}      # key -> when it last happened

    def due(self, key: str, now: float) -> bool:
        """``key`` happened at ``now`` (s, the caller's clock): is a line due?"""
        if key not in self._gap or now - self._seen[key] > self.max_s:
            self._gap[key] = 0.0               # a new episode: said at once
        self._seen[key] = now
        if now - self._logged.get(key, -math.inf) < self._gap[key]:
            return False
        self._logged[key] = now
        self._gap[key] = min(max(2.0 * self._gap[key], self.first_s), self.max_s)
        return True


class BadInput:
    """Per-kind counters of rejected input for one source, with sparing logging (:class:`LogGaps`
    from ``log_every_s`` up to ``max_every_s``)."""

    def __init__(self, source: str, log_every_s: float = 10.0, max_every_s: float = 600.0,
                 clock: Callable[[], float] = time.monotonic) -> None:
        self.source, self.clock = source, clock
        self._counts: dict[str, int] = {}
        self._gaps = LogGaps(log_every_s, max_every_s)
        self._lock = threading.Lock()

    def count(self, kind: str, detail: str = "", n: int = 1) -> None:
        """Count ``n`` rejected items of ``kind``; log one line when one is due (``detail``
        says what was wrong and where)."""
        now = self.clock()
        with self._lock:
            total = self._counts.get(kind, 0) + n
            self._counts[kind] = total
            due = self._gaps.due(kind, now)
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
