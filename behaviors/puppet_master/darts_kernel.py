"""darts.py compiled for the compiled step (step_kernel), operation for operation."""

from __future__ import annotations

import numba
import numpy as np

from behaviors.kernel_cache import compiled
from behaviors.puppet_master import character, darts, step_math
from behaviors.puppet_master.character import TOUCH_M
from behaviors.puppet_master.darts import DART_MARGIN
from behaviors.puppet_master.step_math import _max, _min, hypot

_f8 = numba.float64


@compiled(_f8(_f8, _f8, _f8, _f8, _f8, _f8), step_math)
def span_approach(nx: float, ny: float, ox: float, oy: float, bx: float, by: float) -> float:
    """darts.span_approach."""
    rho = hypot(bx, by)
    return ((nx - ox) * bx + (ny - oy) * by) / rho if rho > 1e-9 else 0.0


@compiled(numba.boolean(_f8[:, ::1], numba.int64, numba.int64, numba.int64, _f8, _f8, _f8, _f8,
                        _f8, _f8), step_math, darts)
def dart_goes_on(recent: np.ndarray, count: int, head: int, n: int, moment: float, dt: float,
                 mx: float, my: float, bx: float, by: float) -> bool:
    """darts.dart_goes_on, the main's positions in the ring ``recent`` (``count`` of them,
    the next written at ``head``)."""
    if count < n:
        return True
    o = (head - n) % recent.shape[0]
    return span_approach(mx, my, recent[o, 0], recent[o, 1], bx, by) <= moment + \
        DART_MARGIN * n * dt


@compiled(numba.types.UniTuple(_f8, 2)(_f8, _f8, _f8, _f8, _f8, _f8, _f8, _f8), step_math,
          character)
def less_inward(sx: float, sy: float, qx: float, qy: float, bx: float, by: float, dist: float,
                disc: float) -> tuple[float, float]:
    """darts.less_inward."""
    rho = hypot(bx, by)
    if not 1e-9 < rho < TOUCH_M <= dist:
        return sx, sy
    a = (qx * bx + qy * by) / rho
    if a >= 0.0:
        return sx, sy
    f = 1.0 - _max(0.0, _min(1.0, (rho - disc) / (dist - disc)))
    return sx - f * a * bx / rho, sy - f * a * by / rho
