"""Visitors' hands over the table, for the synthetic camera: their shape and a scripted reach.

Units: table metres, radians CCW from +x, seconds.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Occluder:
    """A hand-shaped dark blob lying over the table: centre (m), direction of the fingers (rad),
    palm length (m)."""

    x: float
    y: float
    angle: float = 0.0
    size: float = 0.09


def hand_polygons(o: Occluder) -> list[np.ndarray]:
    """A palm and five fingers as table-metre polygons."""
    c, s = math.cos(o.angle), math.sin(o.angle)
    rot = np.array([[c, -s], [s, c]])
    shapes = []
    t = np.linspace(0, 2 * math.pi, 24, endpoint=False)
    palm = np.column_stack([0.5 * o.size * np.cos(t), 0.42 * o.size * np.sin(t)])
    shapes.append(palm)
    for k, (dy, length) in enumerate([(-0.3, 0.75), (-0.1, 0.9), (0.1, 0.85), (0.3, 0.7)]):
        x0, x1 = 0.35 * o.size, (0.35 + length) * o.size
        w = 0.09 * o.size
        shapes.append(np.array([[x0, dy * o.size - w], [x1, dy * o.size - w],
                                [x1 + w, dy * o.size], [x1, dy * o.size + w],
                                [x0, dy * o.size + w]]))
    shapes.append(np.array([[0.0, 0.35 * o.size], [0.25 * o.size, 0.9 * o.size],
                            [0.35 * o.size, 0.85 * o.size], [0.2 * o.size, 0.3 * o.size]]))
    return [(rot @ sh.T).T + [o.x, o.y] for sh in shapes]


def scripted_hands(t: float, table: tuple[float, float], every_s: float = 12.0,
                   duration_s: float = 1.6, size: float = 0.1, seed: int = 0) -> list[Occluder]:
    """A visitor's hand reaching over the table now and then: a pure function of time ``t`` (s).

    Every ``every_s`` seconds a hand comes in over the near edge (y = 0), reaches a seeded
    point on the table, lingers and withdraws, within ``duration_s``. Returns the hands at t
    (none between passes, or when ``every_s`` <= 0)."""
    if every_s <= 0 or t < 0:
        return []
    k = int(t // every_s)
    phase = (t - k * every_s) / duration_s
    if not 0.0 <= phase <= 1.0:
        return []
    rng = np.random.default_rng([seed, k])
    w, h = table
    target = np.array([rng.uniform(0.15, 0.85) * w, rng.uniform(0.25, 0.8) * h])
    entry = np.array([target[0] + rng.uniform(-0.2, 0.2) * w, -1.2 * size])
    reach = min(1.0, 1.6 * math.sin(math.pi * phase))  # in, linger, out
    p = entry + (target - entry) * reach
    angle = math.atan2(target[1] - entry[1], target[0] - entry[0])
    return [Occluder(float(p[0]), float(p[1]), angle, size)]
