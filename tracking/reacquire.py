"""A puck back from a coast: the pose shown while its return is unconfirmed.

Units: whatever the tracker uses (table metres by default), radians.
"""

from __future__ import annotations

import math

from tabletop.frames import wrap_angle


def reacquired(out: list[float], target: list[float], gap: list[float], returning: bool,
               lim: float, step_rad: float, units_per_metre: float
               ) -> tuple[list[float], list[float]]:
    """The pose shown, and the gap (shown minus measured) kept, for a reappeared puck shown at
    ``out`` and measured at ``target`` (``returning``: its first reading back): the gap
    between the two shrinks by at least ``lim`` (``step_rad``) per update, the shown pose
    either stepping toward the puck or keeping its shrunk offset from a moving puck,
    whichever ends nearer. Stepping alone never catches a puck faster than a step per
    update (0.01 m at 60 Hz: 0.6 m/s; pucks move up to 1.5 m/s). Measured on rendered
    frames (1280x720, 60 Hz, four pucks circling), p95 error of the shown pose while seen:
    a puck at 1-1.5 m/s hidden by a hand for 0.15-0.3 s, 79-91 mm stepping alone, 14-19 mm
    so; motion blur of 9.6 mm (0.6 m/s, 16 ms shutter), 34-60 mm and 14-17 mm."""
    # A step per update, not per 1/60 s: scaled by the time between updates, at 30 Hz
    # the shown pose while seen improved (hand over a puck at 0.5 m/s: p95 40-47 ->
    # 12-14 mm) but overall p95 grew at 1 m/s (126-127 -> 127-129 mm) and, scaled at
    # returns too, with 5% of frames read (217 -> 232 mm): kept per update.
    out[2] = target[2] + wrap_angle(out[2] - target[2])  # the measurement's branch
    if returning:
        gap = [out[0] - target[0], out[1] - target[1], out[2] - target[2]]
        g = math.hypot(gap[0], gap[1])
        cap = 0.15 * units_per_metre  # the shown pose held within 0.15 m of a puck back
        # after a long coast, not 0.3-0.77 m away (hand over a 1 m/s puck, 60 Hz: p95 101
        # -> 49 mm)
        if g > cap:
            gap[0] *= cap / g
            gap[1] *= cap / g
    gx, gy, ga = gap
    d = math.hypot(gx, gy)
    k = max(d - lim, 0.0) / d if d > 0.0 else 0.0
    held = [target[0] + gx * k, target[1] + gy * k]           # the offset kept, shrunk
    sx, sy = target[0] - out[0], target[1] - out[1]
    e = math.hypot(sx, sy)
    j = min(lim / e, 1.0) if e > 0.0 else 0.0
    stepped = [out[0] + sx * j, out[1] + sy * j]              # a step toward the puck
    if math.dist(stepped, target[:2]) < math.dist(held, target[:2]):
        held = stepped
    ga = math.copysign(max(abs(ga) - step_rad, 0.0), ga)
    sa = target[2] - out[2]
    sa = min(max(sa, -step_rad), step_rad)
    a = out[2] + sa if abs(target[2] - out[2] - sa) < abs(ga) else target[2] + ga
    gap = [held[0] - target[0], held[1] - target[1], a - target[2]]
    if math.hypot(*gap[:2]) <= 1e-12 and abs(gap[2]) <= 1e-12:
        return list(target), gap
    return [held[0], held[1], a], gap

