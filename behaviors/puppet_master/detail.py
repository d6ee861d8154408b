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
Measured with ``bench/fidelity.py --seeds 0,1,2,3,4,5,8,9,10,11,12,13,26,27,28,29,30,31``
(thresholds met of 720 on seeds 0-5 / 8-13 / 26-31, the engine's alone in brackets): pi/3
676 / 671 / 661 (8 / 13 / 16); pi (the paper's detail added as it is) 660 / 674 / 673
(13 / 16 / 16); 2pi/3 666 / 667 / 669 (12 / 15 / 16); pi/6 663 / 670 / 660 (16 / 14 / 22).
Thresholds met move within a seed group's spread either way; every other clip misses more
where the engine alone is to blame (45 and 43 against 37), and the pursuit paths lose most
(met 137 of 144 at pi/3, 126 at pi).
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


class DetailPatch:
    """Which training sample's detail applies this step: fixed patches of ``length`` steps."""

    __slots__ = ("detail", "length", "start", "offset")

    def __init__(self, detail: np.ndarray, length: int = 16) -> None:
        self.detail = detail
        self.length = length
        self.start = -1
        self.offset = length

    def restart(self) -> None:
        """The next step starts a new patch (at the source it is given)."""
        self.offset = self.length

    def next(self, latest_source: int) -> int:
        """Training index whose detail applies this step (-1: none); starts a new patch at
        ``latest_source`` when due."""
        if self.offset >= self.length:
            self.start, self.offset = latest_source, 0
        i = self.start + self.offset
        self.offset += 1
        return i if 0 <= i < self.detail.size else -1


def texture_rms(xy: np.ndarray, rate_hz: float, min_speed: float = 0.05) -> float:
    """Direction-change texture of a path (n, 2): RMS change of step direction between
    consecutive steps both faster than ``min_speed`` m/s (rad); 0 if there are none."""
    step = np.diff(np.asarray(xy, dtype=float), axis=0)
    speed = np.hypot(step[:, 0], step[:, 1]) * rate_hz
    turn = np.angle(np.exp(1j * np.diff(np.arctan2(step[:, 1], step[:, 0]))))
    ok = (speed[1:] > min_speed) & (speed[:-1] > min_speed)
    return float(np.sqrt(np.mean(turn[ok] ** 2))) if ok.any() else 0.0


class TextureGovernor:
    """Re-applies the demonstrated texture by its measured level, as the paper's balancing
    keeps the similarity ratio at its target (section 4.3.3).

    The generated step has texture of its own before any detail is added: the best match
    jumps between training regions and each jump turns the step. The paper's three-sample
    smooth removes only the fastest of it, so adding the demonstration's full detail on top
    made smooth characters about 60% jitterier than shown, while shaky ones, whose detail is
    clipped, came out smoother. The governor measures the output's texture (RMS change of
    step direction while moving, over about ``span_s``) against the demonstration's and
    integrates the difference into one control value ``z``: above 0 the detail is amplified
    (up to ``1 + z_max``), between -1 and 0 it is reduced, and below -1 the smoothed step is
    smoothed further by an exponential filter (:attr:`alpha`, down to 0.2). ``gain`` 0.02 per
    moving step moves z by 1 in about 1.2 s of texture twice the target.

    The filter smooths the whole step, not its direction alone, and is kept so: it costs the
    character little speed (lover on the slow unseen path, seed 2, main moving: 0.087 m/s
    before the filter, 0.086 after, though it is active on 30% of those steps), and both
    alternatives measured worse with bench/fidelity.py on seeds 0-5 (601 of 720 thresholds
    met): the filter keeping the step's length (direction only) 593, no filter at all (texture
    governed by the detail gain alone) 590, losing look change (-3) and contact (-6).
    Measured again (seeds 0-2, Python step): the filter acts on 17-26% of the playful friend's
    steps (alpha 0.21 at the 10th percentile on the loops paths, its texture 0.31-0.35 rad
    against 0.30 shown) and on 43-81% of the stalker's. Held at alpha >= 0.6 (z_min -1.5) /
    off (-1), the friend and the stalker alone on seeds 0-5, 8-13, 26-31, one run, their misses
    (the engine's): friend 4 -> 5 / 7, stalker 26 (17) -> 27 (19) / 28 (19). Not used.
    """

    __slots__ = ("target", "min_step", "gain", "decay", "ms", "z", "prev", "z_min", "z_max")

    def __init__(self, target_rms: float, rate_hz: float, min_speed: float = 0.05,
                 span_s: float = 2.0, gain: float = 0.02, z_min: float = -2.0,
                 z_max: float = 0.5) -> None:
        self.target = max(target_rms, 1e-3) ** 2
        self.min_step = min_speed / rate_hz
        self.gain = gain
        self.decay = 1.0 / max(1.0, span_s * rate_hz)
        self.ms = self.target
        self.z = 0.0
        self.prev = math.nan
        self.z_min, self.z_max = z_min, z_max

    @property
    def detail_gain(self) -> float:
        """Factor on the demonstrated detail (0 .. 1 + z_max)."""
        return min(max(1.0 + self.z, 0.0), 1.0 + self.z_max)

    @property
    def alpha(self) -> float:
        """Exponential smoothing factor on the step (1 = none, down to 0.2)."""
        return 1.0 if self.z >= -1.0 else max(0.2, 1.0 + 0.8 * (self.z + 1.0))

    def update(self, value: float) -> None:
        """Account for one measured value (the level is the running mean of ``value``)."""
        self.ms += (value - self.ms) * self.decay
        self.z += self.gain * (self.target - self.ms) / self.target
        self.z = min(max(self.z, self.z_min), self.z_max)

    def observe(self, sx: float, sy: float) -> None:
        """Account for one output step (metres)."""
        if math.hypot(sx, sy) <= self.min_step:
            self.prev = math.nan
            return
        heading = math.atan2(sy, sx)
        if self.prev == self.prev:          # not nan: two moving steps in a row
            turn = math.remainder(heading - self.prev, math.tau)
            self.update(turn * turn)
        self.prev = heading


class LookGovernor(TextureGovernor):
    """The same control for the look: its mean absolute change per step against the
    demonstration's (``target_change`` rad). Too much change smooths the look toward its
    desired direction (:attr:`alpha`); too little amplifies the look's own detail.

    Without it, the look copied the target's look every step and took the motion's jitter
    with it: the per-step look change was 1.4-2x the demonstration's for the lover, the
    playful friend and the afraid character even with the frame chosen from the data."""

    __slots__ = ()

    def __init__(self, target_change: float, rate_hz: float, span_s: float = 2.0,
                 gain: float = 0.02) -> None:
        super().__init__(0.0, rate_hz, span_s=span_s, gain=gain)
        self.target = max(target_change, 1e-4)
        self.ms = self.target

    def observe_look(self, change: float) -> None:
        """Account for one step's look change (rad)."""
        self.update(abs(change))
