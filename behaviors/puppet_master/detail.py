"""Detail incorporation (paper section 4.4.2): Haar high-frequency texture of the path.

At training, a ``levels``-level Haar decomposition (PyWavelets) of the reactor's movement
direction (unwrapped, radians) is recomposed from its detail coefficients alone: a
high-frequency-only signal above fs / 2**levels (fs/16 for four levels: 2.5 Hz at 40 Hz).
Live, each step rotates the smoothed step by the detail of the current patch, keeping the step's
length. A patch's source index stays fixed for ``patch`` steps (16), then the latest match picks
the next, so detail from rapidly alternating matches never interleaves.

A reversal in the demonstration is a jump of pi in the movement direction; its Haar detail is a
+-pi/2 spike that, pasted into another moment, would throw the character sideways. The detail is
therefore clipped to +-``clip`` radians (pi/3 by default: a shaky hand's wobble of tens of
degrees passes untouched).
"""

from __future__ import annotations

import math

import numpy as np
import pywt


def haar_detail(signal: np.ndarray, levels: int = 4) -> np.ndarray:
    """High-frequency part (above fs / 2**levels) of a 1-D signal, same length as ``signal``."""
    x = np.asarray(signal, dtype=float)
    if x.size < 2:
        return np.zeros_like(x)
    level = min(levels, pywt.dwt_max_level(x.size, "haar"))
    if level < 1:
        return np.zeros_like(x)
    coeffs = pywt.wavedec(x, "haar", mode="periodization", level=level)
    coeffs[0] = np.zeros_like(coeffs[0])
    out = pywt.waverec(coeffs, "haar", mode="periodization")
    if out.size < x.size:
        # periodization drops an odd tail sample; its detail is unknown: none
        out = np.concatenate([out, np.zeros(x.size - out.size)])
    return out[:x.size]


def direction_detail(move: np.ndarray, levels: int = 4, clip: float = math.pi / 3) -> np.ndarray:
    """Clipped high-frequency detail (rad) of a movement-direction signal wrapped to (-pi, pi]."""
    return np.clip(haar_detail(np.unwrap(move), levels), -clip, clip)


def high_frequency_ratio(signal: np.ndarray, levels: int = 4) -> float:
    """Energy share of the detail part above fs / 2**levels in a signal (0..1); for tests and
    diagnostics of texture (a shaky path scores high, a smooth one near 0)."""
    x = np.asarray(signal, dtype=float)
    x = x - x.mean()
    total = float(np.dot(x, x))
    if total <= 0.0:
        return 0.0
    h = haar_detail(x, levels)
    return float(np.dot(h, h)) / total


class DetailPatch:
    """Which training sample's detail applies this step: fixed patches of ``length`` steps."""

    __slots__ = ("detail", "length", "start", "offset")

    def __init__(self, detail: np.ndarray, length: int = 16) -> None:
        self.detail = detail
        self.length = length
        self.start = -1
        self.offset = length

    def next(self, latest_source: int) -> float:
        """Detail (rad) for this step; starts a new patch at ``latest_source`` when due."""
        if self.offset >= self.length:
            self.start, self.offset = latest_source, 0
        i = self.start + self.offset
        self.offset += 1
        return float(self.detail[i]) if 0 <= i < self.detail.size else 0.0
