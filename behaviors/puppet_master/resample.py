"""Resampling to the fixed generation rate (paper section 4.1: the algorithm runs at 40 Hz).

Demonstrations are resampled offline by linear interpolation (angles through their unwrapped
signal). Live input is resampled causally: a grid sample at time ``g`` uses only input samples
at times <= ``g``, extrapolating linearly from the last two when ``g`` falls after the newest one.
Extrapolation (rather than holding the last value) keeps the speed feature steady when a 30 Hz
camera feeds a 40 Hz grid; holding alternates zero and double speeds.

From the last two samples it about doubles a standing hand's jitter (step_senses.py,
_main_stopped). The slope fitted over the last N samples instead (from the newest sample, so
straight motion stays exact), bench/fidelity.py --seeds 0,1,2,3,4,5 against 676 of 720 (the
engine's alone 8): N = 4 667 (12), N = 3 661 (14), N = 4 for the position only (the direction
from the last two) 671 (11), and on seeds 8-13 664 (17) against 671 (13) (stalker misses 10 ->
14). Not used. A main whose last two samples moved under 0.05 / 0.03 m/s held instead of
extrapolated (a standing hand's jitter not doubled), every character, open misses (the
engine's alone) on seeds 0-5 / 40-51 / 128-139 / 300-311 against 43 (7) / 112 (31) / 104 (21)
/ 110 (24): 46 (7) / 112 (31) / 106 (28) / 126 (29), 56 (16) / 103 (29) / 100 (22) / 108 (28);
still/moving misses (the engine's) 30 -> 40 / 44: the still pace, read more surely, comes out
under the shown one (step_senses.py, _main_stopped). Not used.

Times in seconds, positions in table metres, angles in radians wrapped to (-pi, pi].
"""

from __future__ import annotations

import math

import numpy as np

from tabletop.frames import wrap_angle, wrap_angles


def grid_times(t0: float, t1: float, rate_hz: float) -> np.ndarray:
    """Grid ``t0, t0 + 1/rate, ...`` up to and including ``t1`` (seconds)."""
    count = int(math.floor((t1 - t0) * rate_hz + 1e-9)) + 1
    return t0 + np.arange(max(count, 1), dtype=float) / rate_hz


def resample_uniform(t: np.ndarray, values: np.ndarray, angle_columns: tuple[int, ...],
                     rate_hz: float) -> tuple[np.ndarray, np.ndarray]:
    """Linear resampling of ``values`` (n, k) sampled at strictly increasing ``t`` onto the grid.

    Columns listed in ``angle_columns`` are radians: they are unwrapped before interpolation and
    wrapped back after. Returns (grid times (m,), values (m, k)).
    """
    tg = grid_times(float(t[0]), float(t[-1]), rate_hz)
    out = np.empty((tg.size, values.shape[1]), dtype=float)
    for c in range(values.shape[1]):
        col = values[:, c]
        if c in angle_columns:
            out[:, c] = wrap_angles(np.interp(tg, t, np.unwrap(col)))
        else:
            out[:, c] = np.interp(tg, t, col)
    return tg, out


class CausalResampler:
    """Live pose (x, y, direction) at grid times from irregular samples, using only the past.

    ``max_extrapolation`` (seconds) bounds how far past the newest sample a pose is extrapolated
    (beyond it the pose holds), so a dropped input freezes the pose instead of flinging it.
    """

    def __init__(self, max_extrapolation: float = 0.1) -> None:
        self.max_extrapolation = max_extrapolation
        self._prev: tuple[float, float, float, float] | None = None
        self._last: tuple[float, float, float, float] | None = None

    @property
    def last_time(self) -> float | None:
        """Time of the newest accepted sample, or None before the first."""
        return None if self._last is None else self._last[0]

    def push(self, t: float, x: float, y: float, direction: float) -> bool:
        """Add a sample; returns False (and ignores it) unless finite and later than the last."""
        if not (math.isfinite(t) and math.isfinite(x) and math.isfinite(y)
                and math.isfinite(direction)):
            return False
        if self._last is not None and t <= self._last[0]:
            return False
        self._prev, self._last = self._last, (t, x, y, wrap_angle(direction))
        return True

    def at(self, g: float) -> tuple[float, float, float]:
        """Pose at grid time ``g`` (>= the newest sample's time) from the samples so far."""
        if self._last is None:
            raise ValueError("no sample yet")
        t1, x1, y1, d1 = self._last
        if self._prev is None or g <= t1:
            return x1, y1, d1
        t0, x0, y0, d0 = self._prev
        # at most one input interval and max_extrapolation ahead
        h = min(g - t1, self.max_extrapolation)
        f = min(h / (t1 - t0), 1.0)
        return (x1 + (x1 - x0) * f, y1 + (y1 - y0) * f,
                wrap_angle(d1 + wrap_angle(d1 - d0) * f))
