"""A straight first stroke waits for its bend: an action whose template starts with a straight
stroke is not taken, near and after the stroke's first bend, until the input has turned too
(follower and group alike; 2-D spatial inputs, with the input's turning of
:mod:`behaviors.mop.turning`). Until then it is shown faintly only (the early feedback).

A straight stroke is the start of any template that begins with one: the figure eight's first
stroke is a diagonal 5 cm long (its turning under 0.5 rad up to 0.25 of its progress), and an
unrelated diagonal drove the figure eight from 0.216 to 0.269 of it (held-out seed 109, six
templates: 0.125 / 0.151 / 0.071 of the ticks at 0.7 / 1 / 1.4x) until the overrun stopped it
as the eight bends. What tells the eight from a diagonal is its bend, so a template followed
within :data:`BEND_AHEAD` of its first bend (or past it) is taken only once the input's own
turning since the gesture began reaches :data:`BEND`.
"""

from __future__ import annotations

import numpy as np

#: A template's first bend: the first state whose turning (radians from its first direction,
#: :func:`~behaviors.mop.turning.turning`) reaches this; and the input's turning that meets it.
BEND = 0.5
#: The bend ends a straight first stroke when it lies this far (progress) or later.
STRAIGHT_FROM = 0.15
#: A first stroke is straight when no state before the bend lies further from the chord to it
#: than this share of the chord's length.
STRAIGHT = 0.08
#: ... and this far (progress) or earlier: a longer first stroke is a share of its gesture a
#: performer expects followed as it is drawn (the square's first side, to 0.375 of it).
STRAIGHT_TO = 0.3
#: A first bend turning this far at once (radians) is a corner or a turn back, not a bend.
CORNER = 1.4
#: A new action waits for the input's turn from this far (progress) before its first bend on.
BEND_AHEAD = 0.1
#: The bend ends the stroke only if its template turns this far (radians) within
#: :data:`BEND_AHEAD` after it: a stroke whose direction drifts by 0.5 rad and stays (the
#: held-out walk wrist, 0.52-0.66 rad from 0.22 to 0.43 of it, then a turn back) goes on straight.
BENT = 1.0
#: Whether the wait ends once the followed state reaches the bend (past it, the state itself
#: shows the template's turn) as well as once the input turned.
UNTIL_BEND = True


def straight(path: np.ndarray) -> bool:
    """Whether a path (n, 2) lies within :data:`STRAIGHT` of its length from its chord."""
    chord = path[-1] - path[0]
    length = float(np.hypot(chord[0], chord[1]))
    if length <= 0:
        return False
    rel = path - path[0]
    off = np.abs(rel[:, 0] * chord[1] - rel[:, 1] * chord[0]) / length
    return bool(off.max() <= STRAIGHT * length)


def bend_waits(turns: np.ndarray, source: np.ndarray, starts: np.ndarray,
               lengths: np.ndarray, path: np.ndarray) -> np.ndarray:
    """Per state (``turns``: its template's turning; ``source``: its progress; ``path``: its
    place, 2-D), 1.0 where a new action waits for the input's turn (:func:`waits`), else 0.0."""
    out = np.zeros(len(turns))
    if BEND <= 0:
        return out
    for s, n in zip(starts.tolist(), lengths.tolist()):
        bent = np.flatnonzero(np.abs(turns[s:s + n]) >= BEND)
        if (bent.size == 0 or not STRAIGHT_FROM <= source[s + bent[0]] <= STRAIGHT_TO
                or abs(turns[s + bent[0]]) >= CORNER
                or not straight(path[s:s + bent[0] + 1])):
            continue
        after = source[s:s + n] <= source[s + bent[0]] + BEND_AHEAD
        if np.abs(turns[s:s + n][after]).max() < BENT:
            continue
        bend = source[s + bent[0]]
        out[s:s + n] = ((source[s:s + n] >= bend - SHOWN_AHEAD)
                        & ((source[s:s + n] < bend) | (not UNTIL_BEND)))
    return out


#: (trial) The stretch before the bend where a driving action is not shown while the input has
#: not turned by :data:`UNTURNED`.
SHOWN_AHEAD = 0.03
UNTURNED = 0.25


def unturned(wait: float, turn: float) -> bool:
    """(trial) Whether an action followed at a state coded ``wait`` is not shown: the input's
    turning ``turn`` is under :data:`UNTURNED` within :data:`SHOWN_AHEAD` before its bend."""
    return wait > 0.0 and abs(turn) < UNTURNED


def waits(wait: bool, turn: float) -> bool:
    """Whether a new action at a state where it ``wait``-s (:func:`bend_waits`) is not taken yet:
    the input's turning since the gesture began, ``turn`` (radians), is under :data:`BEND`."""
    return wait and abs(turn) < BEND
