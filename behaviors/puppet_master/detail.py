"""Detail incorporation (paper section 4.4.2): Haar high-frequency texture of the path.

At training, a ``levels``-level Haar decomposition (PyWavelets) of the reactor's movement
direction (unwrapped, radians) is recomposed from its detail coefficients alone: a
high-frequency-only signal above about fs / 2**levels (fs/16 for four levels: 2.5 Hz at 40 Hz).
Live, each step rotates the smoothed step by the detail of the current patch, keeping the step's
length. A patch's source index stays fixed for ``patch`` steps (16), then the latest match picks
the next, so detail from rapidly alternating matches never interleaves.

The decomposition is the stationary (undecimated, shift-invariant) Haar transform
(``pywt.swt``/``pywt.iswt``), not the decimated one (``pywt.wavedec``). Both split at the same
octaves, but the decimated transform approximates a steady turn (a linear ramp of direction)
by a staircase of 16-sample steps, so its "detail" of a smooth turn is a sawtooth of amplitude
slope x 8: 0.5 rad on a character turning at 2.5 rad/s. Pasted onto the output, that made a
smooth follower's path as jittery as a shaky one (measured: step-to-step direction change RMS
0.28 rad vs 0.07 rad in the demonstration). The stationary transform's detail of a ramp is
zero, and its leak from a trend at fs/128 is 5% of the amplitude instead of 22%. The signal is
extended by odd reflection (which continues a trend) so the ends carry no false detail.

A reversal in the demonstration is a jump of pi in the movement direction; its detail would
throw the character sideways wherever it is pasted. The detail is therefore clipped to
+-``clip`` radians (pi/3 by default: a shaky hand's wobble of tens of degrees passes untouched).
"""

from __future__ import annotations

import math

import numpy as np
import pywt


def haar_detail(signal: np.ndarray, levels: int = 4) -> np.ndarray:
    """High-frequency part (above about fs / 2**levels) of a 1-D signal, same length."""
    x = np.asarray(signal, dtype=float)
    n = x.size
    if n < 2 or levels < 1:
        return np.zeros_like(x)
    block = 2 ** levels
    pad = min(block, n - 1)
    total = n + 2 * pad
    extra = (-total) % block
    xp = np.pad(x, (pad, pad + extra), mode="reflect", reflect_type="odd") if pad > 0 else x
    if extra and xp.size < total + extra:  # a very short signal: extend with its last value
        xp = np.pad(xp, (0, total + extra - xp.size), mode="edge")
    coeffs = pywt.swt(xp, "haar", level=levels, trim_approx=True, norm=True)
    coeffs[0] = np.zeros_like(coeffs[0])
    return pywt.iswt(coeffs, "haar", norm=True)[pad:pad + n]


def direction_detail(move: np.ndarray, moving: np.ndarray | None = None, levels: int = 4,
                     clip: float = math.pi / 3) -> np.ndarray:
    """Clipped high-frequency detail (rad) of a movement-direction signal in (-pi, pi].

    ``moving`` (bool, same length) marks the samples whose direction is real; across the others
    (a pause, the time before the first move) the direction is interpolated between the
    neighbouring real ones, so a character that stops and leaves in a new direction shows a
    turn, not a step that the decomposition would smear into 16 samples of false texture.
    """
    a = np.unwrap(np.asarray(move, dtype=float))
    if moving is not None:
        idx = np.flatnonzero(moving)
        if idx.size == 0:
            return np.zeros_like(a)
        if idx.size < a.size:
            # unwrap over the real samples only: a pause may hide any turn
            real = np.unwrap(np.asarray(move, dtype=float)[idx])
            a = np.interp(np.arange(a.size), idx, real)
    return np.clip(haar_detail(a, levels), -clip, clip)


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

    def next(self, latest_source: int) -> int:
        """Training index whose detail applies this step (-1: none); starts a new patch at
        ``latest_source`` when due."""
        if self.offset >= self.length:
            self.start, self.offset = latest_source, 0
        i = self.start + self.offset
        self.offset += 1
        return i if 0 <= i < self.detail.size else -1
