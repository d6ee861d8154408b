"""Constant turn-rate coasting: a hidden puck is predicted to keep turning as it turned while
it was seen, its speed fading, rather than to leave along its last tangent.

The rate of turn is measured from the direction of two chords between the last readings (a
chord across a circle points along the tangent at its middle in time). The velocity the
tracker holds lags the puck's: a chord points along the tangent half its span back, and the
low-pass of the velocity lags by its cutoff's phase; both are turned back before coasting.

Units: whatever the tracker uses (table metres by default), seconds, radians.
"""

from __future__ import annotations

import cmath
import math

from tabletop.frames import wrap_angle

TURN_WINDOW_S = 0.1  # s: the readings a turn is measured over (chords a frame long are too noisy)
TURN_SPAN_S = 0.4    # s: readings further apart than this measure no turn
TURN_SPEED = 0.1     # m/s: a slower chord's direction is too noisy to measure a turn by
REVERSAL_RAD = 2.5   # rad: a chord turned further from the one before is a reversal, not a turn


def decayed_travel(v: float, dt: float, decay_s: float) -> float:
    """Distance travelled in ``dt`` seconds from velocity ``v`` decaying exponentially with time
    constant ``decay_s``: v * decay_s * (1 - exp(-dt / decay_s))."""
    if dt <= 0.0:
        return 0.0
    return v * decay_s * (1.0 - math.exp(-dt / decay_s))


def turned_travel(vx: float, vy: float, turn: float, dt: float, decay_s: float
                  ) -> tuple[float, float]:
    """Displacement in ``dt`` s from velocity (vx, vy) whose speed fades with time constant
    ``decay_s`` while its direction turns at ``turn`` rad/s: the integral of
    v e^((i turn - 1 / decay_s) t). With ``turn`` 0 it is a straight line of
    v decay_s (1 - e^(-dt / decay_s))."""
    if dt <= 0.0:
        return 0.0, 0.0
    lam = complex(-1.0 / decay_s, turn)
    d = complex(vx, vy) * (cmath.exp(lam * dt) - 1.0) / lam
    return d.real, d.imag


def turned_velocity(vx: float, vy: float, turn: float, dt: float, decay_s: float
                    ) -> tuple[float, float]:
    """Velocity ``dt`` s on from (vx, vy) turning at ``turn`` rad/s, its speed fading with time
    constant ``decay_s``: v e^((i turn - 1 / decay_s) dt), the rate of ``turned_travel``."""
    if dt <= 0.0:
        return vx, vy
    z = complex(vx, vy) * cmath.exp(complex(-1.0 / decay_s, turn) * dt)
    return z.real, z.imag


def led_velocity(vx: float, vy: float, turn: float, span_s: float, cutoff_hz: float | None
                 ) -> tuple[float, float]:
    """The held velocity turned to the puck's present direction: back half the chord's span
    ``span_s``, and, where it was low-passed at ``cutoff_hz`` (None: a bare chord), by that
    filter's lag (the inverse of its response, 1 + i turn / (2 pi cutoff))."""
    z = complex(vx, vy) * cmath.exp(complex(0.0, 0.5 * turn * span_s))
    if cutoff_hz is not None:
        z *= complex(1.0, turn / (2.0 * math.pi * cutoff_hz))
    return z.real, z.imag


def extend_trail(trail: list[tuple[float, float, float]], t: float, x: float, y: float
                 ) -> list[tuple[float, float, float]]:
    """The readings (t, x, y) a turn is measured from, with the reading at ``t`` added: those
    within ``TURN_WINDOW_S``, else the last two, none when they span over ``TURN_SPAN_S``."""
    i, n = 0, len(trail)   # times rise: the readings kept are the newest
    while i < n and t - trail[i][0] > TURN_WINDOW_S:
        i += 1
    kept = trail[i:] if i < n else trail[-2:]
    if kept and t - kept[0][0] > TURN_SPAN_S:
        kept = []
    return kept + [(t, x, y)]


def turn_sample(trail: list[tuple[float, float, float]], least_speed: float) -> float | None:
    """Rate of turn (rad/s) between the chords first -> middle and middle -> last reading of
    ``trail`` (at least three); 0 where either is slower than ``least_speed``; None where the
    second turned back (a reversal)."""
    t0, x0, y0 = trail[0]
    t2, x2, y2 = trail[-1]
    mid = 0.5 * (t0 + t2)
    t1, x1, y1 = trail[1]
    for p in trail[2:-1]:   # the reading nearest the middle in time (the first of a tie)
        if abs(p[0] - mid) < abs(t1 - mid):
            t1, x1, y1 = p
    c1x, c1y, c2x, c2y = x1 - x0, y1 - y0, x2 - x1, y2 - y1
    if min(math.hypot(c1x, c1y) / (t1 - t0), math.hypot(c2x, c2y) / (t2 - t1)) <= least_speed:
        return 0.0
    a = wrap_angle(math.atan2(c2y, c2x) - math.atan2(c1y, c1x))
    if abs(a) > REVERSAL_RAD:
        return None
    return a / (0.5 * (t2 - t0))
