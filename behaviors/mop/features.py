"""Input features for action following: per-column standardisation and puck path features.

MOP follows any vector of numbers per sample ("multiple input sources" are simply concatenated).
Features arrive in their own units (metres, radians, m/s, joint angles...); the follower
standardises every column by one scale shared by all templates of a set, so a single relative
``sigma`` works for features of any scale.
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from tabletop.frames import wrap_angle

#: Column names of :class:`PathFeatures` output, in order.
PATH_FEATURE_NAMES: tuple[str, ...] = ("dx", "dy", "heading", "speed")


def fit_scale(templates: Sequence[np.ndarray], relative_floor: float = 0.05,
              min_scale: np.ndarray | Sequence[float] | None = None
              ) -> tuple[np.ndarray, np.ndarray]:
    """Centre and scale per feature column, pooled over all templates: ``(center, scale)``, each
    (d,).

    ``scale`` is the standard deviation of every sample of every template about the pooled mean,
    floored at ``relative_floor`` times the root-mean-square of all column spreads, so a column
    that is still in every template does not get a needle-thin Gaussian, and at ``min_scale``
    (d,), the inputs' noise in their own units when it is known. Shifting a column, or scaling
    all columns together, changes nothing downstream. A set with no spread at all gets scale 1.
    """
    pooled = np.concatenate([np.asarray(t, dtype=float) for t in templates], axis=0)
    center = pooled.mean(axis=0)
    spread = pooled.std(axis=0)
    overall = math.sqrt(float(np.mean(spread ** 2)))
    scale = np.maximum(spread, relative_floor * overall)
    if min_scale is not None:
        scale = np.maximum(scale, np.asarray(min_scale, dtype=float))
    tiny = 1e-12 * max(1.0, float(np.max(np.abs(center))))
    scale = np.where(scale > tiny, scale, 1.0)
    return center, scale


class PathFeatures:
    """Features of a puck path relative to where the gesture started (stateful, causal).

    ``step(x, y, angle, t)`` returns ``[dx, dy, heading, speed]``: position in metres relative to
    the gesture's origin (in the table frame, or in the frame of the puck's starting angle when
    ``rotate`` is True), the puck's rotation since the origin in radians (unwrapped, so several
    turns add up), and its speed in m/s low-passed at ``speed_cutoff_hz``.

    The origin is the first pose seen, or the pose given to :meth:`reset`. A puck that stays
    within ``rest_radius`` metres and ``rest_turn`` radians of where it settled (the mean of its
    poses since it came within that radius) for ``rest_time`` seconds has ended its gesture:
    :attr:`resting` is True and the origin moves to where it settled, so the next gesture starts
    from there; it stops resting as soon as it leaves that radius. While resting nothing is being
    performed: a follower fed by this puck should wait for the next gesture, since a puck at its
    origin looks like the first sample of every template. ``rest_time=inf`` disables this.

    Why a radius and not a speed threshold: tracked positions jitter, and the speed of a jittering
    puck is never small (0.3 mm of noise per 60 Hz frame reads as ~0.03 m/s, low-passed or not),
    so a "speed below 0.02 m/s" rule never saw a real puck rest. Measured on the example
    installation (``tests/mop/test_live.py``) with 0.3 mm of jitter: 29 of 51 gestures recognised
    with the speed rule, every one with the radius; jitter averages out of a displacement.

    Speed depends on the performer's tempo: a gesture performed at half its recorded pace has
    half its speeds, so include ``speed`` only for actions whose tempo matters.
    """

    names = PATH_FEATURE_NAMES
    #: Smallest spread per feature worth telling apart (1 cm, 0.1 rad, 3 cm/s): pass it as the
    #: follower's ``min_scale`` so a still feature (a puck never turned) tolerates tracking jitter.
    min_scale = np.array([0.01, 0.01, 0.1, 0.03])

    def __init__(self, rest_radius: float = 0.003, rest_time: float = 0.8,
                 speed_cutoff_hz: float = 5.0, rotate: bool = False,
                 rest_turn: float = 0.1) -> None:
        self.rest_radius = float(rest_radius)
        self.rest_turn = float(rest_turn)
        self.rest_time = float(rest_time)
        self.speed_cutoff_hz = float(speed_cutoff_hz)
        self.rotate = bool(rotate)
        self._started = False
        self.origin = (0.0, 0.0, 0.0)
        self._origin_turn = 0.0
        self._prev = (0.0, 0.0, 0.0, 0.0)
        self._turned = 0.0      # unwrapped rotation since the first pose, radians
        self._speed = 0.0
        # where the puck settled: sums of x, y and turned over n poses since time t
        self._anchor = [0.0, 0.0, 0.0, 1, 0.0]
        self._resting = False

    @property
    def resting(self) -> bool:
        """True while the puck has stayed where it settled for ``rest_time``: its gesture ended."""
        return self._resting

    @property
    def still(self) -> int:
        """Poses read since the puck last moved beyond ``rest_radius`` (1: it just moved)."""
        return int(self._anchor[3])

    @property
    def dim(self) -> int:
        return len(PATH_FEATURE_NAMES)

    def reset(self, x: float, y: float, angle: float, t: float) -> None:
        """Start a new gesture at this pose (metres, radians) and time (seconds)."""
        self._started = True
        self.origin = (float(x), float(y), float(angle))
        self._prev = (float(x), float(y), float(angle), float(t))
        self._turned = 0.0
        self._origin_turn = 0.0
        self._speed = 0.0
        self._anchor = [float(x), float(y), 0.0, 1, float(t)]
        self._resting = False

    def state(self) -> list[float]:
        """Where the gesture started and the puck settled, and whether it rests (17 floats,
        JSON-able; :meth:`set_state` takes them back)."""
        return [float(self._started), *self.origin, self._origin_turn, *self._prev,
                self._turned, self._speed, *map(float, self._anchor), float(self._resting)]

    def set_state(self, values: Sequence[float]) -> None:
        """Go on from :meth:`state`'s ``values``; ValueError when they are not 17 finite
        numbers."""
        v = [float(x) for x in values]
        if len(v) != 17 or not all(map(math.isfinite, v)):
            raise ValueError(f"a puck path's state is 17 finite numbers, got {values!r:.80}")
        self._started, self.origin, self._origin_turn = bool(v[0]), tuple(v[1:4]), v[4]
        self._prev, self._turned, self._speed = tuple(v[5:9]), v[9], v[10]
        self._anchor = [v[11], v[12], v[13], int(v[14]), v[15]]
        self._resting = bool(v[16])

    def step(self, x: float, y: float, angle: float, t: float) -> np.ndarray:
        """Features of this pose (metres, radians, seconds); see the class docstring."""
        if not (math.isfinite(x) and math.isfinite(y) and math.isfinite(angle)
                and math.isfinite(t)):
            raise ValueError(f"puck pose must be finite, got x={x}, y={y}, angle={angle}, t={t}")
        if not self._started:
            self.reset(x, y, angle, t)
        px, py, pa, pt = self._prev
        dt = t - pt
        if dt > 0:
            k = 1.0 - math.exp(-2.0 * math.pi * self.speed_cutoff_hz * dt)
            self._speed += k * (math.hypot(x - px, y - py) / dt - self._speed)
        self._turned += wrap_angle(angle - pa)
        self._prev = (float(x), float(y), float(angle), float(t))
        a = self._anchor
        n = a[3]
        ax, ay, aturn = a[0] / n, a[1] / n, a[2] / n
        if (math.hypot(x - ax, y - ay) > self.rest_radius
                or abs(self._turned - aturn) > self.rest_turn):
            self._anchor = [float(x), float(y), self._turned, 1, float(t)]
            self._resting = False
        else:
            a[0] += x
            a[1] += y
            a[2] += self._turned
            a[3] += 1
            if t - a[4] >= self.rest_time and not self._resting:
                self._resting = True
                self.origin = (ax, ay, float(angle) - (self._turned - aturn))
                self._origin_turn = aturn
        ox, oy, oa = self.origin
        dx, dy = x - ox, y - oy
        if self.rotate:
            c, s = math.cos(oa), math.sin(oa)
            dx, dy = c * dx + s * dy, -s * dx + c * dy
        return np.array([dx, dy, self._turned - self._origin_turn, self._speed])
