"""Inputs of a live installation: the sources' newest observations fused by a tracker into the
loop's frames (:class:`tabletop.loop.Loop`); the recorded counterpart is
:mod:`tabletop.replay_inputs`. Times are monotonic seconds of this machine (capture times)."""

from __future__ import annotations

import collections
import dataclasses
import logging
import math
import threading
import time
from typing import Protocol, Sequence

import numpy as np

from tabletop.frames import Frame, Observation, Puck, Source, SourceHealth, Touch
from tracking.badinput import LogGaps
from tracking.touch_ids import TouchIds

log = logging.getLogger("tabletop")


class Tracker(Protocol):
    def update(self, observations: Sequence[Observation], t: float) -> tuple[Puck, ...]: ...


class LatestMeasurements:
    """The simplest tracker: every measured puck of the newest observations is reported ``seen``.

    Used for sources that already deliver tracked poses (scripted visitor, replays) when no
    camera tracker is configured.
    """

    def update(self, observations: Sequence[Observation], t: float) -> tuple[Puck, ...]:
        pucks: dict[int, Puck] = {}
        for obs in observations:
            for m in obs.pucks:
                pucks[m.id] = Puck(m.id, m.x, m.y, m.angle, raw_x=m.x, raw_y=m.y, raw_angle=m.angle)
        return tuple(pucks[k] for k in sorted(pucks))


class LiveInputs:
    """Inputs of a live installation: the newest observation of every source, fused by the tracker.

    The frame's ``t`` is the capture time of its newest input; a tick whose sources have nothing
    yet is stamped with the loop's own time, and so is one whose newest input is more than
    ``STALE_S`` old (every source stalled: a camera unplugged or a hand over the lens), so that
    time goes on while nothing comes in: pucks coast and leave, characters keep breathing, the
    view shows its "one moment" screen. Times never go backwards.
    """

    STALE_S = 0.25   # seconds: older than a 5 fps camera's frames ever are

    live = True  # frame times are this machine's capture times (capture-to-render is measured)

    READY_KEPT = 16  # announced capture times remembered for the stage figures

    def __init__(self, sources: Sequence[Source], tracker: Tracker) -> None:
        self.sources, self.tracker = list(sources), tracker
        self._last_t = -math.inf
        # Sources with a ``notify`` attribute (cameras) announce each new observation: ``fresh``
        # is set and the loop ticks at once instead of at its next timer slot (Loop.run).
        self.follow = True
        self.fresh = threading.Event()
        self.arrivals: collections.deque[float] = collections.deque(maxlen=9)  # monotonic s
        self._ready: dict[float, float] = {}   # capture time -> monotonic time it was announced
        self._announced: dict[int, float] = {}  # source index -> its newest announced capture time
        self._lock = threading.Lock()
        # The last frame's time is a new capture (see next()): not a held state's stamp, not
        # the stamp of a tick without input (STALE_S), not a capture already drawn.
        self.captured = False
        # A source whose latest() raised: {name: times}; logged sparingly (LogGaps: it was
        # logged with its stack on every tick) and unhealthy on the ticks it raised
        self.raised: dict[str, int] = {}
        self._raised_log = LogGaps()
        self._touch_ids = TouchIds()

    def open(self) -> None:
        for i, s in enumerate(self.sources):
            if self.follow and hasattr(s, "notify"):
                s.notify = lambda t, i=i: self.announce(t, i)
            s.open()

    def announce(self, t: float, source: int = 0) -> None:
        """The new observation captured at ``t`` (monotonic s) of the ``source``-th source is
        ready; called from that source's thread."""
        now = time.monotonic()
        with self._lock:
            self.arrivals.append(now)
            self._ready[t] = now
            self._announced[source] = t
            if len(self._ready) > self.READY_KEPT:
                del self._ready[next(iter(self._ready))]
        self.fresh.set()

    def ready_time(self, t: float) -> float | None:
        """When the observation captured at ``t`` was announced (monotonic s), if it was."""
        with self._lock:
            return self._ready.get(t)

    def arrival_interval(self, now: float) -> float:
        """Median seconds between recent announcements; inf when none are coming (fewer than
        three, or none for three intervals)."""
        with self._lock:
            a = list(self.arrivals)
        if len(a) < 3:
            return math.inf
        iv = float(np.median(np.diff(a)))
        return iv if now - a[-1] < 3.0 * iv else math.inf

    def close(self) -> None:
        for s in self.sources:
            try:
                s.close()
            except Exception:  # a failing close must not keep the others open
                log.exception("source %s failed to close", getattr(s, "name", s))

    def next(self, seq: int, now: float) -> Frame | None:
        observations = []
        taken: dict[int, float] = {}
        failed: dict[str, str] = {}
        for i, s in enumerate(self.sources):
            try:
                obs = s.latest()
            except Exception as exc:
                n = self.raised[s.name] = self.raised.get(s.name, 0) + 1
                failed[s.name] = f"failed: {exc} ({n} times so far)"
                if self._raised_log.due(s.name, now):
                    log.exception("source %s raised in latest() (%d times so far); treated "
                                  "as empty", s.name, n)
                obs = None
            if obs is not None:
                observations.append(obs)
                taken[i] = obs.t
        with self._lock:   # all that was announced is taken: nothing fresh is waiting
            if all(t <= taken.get(i, -math.inf) for i, t in self._announced.items()):
                self.fresh.clear()
        t = max((o.t for o in observations), default=now)
        t = max(t, now - self.STALE_S, self._last_t)
        # Capture-to-render is measured once per capture, at its first drawing: a held state's
        # stamp, the stamp of every source stalled and a capture drawn again (a 30 Hz camera on
        # the 60 Hz timer) are no capture, and counting them made a 30 fps camera's figure read
        # 21.6 ms median, 49.6 p99 (8.8 and 30.9 at 60 fps, the same run).
        self.captured = t > self._last_t and any(not o.held and o.t == t for o in observations)
        self._last_t = t
        pucks = self.tracker.update(observations, t)
        touches = self._touches(observations)
        streams = {k: v for o in observations for k, v in o.streams.items()}
        health = tuple(SourceHealth(s.name, False, failed[s.name]) if s.name in failed
                       else self._health(s) for s in self.sources)
        return Frame(seq=seq, t=t, pucks=pucks, touches=touches, streams=streams, health=health)

    def _touches(self, observations: Sequence[Observation]) -> tuple[Touch, ...]:
        """Every source's touches, ids unique in the frame (two sources numbering their
        fingers alike, a serial board and a TUIO sender, would give two fingers one id)."""
        found = [(o.source, tc) for o in observations for tc in o.touches]
        ids = self._touch_ids.assign([(src, tc.id) for src, tc in found])
        return tuple(tc if i == tc.id else dataclasses.replace(tc, id=i)
                     for i, (_src, tc) in zip(ids, found))

    @staticmethod
    def _health(s: Source) -> SourceHealth:
        try:
            return s.health()
        except Exception as exc:
            return SourceHealth(s.name, False, f"health() failed: {exc}")
