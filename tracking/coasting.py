"""Coasting: a track's prediction while its puck is hidden, and the rate of turn it follows.

A track whose source delivers a frame without it is predicted with a decaying velocity turning
at the puck's measured rate of turn (tracking.turning) and reported ``coasting``. Units: the
tracker's (table metres by default, scaled by ``units_per_metre``), radians, seconds.
"""

from __future__ import annotations

import math

from tracking.track import MAX_OMEGA, Track, TrackerSettings
from tracking.turning import (TURN_SPEED, decayed_travel, extend_trail, led_velocity, turn_sample,
                              turned_travel, turned_velocity)


def predicted(s: TrackerSettings, tr: Track, t: float) -> tuple[float, float]:
    """Where the track's puck is expected at ``t`` (s): its last reading carried along its
    chord, fading with ``coast_decay_s``."""
    k = decayed_travel(1.0, t - tr.t, s.coast_decay_s)
    return tr.meas[0] + k * tr.chord[0], tr.meas[1] + k * tr.chord[1]


def turned(s: TrackerSettings, tr: Track, meas: list[float], t: float, broken: bool,
           relocated: bool) -> None:
    """Update the rate of turn of the puck's direction of travel (tracking.turning). A puck
    back from a coast keeps turning as it did; a relocated one does not. Reset at a return,
    pucks on 9 cm circles read in 7-8% of frames (12.8 mm blur) were shown worse: overall
    p95 181.7 -> 189.6 mm at 60 Hz, 180.0 -> 184.9 mm at 30 Hz, nine seeds pooled."""
    if broken:
        tr.steady = len(tr.trail) >= 3 and not relocated
        tr.trail = []
        if relocated:
            tr.turn = 0.0
    if tr.trail and t <= tr.trail[-1][0]:
        return  # another reading of the same moment
    tr.trail = extend_trail(tr.trail, t, meas[0], meas[1])
    if len(tr.trail) < 3:
        return
    sample = turn_sample(tr.trail, TURN_SPEED * s.units_per_metre)
    if sample is None:  # turned back, not turning
        tr.turn = 0.0
        return
    dt = max(t - tr.t, 1e-6)
    a = 1.0 / (1.0 + 1.0 / (2.0 * math.pi * s.velocity_cutoff_hz * dt))
    tr.turn += a * (min(max(sample, -MAX_OMEGA), MAX_OMEGA) - tr.turn)


def miss(s: TrackerSettings, tr: Track, t: float) -> None:
    """The track's puck is not read at ``t`` (s): it coasts from the pose shown when it was
    last seen."""
    # A reappeared puck's gap is held, not closed, while it is hidden again: closing it
    # then too made the shown pose of pucks seen in 14-17% of frames (motion blur) worse
    # (p95 198-257 -> 256-289 mm).
    if tr.state != "coasting":
        tr.state, tr.anchor = "coasting", list(tr.out)
    k = decayed_travel(1.0, t - tr.t, s.coast_decay_s)
    a = tr.anchor
    dx, dy = turned_travel(*led(s, tr), tr.turn, t - tr.t, s.coast_decay_s)
    tr.out = [a[0] + dx, a[1] + dy, a[2] + k * tr.omega]
    tr.coast_t = max(t, tr.t)


def led(s: TrackerSettings, tr: Track) -> tuple[float, float]:
    """The held velocity turned to where the puck heads when it was last read."""
    return led_velocity(tr.vx, tr.vy, tr.turn, tr.vspan,
                        s.velocity_cutoff_hz if tr.vfiltered else None)


def coasting_velocity(s: TrackerSettings, tr: Track) -> tuple[float, float, float]:
    """The fade ``k`` of the angular velocity and the velocity (vx, vy) of the pose shown:
    the prediction's, turned and faded, while coasting; else the track's own."""
    if tr.state != "coasting":
        return 1.0, tr.vx, tr.vy
    dt = max(tr.coast_t - tr.t, 0.0)
    k = math.exp(-dt / s.coast_decay_s)
    vx, vy = turned_velocity(*led(s, tr), tr.turn, dt, s.coast_decay_s)
    return k, vx, vy
