"""Coverage counts only arc the performance went along (part of the coverage rule of
:mod:`behaviors.mop.refusal`): a template counts as covered only while its followed progress's
arc from its start is at most :data:`RUN_AHEAD` times the input's farthest reach from its anchor
since the performance began (both RMS per column in the template's spread, at its size; the
last samples averaged as engagement reads them). The bound bites only where the followed state
runs far ahead of anything the input did.

Why: the forward floor (:func:`behaviors.mop.window_kernel.step_windows`) keeps probability on
every state of the window, and a window of half-width 23 or more holds the whole line (46
states), whose end lies 0.11 sigma from its start. On a still puck the end state, matching it,
gains and wins after 3-8 s: the followed arc climbs 0.14 -> 4.65 (the line's whole path) over
15-20 samples while the input moves nowhere, and coverage counted it (``tabletop follow``'s
defaults, features as recorded, the six example gestures, 10 s still with 0.7 mm jitter, 40
draws: with ``--window`` 25 or 40 18 draws valid, up to 240 of 300 samples, 0.312 of the time;
none with 15 or with a puck's settings). There the followed arc is 20.6 or more times the
input's reach (10th percentile of the covered samples, the least draw); on true performances
(every template of ``bench/follow_quality.py`` at 0.7, 1 and 1.4x) at most 11.1 (follow's
defaults: a 0.7x figure eight at its end; 8.9 with a puck's settings). Measured with 15: the
still draws at windows 15, 25 and 40 valid on none of 40, either settings;
``bench/follow_quality.py --sections=sized,sequences,unrelated,after`` every tuned and held-out
figure identical (20: the same).

Measured and not kept: the arc asked for coverage (8% of the path) bounded when it is reached by
a multiple of the input's *current* reach: on true performances that need is up to 2.14 times
the reach when covered (the line at 0.7x with follow's defaults, its size not estimated), while
a still line's need is 1.69 times the jitter's reach at the least; 1.5 took every still draw
to 0, but valid after 30% of gestures at 0.7-1.4x 0.9157 -> 0.9124 (held-out 0.9049 -> 0.8899)
and gestures back to back among twenty recognised within 20% 0.344 -> 0.313 (mocap paths that
curve: their arc runs ahead of their chord); 1.8: 0.9138, 0.313; 2.0: 0.9147, held-out 0.8949.
A bound on each sample's advance by that sample's own displacement does not tell the still line:
a jitter step in its narrow column (spread 0.01 m) is 0.07 units, as large as a 0.7x stroke's
step. The input's own travel *in place of* the followed arc delayed recognition (see
:mod:`behaviors.mop.refusal`).
"""

from __future__ import annotations

#: A template counts as covered only while its followed arc is at most this many times the
#: input's farthest reach since the performance began (both in the template's spread).
RUN_AHEAD = 15.0
