"""Association: which of the measurements of a puck's id the track takes.

Of the measurements of an id, the one nearest the track's prediction is taken (a duplicate id
in one frame is resolved by consistency with the track, not by order); one outside the gate
(``gate_m`` plus ``max_speed`` times the time since the puck was last seen) is an outlier and
ignored, unless it is seen again at the same place ``confirm_frames`` times in a row (the puck
was really moved there), but not a still place while the track was moving. Far readings are
followed as the track's rival (tracking.rivals): a rival that moves while the track lies still
is the puck, and the place left is a print. Units: the tracker's (table metres by default,
scaled by ``units_per_metre``), seconds.
"""

from __future__ import annotations

import math

from tabletop.frames import PuckMeasurement
from tracking.coasting import predicted
from tracking.rivals import follow, screened
from tracking.track import STILL_SPEED, Track, TrackerSettings


def gate(s: TrackerSettings, tr: Track, t: float) -> float:
    """The outlier gate's radius at ``t`` (s), in the tracker's units."""
    u = s.units_per_metre
    return u * (s.gate_m + s.max_speed * max(t - tr.t, 0.0))


def associate(s: TrackerSettings, tr: Track, ms: list[PuckMeasurement]
              ) -> tuple[PuckMeasurement, bool] | None:
    """The measurement consistent with the track and whether it relocates the puck; None if
    every one is an outlier. ``ms`` share one time, not older than the track's."""
    t = ms[0].t
    px, py = predicted(s, tr, t)
    g, u = gate(s, tr, t), s.units_per_metre
    if len(ms) == 1 and tr.decoy is None:   # the usual case, without list overhead
        if math.hypot(ms[0].x - px, ms[0].y - py) <= g:
            tr.candidate, tr.candidate_count = None, 0
            return ms[0], False
    dists = [math.hypot(m.x - px, m.y - py) for m in ms]
    if tr.decoy is not None:
        ms, dists = screened(ms, dists, tr.decoy, u * s.gate_m)
        if not ms:
            return None
    far = [i for i in range(len(ms)) if dists[i] > g]
    if far:
        m = ms[min(far, key=lambda i: math.dist((ms[i].x, ms[i].y), (tr.rival.x, tr.rival.y))
                   if tr.rival else dists[i])]
        reach = u * (s.gate_m + s.max_speed * (t - tr.rival.t if tr.rival else 0.0))
        r = tr.rival = follow(tr.rival, m.x, m.y, t, reach, tr.meas, u * s.gate_m)
        if (r.moved() > u * s.gate_m and tr.state == "seen"
                and math.hypot(tr.meas[0] - r.tx, tr.meas[1] - r.ty) <= u * s.gate_m):
            # The rival moves, the track's place lies still: the rival is the puck.
            # Rendered frames, puck and print of its marker lying still, the puck then
            # moved at 0.4 m/s: taken 0.15-0.2 s after it starts, then 5-11 mm off (held
            # by the print, 0.47-0.57 m); the bench's figures without prints unchanged.
            tr.decoy, tr.rival = (tr.meas[0], tr.meas[1]), None
            tr.candidate, tr.candidate_count = None, 0
            return m, True
    k = min(range(len(ms)), key=dists.__getitem__)
    if dists[k] <= g:
        tr.candidate, tr.candidate_count = None, 0
        return ms[k], False
    # Far from the track: a false detection, unless it keeps appearing at the same place.
    m = ms[k]
    still_at, still_t = tr.candidate, tr.candidate_t
    tr.candidate_t = t
    if (tr.candidate is not None
            and math.hypot(m.x - tr.candidate[0], m.y - tr.candidate[1]) <= u * s.gate_m):
        tr.candidate_count += 1
    else:
        tr.candidate_count = 1
    tr.candidate = (m.x, m.y)
    if tr.candidate_count >= s.confirm_frames:
        tr.candidate, tr.candidate_count = None, 0
        if (math.hypot(*tr.chord) > STILL_SPEED * u and not tr.reacquiring
                and still_at is not None and math.hypot(m.x - still_at[0], m.y - still_at[1])
                <= STILL_SPEED * u * max(t - still_t, 0.0) + 1e-3 * u):
            # A still place read again and again while the track was moving: a print
            # of its marker, not the puck moved there. Rendered frames, a circling puck
            # hidden 0.3 s by a hand: 53-57 mm off while coasting (relocated to the print,
            # 0.47-0.63 m off until dropped).
            tr.decoy = (m.x, m.y)
            return None
        return m, True
    return None
