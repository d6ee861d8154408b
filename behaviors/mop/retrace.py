"""Where a followed action that fits the input still does not drive: its template's stretch
run backwards, and a size beyond the sizes performed (rules beside those of
:mod:`behaviors.mop.validity`, applied by :meth:`~behaviors.mop.recognition.Recognition._conclude`
and the group's :func:`behaviors.mop.members.conclude`).

Followed back away from where it reached (:func:`slid_away`): an action that drives, followed back
from its highest progress since it began driving to a place :data:`SLIDE_AWAY` of its template's
extent from the place it had there, stops driving, unless it had carried its performer
:data:`SLIDE_CARRY` forward (a performer going back along the gesture they performed rewinds it,
``tests/mop/test_plugin.py``) or its template turns back itself and comes back near the followed
place, with a size from ``scale_range``'s bottom on that puts the peak's place on the template's
turn (a line's return followed backwards at a size overestimated: the input turned where the line
turns, at a performed size). Mirrored paths among twenty templates retrace a template's stretch the
template never runs backwards: the zigzag taken at its corner (0.24) on the mirrored dance wrist,
followed to its next corner (0.38) and back along the same stroke; the walk ankle taken at 0.13 on
the mirrored spin ankle (out 5 cm and back), followed to 0.27 and back to 0.09, where the walk
turns only at 0.57 (13.7 cm out: a size of 0.44). True performances go back so only through a hold
drifted through while paused (the punch's fist held out, 0.74 -> 0.62, within 0.09 of its extent).
Tuned on ``bench/follow_widened.py`` (seeds 201-210; mirrored paths among twenty: worst / mean
valid share / over 0.1 of 540; sequences' wrong runs over 2 samples / their sum): before 0.239 /
0.01453 / 22, 14 / 46; with :func:`at_size_top` below, 0.184 / 0.01333 / 18, 14 / 46. Each alone:
this rule 0.212 / 0.01367 / 19, :func:`at_size_top` 0.239 / 0.01419 / 21 (sequences 14 / 46 both).
Without the line's exception the line of seed 202's fifth sequence stopped on its return, its end
was not seen and the walk ankle drove the roll after it 3 samples (over 2: 14 -> 15); without
:data:`SLIDE_CARRY` a figure eight rewound from 0.6 to 0.35 stopped driving, and the pauses of
``bench/follow_quality.py`` lost a little (valid over the pause 0.9551 -> 0.9534).
``bench/follow_quality.py`` (tuned): sized, holds, back to back, pauses and the CLI defaults the
same to the digit; unrelated mean 0.0154 -> 0.0151 (six templates' triangle 0.042 -> 0.029), worst
0.068 the same; after a gesture mean 0.0730 -> 0.0719. Held out (the final check, not chosen by):
valid after 30% at 0.7-1.4x 0.9049 -> 0.9046, unrelated worst 0.346 the same.
Screened on recorded ticks (the valid ticks each rule would stop, before the line's exception and
:data:`SLIDE_CARRY`): :data:`SLIDE_AWAY` 0.1, worst 0.175 but true ticks after 30% of gestures lost
(a 1.5x zigzag 3, a 0.85x line 1); 0.15 (kept) none lost, 0.184; 0.2: 0.193. Not kept: any slide
back of the progress while the performer moves (0.03 from the peak, with :func:`at_size_top`):
worst 0.172, but valid after 30% of gestures at 0.7-1.4x 0.9131 -> 0.9109 on the recorded ticks: a
1.2x punch paused with its fist held out, drifted to 0.74, lost 15 true ticks sliding back to 0.62
as its performer moved on (a 0.85x line 1).

At the top of the sizes performed (:func:`at_size_top`): an action whose size estimate is at
least :data:`SIZE_TOP` of ``scale_range``'s top does not drive: its path fits the input only at
a size beyond what is performed. The roll ankle followed the mirrored square at 1.4x at sizes
1.60-1.79 of 1.8 (0.212 of the time, seed 206); no true performance of ``bench/follow_quality.py``
(0.6-1.5x, tuned) drove at a size above 1.65.
"""

from __future__ import annotations

import numpy as np

from behaviors.kernel_cache import compiled


#: An action whose followed place lies this far (share of its template's extent) from its place
#: at the highest progress it reached while driving, back along its path, does not drive
#: (:func:`slid_away`; 0: never).
SLIDE_AWAY = 0.15
#: ... unless it carried its performer this far (progress) forward from where it began driving
#: first: a performer going back along the gesture they performed rewinds it.
SLIDE_CARRY = 0.2


def turns_ahead(reversal_at: np.ndarray, starts: np.ndarray, lengths: np.ndarray) -> np.ndarray:
    """Per state, its template's reversal that :func:`slid_away` measures a turn against (states
    from the template's first; -1 where none): the one
    :func:`~behaviors.mop.invariance.reversal_map` gives it (``reversal_at``, bank states), else
    the template's next reversal after it."""
    out = np.full(len(reversal_at), -1, dtype=np.intp)
    for s, n in zip(starts.tolist(), lengths.tolist()):
        own = reversal_at[s:s + n]
        turns = np.unique(own[own >= 0]) - s
        for i in range(n):
            later = turns[turns > i]
            out[s + i] = own[i] - s if own[i] >= 0 else (later[0] if later.size else -1)
    return out


@compiled()
def slid_away(places: np.ndarray, source: np.ndarray, turns: np.ndarray, began: float,
              peak: float, g: float, extent: float, size: float, lo: float, away: float,
              carry: float) -> bool:
    """Whether a driving action's followed state ``g`` (states from its template's first) lies
    ``away`` (:data:`SLIDE_AWAY`) ``extent`` or farther from its place at progress ``peak`` (its
    highest since it began driving, which was ``began``, by less than ``carry``:
    :data:`SLIDE_CARRY`) where its template never comes back: ``places`` (n, D), the
    template's states from its first (units); ``source`` (n,), their progress; ``turns`` (n,):
    :func:`turns_ahead`. Followed back that far, the action's path is run backwards over a
    stretch its performer went out along (see the module docstring). It is not when the
    template itself turns back (its reversal ``turns`` at the peak's state) and comes back
    within that distance of the followed place, and a size of at least ``lo`` puts the peak's
    place on that reversal (``size``: the estimate; a line's return followed backwards at a size
    overestimated): within the sizes performed, the input turned where the action turns. A hold
    drifted through (the punch's fist held out, 0.74 -> 0.62) moves less than that."""
    n = source.shape[0]
    if away <= 0.0 or n < 2 or peak - began >= carry:
        return False
    j = 0
    while j < n - 2 and source[j + 1] <= peak:
        j += 1
    span = source[j + 1] - source[j]
    f = min(max((peak - source[j]) / span, 0.0), 1.0) if span > 0.0 else 0.0
    i = min(max(int(g), 0), n - 2)
    h = min(max(g - i, 0.0), 1.0)
    d = places.shape[1]
    at = np.empty(d)
    top = np.empty(d)
    d2 = 0.0
    for c in range(d):
        top[c] = places[j, c] + f * (places[j + 1, c] - places[j, c])
        at[c] = places[i, c] + h * (places[i + 1, c] - places[i, c])
        d2 += (top[c] - at[c]) ** 2
    limit2 = (away * extent) ** 2
    if d2 < limit2:
        return False
    r = int(turns[j])
    if r < 0:
        return True
    qq = 0.0
    qp = 0.0
    for c in range(d):
        qq += places[r, c] * places[r, c]
        qp += places[r, c] * top[c]
    if qq <= 0.0 or size * qp < lo * qq:   # no size from lo on puts the peak on the turn
        return True
    for k in range(r, n):   # the template comes back near the followed place
        e2 = 0.0
        for c in range(d):
            e2 += (places[k, c] - at[c]) ** 2
        if e2 < limit2:
            return False
    return True


#: An action whose size estimate is at least this share of ``scale_range``'s top does not drive
#: (:func:`at_size_top`; above 1: never).
SIZE_TOP = 0.97


def at_size_top(size: float, hi: float) -> bool:
    """Whether a size estimate ``size`` sits at the top of the sizes a performer may give
    (``hi``: ``scale_range``'s top, above 1 / :data:`SIZE_TOP` only): its path fits the input
    only at a size beyond what is performed (see the module docstring)."""
    return size >= SIZE_TOP * hi > 1.0
