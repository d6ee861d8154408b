"""Per-stage durations of the frame loop and its tick rate, read by the overlay and the benchmarks.

Units: seconds recorded, milliseconds reported.
"""

from __future__ import annotations

import collections

import numpy as np

STAGES = ("capture_age", "inputs", "engines", "sinks", "tick")
# how the overlay names a stage whose key is not the README's word for it
LABELS = {"capture_age": "capture-to-render"}


class LoopStats:
    """Per-stage durations of the last ``window`` ticks, in seconds, and the tick rate.

    Stages: ``inputs`` (sources and tracker), ``engines`` and ``sinks`` (all of them, and each
    as ``engine:NAME`` / ``sink:NAME``, the view's being its render time), ``tick`` (the whole
    tick) and ``capture_age``, the capture-to-render latency: from a capture's time to its first
    presentation (a capture drawn again, or a tick with no new capture, is not counted), i.e.
    the end of the first sink with a true ``presents`` attribute (the view; what later sinks
    and hooks do, such as recording, comes after the visitor saw it), or the end of the tick
    when no sink presents. For sources that announce new observations (cameras) also
    ``source`` (capture to observation ready) and ``queued`` (ready to the tick that took it):
    ``capture_age`` = ``source`` + ``queued`` + the tick up to the view for those frames. Read by
    the view's overlay and by the benchmarks.
    """

    RATE_MIN_S = 1.0   # seconds of ticks before a rate is said

    def __init__(self, window: int = 600) -> None:
        self.window = window
        self.samples: dict[str, collections.deque[float]] = {
            s: collections.deque(maxlen=window) for s in STAGES}
        self.tick_times: collections.deque[float] = collections.deque(maxlen=window)
        self.ticks = 0
        self.skipped = 0
        self.first_t: float | None = None  # the first frame's time, seconds
        self.errors: collections.Counter[str] = collections.Counter()

    def record(self, stage: str, seconds: float) -> None:
        self.samples.setdefault(stage, collections.deque(maxlen=self.window)).append(seconds)

    def fps(self) -> float | None:
        """Ticks per second over the kept window; None while there is no rate yet (less than
        ``RATE_MIN_S`` of ticks): 0.0 there read as a loop that had stalled, and the rate of
        the first few ticks is that of a late first tick's catch-up (70.6 fps at tick 12 of
        a 60 Hz loop)."""
        if len(self.tick_times) < 2:
            return None
        span = self.tick_times[-1] - self.tick_times[0]
        return (len(self.tick_times) - 1) / span if span >= self.RATE_MIN_S else None

    def summary_ms(self) -> dict[str, tuple[float, float]]:
        """Stage -> (median ms, p99 ms) over the kept window."""
        out = {}
        for stage in list(self.samples):
            m = self.stage_ms(stage)
            if m is not None:
                out[stage] = m
        return out

    def stage_ms(self, stage: str) -> tuple[float, float] | None:
        """(median ms, p99 ms) of one stage over the kept window; None without samples."""
        d = list(self.samples.get(stage, ()))   # other threads may record meanwhile
        if not d:
            return None
        a = np.sort(np.asarray(d, dtype=float)) * 1e3   # one sort: ~20x cheaper than
        return _sorted_percentile(a, 50.0), _sorted_percentile(a, 99.0)  # median + percentile


def _sorted_percentile(a: np.ndarray, q: float) -> float:
    """The ``q``-th percentile of sorted values, linearly interpolated (numpy's default)."""
    pos = (len(a) - 1) * q / 100.0
    lo = int(pos)
    hi = min(lo + 1, len(a) - 1)
    return float(a[lo] + (a[hi] - a[lo]) * (pos - lo))
