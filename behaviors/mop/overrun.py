"""Overrun: the input going on past where the action driving goes, while its progress lags.

A diagonal stroke among the six example gestures is the figure eight's first stroke (36 degrees
against 45, nearly straight): covered at 22% of the eight, it drives while the input goes on
straight and the eight's path turns away, its progress slowing (0.25 -> 0.28) while the input
keeps its pace. Traced (``bench/follow_quality.py``, held-out seed 101, six gestures, 0.7x): the
input's distance from the path near the followed state rises 0.5 -> 1.4 sigma over samples
36-45, while the path misfit (16 samples' memory) reads 0.29 -> 0.81 and the recent likelihood
0.81 -> 1.17; the drift's run (:meth:`~behaviors.mop.shape_lead.ShapeLead._drifts`), ended by
one dip, stopped it at sample 46: about 10 samples after the input left the path.

So the driving action is not shown valid while both hold (:func:`overruns`, for the best
template, against the samples and followed states the tempo keeps,
:meth:`~behaviors.mop.follower_validity.Validity._remember_tempo`):

- its followed progress covered less than :data:`PACE` of the input's displacement over the last
  :data:`PACE_SAMPLES` samples (path length against displacement, both in sigma at the size;
  the input moved at least :data:`PACE_MOVED`: a hold or a rest is no overrun), and
- the input's distance from the path (as the path misfit measures one sample, at the current
  size) is beyond :data:`RISE_AT` and grew by more than :data:`RISE` since
  :data:`RISE_SAMPLES` samples back,

unless the action's size estimate grew by :data:`GROWN` meanwhile: a gesture at 1.4x, its size
still converging outwards at its first turn, lies beyond the path at the estimate while its
progress waits (without it the figure eight, circle, zigzag and wave at 1.4x, seeds 0-1, were
vetoed 2-6 samples each around 25-40% of them; at 1.03, one sample each). The growth spares
an overrun's onset only (:data:`GROWN_ONSET_ONLY`): an action that overran at the sample before
stays overrun, its size growing or not, while the input lies beyond :data:`HELD_BEYOND` (last
paragraph).

Only what is shown is vetoed: the rules go on as if the tick were valid (the action stays
acquired, its run and drive go on, spotting sees it valid), so an action whose input comes back
to its path drives again at once. Vetoing through the rules instead (no longer acquired, taken
anew only once it leads, turned and is not slow; and at 0.6 sigma) cost valid after 30% of
gestures at 0.7-1.4x 0.9123 -> 0.8932 tuned, 0.9030 -> 0.8912 held-out (seed 101).

Chosen by replaying the follower's own per-tick figures (``--sections=sized,unrelated``, tuned
seed 13 and held-out 101: the share of true valid ticks after 30% the rule takes against the
worst unrelated valid share): pace over 6 samples below 0.85, distance rise over 4 samples
above 0.3 beyond 0.9 sigma took 0.13% / 0.22% of true ticks, held-out worst 0.138 -> 0.094
(beyond 1.0: 0.13% / 0.19%, 0.094; pace below 0.9: 0.22% / 0.22%, 0.087); beyond 0.6: 0.24% /
0.29% (0.094); without the pace term (rise 0.4 beyond 0.7): 1.2% / 0.8% (0.083); pace below
1.0: 0.46% / 0.29% (0.087); a decayed pace and distance (memories 6 and 4, path
length for the input's travel, jitter included): 0.7% / 0.5% (0.098); a shorter misfit memory
(4 samples, refused beyond 1.0): 0.6% / 0.5% (0.118). What the others miss: true performances
whose followed state lags on a fast segment (pace 0.55-0.9) while the size still converges
(the distance grows with it).

``OPENBLAS_NUM_THREADS=1 bench/follow_quality.py --sections=unrelated,sized,holds --seed=N``,
before -> after (tuned seed 13; held-out 101 / 102 / 103): unrelated worst 0.0649 -> 0.0582;
0.1379 -> 0.0986 / 0.1052 -> 0.0853 / 0.1356 -> 0.1049 (the diagonal among six, among twenty,
among twenty; 103's mirrored square 0.1091 -> 0.1030, the roll ankle's first half); mean
0.0130 -> 0.0110; 0.0151 -> 0.0128 / 0.0144 -> 0.0129 / 0.0172 -> 0.0157; valid after 30% of
gestures at 0.7-1.4x 0.9123 -> 0.9121; 0.9030 -> 0.9022 / 0.8759 -> 0.8749 / 0.9055 -> 0.9055;
at 0.6 / 1.5x 0.7556 -> 0.7543; holds' progress RMSE max unchanged (0.0555; 0.0461 / 0.0560 /
0.0489). Without :data:`GROWN`: held-out worst 0.0944 / 0.0814 / 0.1030, after 30% 0.9114;
0.9013 / 0.8747 / 0.9052. ``--sections=sequences,shapes`` (tuned / held-out 101): gestures
back to back identical; redrawn shapes valid after 30% bent 5% 0.8702 -> 0.8659 / 0.7465 ->
0.7450, bent 10% 0.6315 -> 0.6208 / 0.4761 -> 0.4686, 1.1x taller 0.8937 -> 0.8896 / 0.8703 ->
0.8674, 1.2x 0.3884 -> 0.3843 / 0.4342 -> 0.4273 (a bend the input follows away from the path
reads as an overrun). Left: the diagonal among twenty on seed 103 (0.117 / 0.088 / 0.110 at
0.7 / 1.0 / 1.4x), the eight driving 9-11 samples from 22% of it before the input's distance
from its path passes 0.9 sigma.

Held-out seeds 101-106 (``--sections=unrelated,sized,holds --seed=N``): unrelated worst 0.0986 /
0.0853 / 0.1049 / 0.1112 / 0.1080 / 0.1173, mean 0.0128 / 0.0129 / 0.0157 / 0.0189 / 0.0168 /
0.0208; valid after 30% at 0.7-1.4x 0.9022 / 0.8749 / 0.9055 / 0.8871 / 0.8818 / 0.8744 (tuned
0.9121); holds' RMSE max 0.037-0.056, backward at most 0.0023. Over 0.10: the diagonal (103
among twenty, 105 among six), the mirrored square (103, 0.1030), a wander (104, 0.1112), a spiral
with the circle alone (106, 0.1173). Traced per tick, of the valid ticks those where the motion
so far is a start of the action driving at some size and tempo (the bench's ``performs``), at
0.7 / 1.0 / 1.4x: the diagonal 2 of 9, 8 of 8, 11 of 11 (103), 2 of 9, 9 of 9, 12 of 12 (105
among six), 2 of 11, 7 of 7, 7 of 7 (101): the figure eight's first stroke (43-46 degrees up to
20% of it) at a larger size, followed at its estimate (0.92-0.99, shrinking) into its turn
(0.22-0.28), 0.2-0.85 sigma off its path, at pace (0.85-1.2 of the input's travel); the mirrored
square 4 of 5, 9 of 10, 16 of 19 (the punch ankle's first stretch; it stops a sample after
the corner). The wander (none of 23 and 24 at 1.0 / 1.4x) is the zigzag, sized afresh at the
wander's reversal (1.0 -> 0.58), its state leaping 0.19 -> 0.30 and taken again strained (recent
likelihood 1.46 sigma), then held through the final rest (carried forward, not weighed); the
spiral is its second loop followed as a circle (:mod:`behaviors.mop.refusal`). Measured and
not kept (tuned / held-out 103 / 104 valid after 30%; worst): an overrun whatever the pace once
the sample lies beyond 1.0 sigma (the misfit's acceptance) and rose by :data:`RISE`: 0.9071 /
0.9040 / 0.8847, worst unchanged (103's mirrored square 0.1030 -> 0.0970; its 0.7x corner and
the diagonal's last tick are spared by :data:`GROWN`); no new take while strained, or only a
re-take of the action that drove last (:mod:`behaviors.mop.refusal`); the wander's carry
(:func:`~behaviors.mop.validity.stalls`) counted from a re-take of the same action, not from its
first take: where the drive began reset there too, 0.9121 / 0.9018 / 0.8807, the wander 0.111 ->
0.084 (104's worst 0.0879), 103's unchanged; the carry alone, 0.9089 / 0.9002 / 0.8778. Each
ends one seed's worst at a cost near or over 0.005 and leaves the others. Replayed on the valid
ticks (the diagonal's on 103 and 105, 84; true ones after 30%, tuned, 3832): the distance
rising by 0.3 over 8 samples beyond 0.6 sigma while the size shrank below 0.985 of its value
then takes 17 of the 84 and 0.86% of the true (gestures at 0.7-0.85x whose size converges down
while they lag: the mirror of :data:`GROWN`); the input's heading against the path's over 6
samples, 9 degrees median on the diagonal, 13 at 90% of true ticks; the forward's spread, 0.8-0.9
states against 0.9 median true. The largest one-sample leap of the followed state in the 10
samples before a take: over 4 states at 10 of 126 unrelated takes (103, 104, 106) and 7 of 121
true ones.
Measured and not kept: the pace not counted once the input stopped (its last sample under a
quarter of its mean step over :data:`PACE_SAMPLES`), since the followed state runs on for a few
samples after a sudden stop and keeps the pace: the held-out spiral with the circle alone (seed
106, 1.0x) ends off the circle's path (0.93-0.97 sigma, 0.02-0.20 four samples back) and drove
the 3 samples after it stopped. ``bench/follow_seeds.py --sections=unrelated,sized,holds``
(seeds 101-106): unrelated worst of 106 0.1173 -> 0.1073, over the seeds 0.1173 -> 0.1112 (104's
wander), held-out valid after 30% 0.8818 -> 0.8816 on 105, the rest identical; but tuned
(``bench/follow_quality.py``) valid after 30% 0.91207 -> 0.91179 (a 0.7x walk ankle stopping in
its stance off its path at a size still converging: last step 0.04 sigma against 0.31, distance
0.66 -> 1.25), redrawn shapes bent 10% 0.6208 -> 0.6191, 1.2x taller 0.3843 -> 0.3811 (held-out
1.1x 0.8674 -> 0.8647), unrelated unchanged. With a strained action refused at rest as well
(:mod:`behaviors.mop.validity`, not kept either): over the seeds 0.1173 -> 0.1080 (105's
diagonal left), held-out valid after 30% mean 0.8876 -> 0.8866, tuned 0.9121 -> 0.9106; with it
refused only until carried forward (:mod:`behaviors.mop.validity`): 0.1080, mean 0.8864, tuned
as the pace alone.
Nor does the spiral's size keep drifting (106, 1.0x, per sample): the circle's estimate goes
1.026 at the take (sample 54) to 0.948 by sample 70 and stays 0.947-0.950 to its end; the size of
the last 6, 12 or 20 samples alone stays 0.93-0.96 over samples 62-82. Its second loop is one
circle drawn lopsided (it does not close), so a refusal on the size's drift does not tell it:
the estimate's largest change over 8 samples (log) on the spiral's valid ticks is 0.064 at most
(0.085 on 104's, the circle alone), against a median 0.004, 0.096 at 90% and 0.19 at 95% on the
true ticks valid after 30% (held-out seed 106, sized and holds, 6330 ticks: gestures drawn at
0.7-0.85x converge through their first half). The size of the input's last 6 samples' chord
against the followed states' (log, over the estimate) swings -0.25 .. 0.13 on the spiral and
past -6 (5%) and 0.96 (95%) on true ticks (the followed state lags, then leaps).
Measured and not kept: :data:`GROWN` sparing a sample only while the estimate is at least 1.0,
where it starts (the diagonal's eight shrinks to 0.97 along the stroke and grows back 0.979 ->
1.004 while the input runs past its turn: 105 at 1.4x; 103's 0.7x sample 46, 0.959 -> 0.972):
``bench/follow_seeds.py --sections=unrelated`` 101 0.0986 -> 0.0944, 103's diagonal 0.1049 ->
0.1006, 105 0.1080 -> 0.1017 (``tests/mop/test_overrun.py``'s diagonals 65 -> 59 valid, its
eights unchanged); but a 1.0x getup wrist (tuned), its estimate converging back up to 1.0 from
below at a turn, lost 3 samples (valid after 30% 0.887 -> 0.839), held-out (``--sections=sized``)
101 0.9022 -> 0.9018, 106 0.8744 -> 0.8741: an estimate converges to the truth from either side,
so where it started tells nothing. Figures with the carry counted while
driving as well: :mod:`behaviors.mop.validity` (stalls).
Kept, :data:`GROWN_ONSET_ONLY` (held-out seeds 107-112 as well): the diagonal's figure eight,
overrun 3-5 samples, parks at 0.281-0.283 of it while its size estimate grows back (0.959 ->
0.978; 0.985 -> 1.004) and :data:`GROWN` spared it again 1.5-1.95 sigma off its path (112 among
six at 0.7x, 3 ticks; 111 at 1.4x, 2; 105 at 1.4x, 3; 103 among twenty at 0.7x, 1). A cap on the
distance or a size floor does not tell them: the growth spares true ticks counted in valid after
30% at 1.5-2.3 sigma and sizes 0.68-1.21 too (a cap at 1.5: held-out 111 and 112 two each, a
1.0x figure eight at 2.12; tuned redrawn shapes four, a punch wrist at 2.3), but none of those
overran the sample before. ``bench/follow_seeds.py --sections=unrelated,sized,holds,sequences``
(seeds 101-112), unrelated worst 0.0986 / 0.0853 / 0.1049 / 0.1112 / 0.1080 / 0.1173 / 0.1206 /
0.0913 / 0.1193 / 0.0891 / 0.1058 / 0.1036 -> 0.0944 / 0.0814 / 0.1030 / same / 0.0996 / same /
same / same / 0.1154 / same / 0.0918 / 0.0936, the 135 other figures identical (valid after 30%,
RMSE, holds, back to back). ``bench/follow_quality.py``: 509 of 541 figures identical, the rest
lower unrelated and after-a-gesture shares (unrelated mean 0.0109 -> 0.0105; after a gesture max
0.1654 -> 0.1604, held-out 0.1891 -> 0.1758). Held at any distance (beyond :data:`RISE_AT`) the
same, but the pauses section lost a wave driving as its pause began (3 ticks at 1.14 / 0.99 /
0.91 sigma, its size growing: valid over the pause 0.9551 -> 0.9545) and held-out redrawn shapes
bent 5% a dance ankle (5 ticks, 1.07 -> 1.80 sigma at size 0.93-0.95; 0.7450 -> 0.7425); held
only beyond :data:`HELD_BEYOND` (1.2, the refusal's default acceptance), both began their hold
nearer and are spared.

The held-out spin wrist on a circle (twenty templates back to back): its path up to its turn
(0.29) is the circle's start up to 0.37; taken there as true spins are, it drove 4-6 ticks while
its followed state waited at the turn and the input went on up the circle at its speed, its
size estimate growing 1.05 -> 1.36 (:data:`GROWN` spares that) at pace 0.89-1.1. Beside this
veto, :mod:`behaviors.mop.speed_profile` hides it there (longest wrong run on seeds 110 and 112
4 -> 3; at one sample alone it lowered valid after 30% at 0.7-1.4x on four seeds, held-out holds
0.9625 -> 0.9610 and bent 5% 0.7466 -> 0.7448; at 0.1 sigma a sample and without the input past
the state, valid after 30% 0.9036 -> 0.9007 mean over seeds 107-112: joints' slow stretches).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from behaviors.kernel_cache import compiled
from behaviors.mop import path_kernel
from behaviors.mop.path_kernel import PATH_REACH, nearest_on_path

#: Samples back over which the action's progress is weighed against the input's travel ...
PACE_SAMPLES = 6
#: ... an overrun only while the path length the followed progress covered meanwhile is under
#: this share of the input's displacement (both in sigma, RMS per column, at the size) ...
PACE = 0.85
#: ... and the input moved at least this many sigma meanwhile (a hold is no overrun) ...
PACE_MOVED = 0.5
#: ... and the input's distance from the path (sigma, RMS per column, at the size) grew by more
#: than this since :data:`RISE_SAMPLES` samples back ...
RISE = 0.3
RISE_SAMPLES = 4
#: ... to beyond this (0: never an overrun) ...
RISE_AT = 0.9
#: ... unless the size estimate grew by this factor over :data:`PACE_SAMPLES` (an input larger
#: than the estimate lies beyond the path at it while its progress waits: the size converges);
#: not where its template waits while the input goes on straight (bends.unspared).
GROWN = 1.01
#: Whether an action that overran at the sample before stays overrun while the input runs on,
#: its size growing or not (:data:`GROWN` spares an overrun's onset only; see the docstring).
GROWN_ONSET_ONLY = True
#: ... while the input lies beyond this many sigma of the path (the refusal's default
#: acceptance, ``accept_distance``).
HELD_BEYOND = 1.2

_FA1, _FA2 = numba.float64[:], numba.float64[:, :]


@compiled(numba.float64(_FA2, numba.intp, numba.intp, numba.intp, _FA1, _FA1, _FA1, _FA1,
                        _FA1, numba.float64, numba.float64, numba.float64), path_kernel)
def off_path2(means, lo, n, off, scale, uf, co, x, anchor, g, size, path_scale) -> float:
    """The squared distance (sigma squared, mean per column) of sample ``x`` seen from
    ``anchor`` (``(x - anchor) / scale + uf``, read at ``size`` and offset by ``co``: the
    template's mapping) from the template's path (its states ``lo`` .. ``lo + n - 1``, rows
    ``off`` on in ``means``) within :data:`PATH_REACH` states of the followed state ``g``
    (from the template's first; ``path_scale``: sigma^2 times the columns):
    :func:`behaviors.mop.path_kernel.nearest_on_path`."""
    z = np.empty(x.size)
    for c in range(x.size):
        z[c] = ((x[c] - anchor[c]) / scale[c] + uf[c]) / size + co[c]
    best = nearest_on_path(means.T, lo, lo + n - 1, off, lo + g, z, np.empty(x.size),
                           PATH_REACH[0], PATH_REACH[1])
    return best / path_scale


@compiled(numba.float64(_FA1, numba.intp, numba.intp, numba.intp, numba.float64))
def arc_at(arc, lo, n, off, g) -> float:
    """The path length (the template's spread) from its first state to ``g``."""
    j = int(math.floor(g))
    a = arc[lo + j + off]
    return a + (g - j) * (arc[lo + min(j + 1, n - 1) + off] - a)


@compiled(numba.boolean(_FA2, _FA1, numba.intp, numba.intp, numba.intp, _FA1, _FA1, _FA1,
                        _FA1, _FA1, _FA1, _FA1, numba.float64, numba.float64, numba.float64,
                        numba.float64, numba.float64, numba.float64, numba.float64,
                        numba.boolean, numba.boolean), path_kernel)
def overruns(means, arc, lo, n, off, scale, uf, co, anchor, x, x_rise, x_pace, g, g_rise, g_pace,
             size, size_pace, path_scale, dims, held, sparing) -> bool:
    """Whether the input ``x`` departs from the template's path (see the module docstring):
    ``x_rise``, ``g_rise``: the sample and followed state (from the template's first)
    :data:`RISE_SAMPLES` back, ``x_pace``, ``g_pace`` and the size ``size_pace``
    :data:`PACE_SAMPLES` back; the rest as
    :func:`off_path2` (``arc``: each state's path length, rows as ``means``; ``dims``: the
    columns; ``held``: the action overran at the sample before, which its size's growth does
    not spare beyond :data:`HELD_BEYOND`; ``sparing``: whether its size's growth may spare it at
    all, :func:`behaviors.mop.bends.unspared`)."""
    grown = sparing and size > GROWN * size_pace
    if RISE_AT <= 0.0 or (grown and not (held and GROWN_ONSET_ONLY)):
        return False
    moved2 = 0.0
    for c in range(x.size):
        r = (x[c] - x_pace[c]) / (scale[c] * size)
        moved2 += r * r
    moved2 /= path_scale
    if moved2 <= PACE_MOVED * PACE_MOVED:
        return False
    sigma = math.sqrt(path_scale / dims)
    adv = abs(arc_at(arc, lo, n, off, g) - arc_at(arc, lo, n, off, g_pace)) / sigma
    if adv >= PACE * math.sqrt(moved2):
        return False
    now = math.sqrt(off_path2(means, lo, n, off, scale, uf, co, x, anchor, g, size, path_scale))
    if grown and now <= HELD_BEYOND:
        return False
    then = math.sqrt(off_path2(means, lo, n, off, scale, uf, co, x_rise, anchor, g_rise, size,
                               path_scale))
    return now > RISE_AT and now - then > RISE
