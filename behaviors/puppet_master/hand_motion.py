"""Motion helpers shared by the scripted hands (designers, chased, visitors): a hand's shake,
vector limits, turning at a rate, and what a reactor's hand perceives of the main puck.

Units: table metres, seconds, radians (wrapped to (-pi, pi]).
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from tabletop.frames import wrap_angle

Table = tuple[float, float]
Vec = np.ndarray


def _tremor(rng: np.random.Generator, n: int, rate_hz: float, lo_hz: float, hi_hz: float,
            rms: float) -> np.ndarray:
    """Band-limited noise (lo_hz..hi_hz) of ``n`` samples with the given RMS: a hand's shake."""
    if n < 4 or rms <= 0.0:
        return np.zeros(n)
    white = rng.standard_normal(n)
    spec = np.fft.rfft(white)
    f = np.fft.rfftfreq(n, 1.0 / rate_hz)
    spec[(f < lo_hz) | (f > hi_hz)] = 0.0
    band = np.fft.irfft(spec, n)
    s = float(np.sqrt(np.mean(band ** 2)))
    return band * (rms / s) if s > 0 else band


def _unit(v: Vec) -> Vec:
    n = float(np.hypot(v[0], v[1]))
    return v / n if n > 1e-9 else np.zeros(2)


def _limit(v: Vec, most: float) -> Vec:
    n = float(np.hypot(v[0], v[1]))
    return v * (most / n) if n > most else v


def _turn_toward(a: float, target: float, most: float) -> float:
    # min/max, not np.clip: the same float, a tenth of the time on a scalar (the scripted
    # hands call this every sample)
    return wrap_angle(a + float(min(max(wrap_angle(target - a), -most), most)))


class _Seen:
    """What the reactor's hand perceives of the main puck (delayed): position, velocity, look."""

    def __init__(self, p: Vec, v: Vec, look: float, speed: float | None = None) -> None:
        """``speed``: ``v``'s norm (m/s) if the caller has it (np.hypot's, the same float)."""
        self.p, self.v, self.look = p, v, look
        self.speed = float(np.hypot(v[0], v[1])) if speed is None else speed


Policy = Callable[[float, Vec, Vec, float, _Seen], tuple[Vec, float]]
