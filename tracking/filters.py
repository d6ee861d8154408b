"""The One Euro filter (Casiez, Roussel and Vogel, CHI 2012): an adaptive low-pass filter whose
cutoff rises with speed, so a still puck is still and a moving one does not lag.

    cutoff = min_cutoff + beta * |speed|,   speed low-passed at d_cutoff

Parameters are in the units of the signal: ``min_cutoff`` and ``d_cutoff`` in Hz, ``beta`` in
1 / (signal unit) (per metre for positions in metres, per radian for angles). A beta tuned in
pixels is wrong in metres: :func:`scale_beta` converts. The filter works on a vector (e.g. x
and y of a puck); the speed of a vector signal is its Euclidean norm, so the filter is the same
in every direction.
"""

from __future__ import annotations

import math


def one_euro_floats(x: list[float], value: list[float], derivative: list[float], dt: float,
                    min_cutoff: float, beta: float, d_cutoff: float
                    ) -> tuple[list[float], list[float]]:
    """One step of the One Euro filter on one short vector in plain floats (a puck's x, y or
    its heading; numpy's per-call overhead would dominate at this size). ``value`` and
    ``derivative`` (units per second) are the filtered ones of the previous sample, ``dt``
    seconds before ``x``. Returns the new (value, derivative)."""
    a_d = 1.0 / (1.0 + 1.0 / (2.0 * math.pi * d_cutoff * dt))
    if len(x) == 2:   # a position, unrolled (the tracker's most frequent call)
        (x0, x1), (v0, v1), (d0, d1) = x, value, derivative
        d0 += a_d * ((x0 - v0) / dt - d0)
        d1 += a_d * ((x1 - v1) / dt - d1)
        a = 1.0 / (1.0 + 1.0 / (2.0 * math.pi * (min_cutoff + beta * math.sqrt(
            d0 * d0 + d1 * d1)) * dt))
        return [v0 + a * (x0 - v0), v1 + a * (x1 - v1)], [d0, d1]
    d = [di + a_d * ((xi - vi) / dt - di) for xi, vi, di in zip(x, value, derivative)]
    speed = math.sqrt(sum(di * di for di in d))
    a = 1.0 / (1.0 + 1.0 / (2.0 * math.pi * (min_cutoff + beta * speed) * dt))
    return [vi + a * (xi - vi) for xi, vi in zip(x, value)], d


def scale_beta(beta: float, units_per_metre: float) -> float:
    """A beta given per metre, expressed for a signal in other units (e.g. pixels): the cutoff
    ``beta * speed`` must stay the same, and speeds scale by ``units_per_metre``."""
    return beta / units_per_metre
