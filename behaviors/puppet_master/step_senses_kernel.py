"""The look and the new sample pair's motion (look.desired_look, features.EntityMotion.step
and features.relative_pose) compiled for the compiled step (step_kernel), operation for
operation. Units: table metres, radians, Hz."""

from __future__ import annotations

import math

import numba
import numpy as np

from behaviors.kernel_cache import compiled
from behaviors.puppet_master import step_math
from behaviors.puppet_master.step_math import hypot, remainder

GAZE, RELATIVE, NORMALISED = 0.0, 1.0, 2.0   # look.FRAMES' codes in the step table

_f8 = numba.float64
_F1 = numba.float64[::1]


@compiled(_f8(_f8, _f8, _f8, _f8, numba.boolean, _f8, _f8, _f8))
def desired_look(frame: float, angle: float, still_frame: float, still_angle: float,
                 moving: bool, move_dir: float, md: float, gaze_base: float) -> float:
    """look.desired_look."""
    if frame == NORMALISED and not moving:
        frame, angle = still_frame, still_angle
    base = gaze_base if frame == GAZE else md if frame == RELATIVE else move_dir
    return base + angle



@compiled(numba.types.UniTuple(_f8, 3)(_F1, numba.int64, _f8, _f8, _f8, _f8), step_math)
def _motion(s: np.ndarray, at: int, x: float, y: float, rate_hz: float,
            min_speed: float) -> tuple[float, float, float]:
    """features.EntityMotion.step on s[at: at + 3] (x, y, move)."""
    dx, dy = x - s[at], y - s[at + 1]
    s[at], s[at + 1] = x, y
    speed = hypot(dx, dy) * rate_hz
    prev = s[at + 2]
    if speed >= min_speed:
        s[at + 2] = math.atan2(dy, dx)
    d = remainder(s[at + 2] - prev, math.tau)
    return speed, s[at + 2], (math.pi if d == -math.pi else d)


@compiled(numba.types.UniTuple(_f8, 3)(_f8, _f8, _f8, _f8, _f8, _f8), step_math)
def relative_pose(mx: float, my: float, md: float, rx: float, ry: float,
                  rd: float) -> tuple[float, float, float]:
    """features.relative_pose."""
    c, s = math.cos(md), math.sin(md)
    dx, dy = rx - mx, ry - my
    d = remainder(rd - md, math.tau)
    return c * dx + s * dy, -s * dx + c * dy, (math.pi if d == -math.pi else d)
