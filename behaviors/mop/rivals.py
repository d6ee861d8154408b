"""Broader rivals: a template improbable only for its breadth still keeps a narrower action from
driving (:meth:`~behaviors.mop.shape_lead.ShapeLead._leads`, the group's kernel alike).

The held-out twenty templates' 11-tick run is the evidence's breadth, not the fit: a spin wrist
drove a circle's 0.297-0.399 (seed 101's first twenty-template sequence, after a wave). The
circle's path so far lies within 2.2-4.1 mm of a start of the spin's
(``bench.spotting_reach.closest_start``) up to 0.37 of it, then 6.3, 10.8 and 19 mm at 0.38-0.40;
sigma is 9.0 x 11.1 mm on the circle (the broadest of the twenty), 7.9 x 5.9 mm on the spin, whose
narrower Gaussian (the evidence's Jacobian) is worth it 0.77 nats a sample where both fit. Per
tick: the circle engaged at 0.17 and covered at 0.25, on its path, fitting better in shape by
0.8-1.0 nats up to 0.32 and worse by at most 1.3 up to 0.37, but probability 0.000, so no rival;
the spin, best from 0.25, took the drive at 0.297 leading no one, and drove until the circle led by
10.5 and 39 nats (0.389, 0.399) and became best at 0.41; no commitment (the circle never led by
:data:`~behaviors.mop.shape_lead.LEAD`), no spotting reset in between. Within sigma (and the 7.5 mm
of the 5% bend ``bench/follow_shapes.py`` asks it to follow) the two starts are one path; a shape
margin alone holds true actions (where one at 0.7-1.4x, not yet driving, passed this rule, a
covered template on its path fitted better by over 2 nats at 23 of 895 samples, held-out 37 of 890:
a line by the square). ``bench/follow_seeds.py --sections=sequences`` (longest wrong run 11, 7, 10,
2, 2, 4 on 101-106): the spin on a circle 7 (102: it fits better in shape by 4-12 nats at
0.30-0.37) and 10 ticks (103), the punch ankle on a getup wrist 4 and 7 (103); ``--seed=202``: the
spin on circles, 6 and 7.

Kept: a template broader than the action by :data:`BROADER` nats a sample (the Jacobian at their
sizes), engaged, covered, on its path, not going back (as
:meth:`~behaviors.mop.spotting.GestureSpotting._shares`' rivals) and within
:data:`~behaviors.mop.shape_lead.LEAD` of its shape sum either way is a rival whatever its
probability: where two fit alike, the narrower's probability is its sharper Gaussian.
``bench/follow_quality.py`` (tuned / held-out): held-out twenty's longest wrong run 11 -> 4 (the
backflip ankle's end into a square's eased start, the input under 1 mm; any other wrong action 11
-> 2), every within-20% share, the six's runs and every other target figure unchanged but valid
after 30% at 0.7-1.4x 0.9121 -> 0.9117 / 0.9022 (a spin ankle held 1-2 samples);
``bench/follow_seeds.py --sections=sized,sequences`` (101-106): runs 11, 7, 10, 2, 2, 4 -> 4, 5, 7,
2, 2, 4 (102: the spin fits that circle better in shape; 103: the punch ankle on the getup wrist,
broader by less), within 20% and held-out valid after 30% unchanged on every seed. 0.45 a sample:
the same runs, valid after 30% lower on every seed (mean 0.8876 -> 0.8867); any broader (0): runs
4, 5, 2, 2, 2, 4, but lower on every seed (mean 0.8844; 102 0.8749 -> 0.8670: lines held behind
squares on their shared stroke, 0.35 broader, punch ankles behind getup wrists), bench 0.9113 /
0.9004, aspect 1.1 shapes 0.8896 -> 0.8736. 0.6 lies between the pairs it must spare (a line under
the square 0.35 nats a sample, a punch ankle under a getup wrist 0.48) and the spin under the
circle (0.77); among the tuned twenty no longest wrong run changes (``back_to_back`` seeds 0-39).
Any broader rival however it fits: valid after 30% 0.9113 / 0.8978 (a 0.7x line, followed at the
wrong size until its turn, fits 18-25 nats worse than the square: 0.611 -> 0.417), 0.9115 / 0.8978
with the rival's probability re-weighed at the action's spread instead; also going back: 0.9090 /
0.8936, a line back to back never recognised (102).

Measured and not kept before: any better-fitting covered template on its path: 11 -> 4, but sized
0.9014 -> 0.8942 held-out (an earlier follower). Shared starts made symmetric (also held while a
rival's followed state lies in its start shared with the action, ``sharing.shared_until``): the
held-out run 11 -> 7 (share radius 4: 4), but six gestures within 20% 0.125 -> 0.

Seeds 107-112 (``bench/follow_seeds.py --sections=sequences``; twenty templates' longest wrong run
3, 6, 4, 4, 5, 4), both 6-tick runs on 108 traced per tick:
- getup wrist, circle, square, figure eight: the punch left ankle drove the getup wrist's
  0.110-0.152, from the gesture's start. The getup was engaged, covered and not misshaped from
  0.08, fitting *better* in shape by 16.7-25.7 nats, at probability 0.000-0.002: the punch's
  Gaussian is narrower by 0.49-0.51 nats a sample. No rival twice over: under :data:`BROADER`,
  and beyond LEAD of the punch's shape sum (the bound "either way"). It ended when the getup
  reached probability 0.019 (a rival by probability, leading by 30 nats); the getup drove from
  0.183.
- jump ankle, circle, crawl ankle, kick wrist: the spin wrist drove the circle's 0.313-0.382.
  The circle, a broader rival alike in shape, held it at 0.265-0.289. From 0.301 the spin led it
  in shape by 6.2-17 nats (as on 102), the circle no rival, while the spin's size rose 1.10 ->
  1.41 (its progress 0.24-0.29, its take misfit 0.12 -> 0.63) until misshaped at 1.5.
Measured and not kept (the follower alone, ``--sections=sized,sequences`` on 107-112): broader
rivals *ahead* in shape by LEAD or more counted from 0.45 nats a sample: runs 3, 6, 4, 2, 5, 4,
but valid after 30% lower on every seed, mean 0.8745 -> 0.8729 (111: 0.8812 -> 0.8760); an
action whose size moved by over 3% in three samples does not lead: runs 3, 6, 4, 2, 2, 2, but
valid after 30% mean 0.8745 -> 0.8234, twenty within 20% 0.297 -> 0.260 (8%: runs 3, 6, 4, 4,
5, 2, valid after 30% 0.8544): true actions' sizes move as much early on.
Broader rivals ahead in shape by LEAD or more counted at BROADER too (the bound one way, follower
and group): on seeds 101-112 runs 4 -> 3 on 106 and 110, no other run or within-20% share
changed; but held-out valid after 30% 0.9022 -> 0.9013 (101: a 0.7x line held behind the square,
0.611 -> 0.528) and 0.9055 -> 0.9044 (103), held-out bent 10% 0.4686 -> 0.4590; tuned, only
after a gesture changed (mean 0.0639 -> 0.0627). Elsewhere the spin's rising size narrows its
gap to the circle under BROADER (112: 0.63 -> 0.27 nats a sample over its 4-tick drive).
Traced again (``bench/follow_seeds.py --sections=sequences``, the follower per tick): on seeds 110
and 112 the spin wrist drove the circle's 0.362-0.393 and 0.365-0.395 (4 ticks each) while its
progress stalled at 0.28-0.29 and its size rose 1.10 -> 1.27 and 1.20 -> 1.36 (110: the circle
fitting better by 5.7-30 nats, beyond LEAD; 112: within LEAD for its first two ticks, their gap
under BROADER at the spin's size); on 103 the punch ankle drove the getup wrist's 0.107-0.171 (7
ticks) at its size 0.98 -> 0.92, the getup engaged, covered and fitting better by 22-35 nats (RMS
2.0-2.6 still radii against the punch's 3.6-4.2). Measured and not kept (the follower alone):
broader rivals ahead by LEAD or more counted from 0.45 nats a sample (as above) end the punch's runs
(103: 7 -> 0 and 4 -> 2; 108: 6 -> 2), but on the sized performances (seed 111, valid after 30%
0.8812 -> 0.8760) the getup wrist fits the punch ankle's *own* performances better by 5-34 nats too
(RMS 1.5-3 still radii, the punch's 2-4): neither the shape nor the fit tells the two apart. An
action that stalls while its size grows does not drive (its log size up by over 0.07 in two samples
while its progress advanced under 0.03): runs 110 4 -> 2, 112 4 -> 1, 108 6 -> 3, 102 5 -> 3, but
seed 111's valid after 30% 0.8812 -> 0.8683: on the sized performances the spin stalls so at
0.27-0.29 of its path (at 0.9-1.8x), and figure eights, lines and punch ankles while they drive:
actions' sizes grow as their progress stalls on their own performances too.
Each template's breadth averaged over the samples since the gesture began, forgotten over 20
samples (the evidence's memory), instead of at its size now (follower and group): the spin is
judged as narrow as it was, 112's run 4 -> 2 (draws 65, 123, 212 of ``back_to_back`` among the
held-out twenty: 4 -> 1, 4 -> 2, 3 -> 0), every other run on 101-112 and every within-20% share,
unrelated and holds figure unchanged; but valid after 30% lower on 9 of the 12 seeds (102
0.8749 -> 0.8746, 110 0.8877 -> 0.8873, 111 0.8812 -> 0.8807). ``bench/follow_quality.py``:
tuned valid after 30% 0.9117 -> 0.9119, held-out bent 5% 0.7450 -> 0.7444, the rest identical.
Not forgotten (the plain mean): the same runs, valid after 30% lower on 10 of the 12 seeds (104
0.8871 -> 0.8867); where it changed the rivals on seed 111's sized performances, spins at
1.2-1.4x were held by the circle (gap 0.33-0.48 at their size, 0.70-0.76 as the mean) and jump
ankles at 1.2-1.5x by the square and the circle: actions whose size grew, as the spin grown on
the circle.
Every run over 2 ticks among the held-out twenty (``bench/follow_seeds.py --sections=sequences``,
seeds 101-112, longest 4/5/7/2/2/4 and 3/6/4/4/5/4), traced per tick: the spin wrist on a circle's
0.31-0.40 (102, 108, 110, 111, 112: 4-6 ticks, its size rising 1.10 -> 1.41 as above); the punch
ankle on a getup wrist's 0.11-0.30 (103: 7 and 4, 108: 6, 109: 4); an ended action into the next
gesture's eased start, its follower two samples behind its performer at the end (101: the
backflip ankle into a square, 4; 106: the jump ankle into a crawl ankle, 3; 107: the backflip
ankle into a wave, 3; 109: the line into a zigzag, 3: :mod:`~behaviors.mop.gesture_end`); the
line on the square's first side (106, 3); and on 106 the crawl ankle on a wave's 0.18-0.24 (4):
the dance ankle before it, followed back down its path (0.53 -> 0.24 while its performer went
0.61 -> 0.905), ended there as a return (``gesture_end.RETURN_BACK``), so the wave's attempt was
anchored four samples before the wave began, on the dance's last stroke.
Measured and not kept: shared starts (:mod:`~behaviors.mop.sharing`) at 4 still radii instead of
3 only against a template broader than the action by X nats a sample (the Jacobian at size 1: the
circle over the spin 0.77, the getup wrist over the punch ankle 0.48, the square over the line
0.35). X 0.45 (the spin held by the circle's start to 0.26 of it, the punch by the getup's to
0.29): ``bench/follow_seeds.py --sections=sequences`` (101-112) runs 4, 5, 7, 2, 2, 4 -> 4, 2, 2,
2, 2, 4 and 3, 6, 4, 4, 5, 4 -> 3, 2, 4, 4, 2, 4, but twenty within 20% on 102 0.281 -> 0.250 (a
true punch from rest recognised at 0.197 -> 0.277, spins 0.270 -> 0.322) and valid after 30% at
0.7-1.4x lower on every seed 101-106 (mean 0.9000 -> 0.8968). X 0.6 (the spin alone): runs 102 5
-> 2 and 111 5 -> 2, every within-20% share unchanged, but ``bench/follow_quality.py`` valid after
30% 0.9124 -> 0.9107 (tuned; held-out 106 0.8910 -> 0.8909): true spins wait for the circle's
start as long.
Measured and not kept: a rival within the evidence's own noise. Each sample's log-likelihood under
a template's Gaussian varies by sqrt(d / 2) nats on its own spread, two templates' difference by
sqrt(d), so their evidence difference after n samples (forgotten over ``memory``) by sqrt(d * sum
of decay^(2i), i < n): 4.2 nats 20 samples into a gesture. At the wrong takes above the true
template lay 6.7-12.2 nats behind (109's punch 46), 13-29 samples in; the 108 right takes within
20% led their runner-up by a median 9.1 (52 by under 8.5). Any template within Z such deviations
behind the action, whatever its probability, made a rival
(:meth:`~behaviors.mop.shape_lead.ShapeLead._leads`; follower and group kernel).
``bench/follow_seeds.py --sections=sequences`` (101-112), twenty longest wrong run 4/5/7/2/2/4 and
3/6/4/4/5/4: Z 2 -> 110 and 112 4 -> 2, every within-20% share and six-gesture figure unchanged; Z
3 also 103 7 -> 2, 106 4 -> 3, but within 20% 104 0.313 -> 0.281 (a true dance ankle from rest
0.191 -> 0.212, held by the getup wrist and the square, 10-12 nats behind and ahead of it in
shape); Z 5 also 102 0.281 -> 0.250. Only where the rival also agrees over the part seen (its
summed standardized fit within 1 deviation of the action's): figures as Z 3. Z 2
``--sections=sized,unrelated``: valid after 30% at 0.7-1.4x lower on every seed (mean 0.9000 ->
0.8962, 0.8944 -> 0.8903; 105 0.8937 -> 0.8823), and with shared starts off (``share_radius`` 0) a
line waits for the square up to 0.42 of it (0.35). Z 2 only for a rival broader than the action
(its Jacobian at its size): runs 110 and 112 4 -> 2, 103's 7 stays; valid after 30% on 105 0.8937
-> 0.8831. Z 3 only for a rival fitting the part seen at least as well in shape: runs 103 7 -> 2,
110 and 112 4 -> 2 (102's 5 stays), but within 20% 104 0.313 -> 0.281 and valid after 30% on 105
0.8937 -> 0.8814: the getup wrist fits a true dance ankle's start better in shape too.
Measured and not kept: the take decided on the fit in each template's own spread. The evidence is
each template's standardized log-likelihood (the forward's ``step_ll``) less its spread's log volume
at its size; summed since the gesture began, that fit leads the narrower action only where it fits
better than its narrowness explains. At the wrong takes above it did not separate them from right
ones: the spin wrist fitted the circle's start -0.6 to -3.4 nats worse than the circle, the punch
ankle the getup wrist's +2.9 to +5.9 better (both rivals within their own spread: mean chi-square
0.36-0.69 per feature, its expected value 1), but true spins fitted as close to the circle at
their takes (-0.7 to +1.0). Rule (the follower alone): an action not yet driving is held while a
template broader by :data:`BROADER` nats a sample (its mean since the gesture began), open, not
going back and within chi-square 1 per feature fits at least as well in its own spread.
``bench/follow_seeds.py --sections=sequences`` (seeds 102, 108, 110, 111, 112): twenty templates'
longest wrong run 5/6/4/5/4 -> 2/6/2/2/2 (108: the punch ankle, fitting better), within 20% and
six gestures unchanged; but ``--sections=sized,unrelated`` (101-106) valid after 30% at 0.7-1.4x
lower on every seed, 0.9076/0.8938/0.9162/0.9028/0.8937/0.8910 -> 0.9062/0.8924/0.9150/0.9006/
0.8904/0.8893 (105: a dance ankle at 0.7x 1.0 -> 0.78, held by broader templates fitting it
better in their spread while it fitted its own at chi-square 1.1-1.6; spins at 0.85-1.4x held
1-4 samples by the circle; a jump ankle at 1.4-1.5x by the backflip ankle). The action within
its own spread too: 105 0.8937 -> 0.8928; and held only while the rival fits better by 1 nat
(``--sections=sized,unrelated,sequences``, 101-112): runs 110 and 112 4 -> 2, every other figure
unchanged but valid after 30% lower on 11 of 12 seeds (mean 0.9008 -> 0.9003, 0.8960 -> 0.8952;
105: the spin at 1.2x, its rival fitting better by 2.1-3.1 nats, the jump ankle at 1.4x by
5.3-7.2, both held at a 2-nat margin too).
Measured and not kept: a narrower rival less probable than the action no rival (the reverse of
:func:`broad_rivals`: the line, predicting a spin's or a circle's start more sharply, kept it from
leading while the broader action was the likelier all the same). ``bench/follow_quality.py
--sections=sequences`` (tuned / held-out): narrower by more than 0.01 nats a sample, held-out twenty
within 20% or by the reach + 0.05 0.625 -> 0.656 (one gesture), by the reach 0.406 -> 0.438, no
wrong run longer, the rest unchanged; but ``--sections=unrelated,after`` a template's own stroke
among twenty told 0.098 -> 0.120 (over its 0.10), twenty templates' unrelated mean 0.0086 ->
0.0105, a wander among twenty held-out 0.006 -> 0.021: on a straight stroke the narrow line is
what keeps a broader template from driving it. Only where the rival is under a tenth as probable:
the same gains, own stroke 0.120, mean 0.0092; narrower by :data:`BROADER` (0.6): only the tuned
twenty's mean past the reach moves (0.101 -> 0.100); only a rival beyond ``COMMIT_FIT`` itself:
every figure as at 0.01 (the narrower rivals waived never fitted the stroke that well).
Measured and not kept (the shown valid replayed over one recorded run, 107-112,
``--sections=sized,sequences``): in an action's first 25% or 30%, every open template (engaged,
covered, on its path, not going back) a rival whatever its probability or breadth, the action
not shown until it leads them all by LEAD: no seed's longest wrong run shorter (108's and
111's are the spin's, which leads the circle in shape at its take), sized valid after 30% 0.9070
-> 0.9069 (25%), 0.9061 (30%). On 101-106 (25%; alike with the rival broader, or leading the
action by LEAD, or both): 103's run 3 -> 2 (the punch ankle on the getup wrist), but twenty
within 20% on 102 0.313 -> 0.281 and sized valid after 30% lower on 102, 104 and 105 (0.9036 ->
0.9033 on 102); at 30% also 101's by the reach + 0.05 0.625 -> 0.594, sized lower on five seeds.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from behaviors.kernel_cache import compiled
from behaviors.mop import spotting
from behaviors.mop.compiled import CONTRACT
from behaviors.mop.spotting import SHARE_BACK

#: A template broader than the action by more than this many nats a sample (the evidence's
#: Jacobian at their sizes: the log of their spread's volume) is a rival whatever its
#: probability, where alike in shape (:func:`broad_rivals`; inf: never).
BROADER = 0.6


def broad_rivals(bi: int, spread: np.ndarray, open_: np.ndarray, progress: np.ndarray,
                 gone: np.ndarray, shape: np.ndarray, lead: float) -> np.ndarray:
    """(K,) the rivals of template ``bi`` whatever their probability: broader than it by
    :data:`BROADER` (``spread``: each template's log spread volume at its size, nats a sample),
    ``open_`` (not refused, engaged, covered, on their path), not going back (``progress``
    :data:`~behaviors.mop.spotting.SHARE_BACK` below ``gone``, their highest since the gesture
    began) and within ``lead`` of its ``shape`` sum either way (the shape sums' units)."""
    return (open_ & (progress >= gone - SHARE_BACK) & (spread > spread[bi] + BROADER)
            & (np.abs(shape - shape[bi]) < lead))


_FA1, _BA1 = numba.float64[:], numba.boolean[:]


@compiled(numba.float64(numba.intp, numba.intp, numba.intp, numba.intp, numba.intp,
                        numba.float64, numba.float64, numba.float64, numba.float64, numba.float64,
                        _FA1, numba.float64[::1], _FA1, _FA1, _FA1, numba.float64[::1], _BA1, _BA1,
                        _BA1, _BA1, numba.float64[:, ::1]),
          spotting, fastmath=CONTRACT)
def least_rival(a0: int, a1: int, gb: int, bk: int, fb: int, others: float, kept: float,
                rival_p: float, lead: float, dims: float, ev: np.ndarray, p: np.ndarray,
                shape: np.ndarray, size: np.ndarray, gone: np.ndarray, progress: np.ndarray,
                refused: np.ndarray, engaged: np.ndarray, covered: np.ndarray,
                misshaped: np.ndarray, tc: np.ndarray) -> float:
    """The least shape sum among template ``gb``'s rivals in ``a0:a1`` (a group member's;
    inf where none), compiled for the group's kernel (:meth:`ShapeLead._leads
    <behaviors.mop.shape_lead.ShapeLead._leads>`): not refused, and probable (``p``, times the
    threshold model's share ``kept``, at least ``rival_p``; with a barred best ``bk`` >= 0 the
    probabilities among the others, ``fb`` the likeliest of them and ``others`` their
    normaliser: :mod:`~behaviors.mop.blocked`) or broader by :data:`BROADER` and alike in shape
    (:func:`broad_rivals`; ``lead``: the shape sums' lead, ``tc``'s first column and ``size``
    each template's log spread and size, ``dims`` the member's columns)."""
    rival = np.inf
    spread = tc[gb, 0] + dims * math.log(size[gb])
    for k in range(a0, a1):
        if k == gb or refused[k] or shape[k] >= rival:
            continue
        # ... or broader and alike in shape (broad_rivals)
        pk = p[k] if bk < 0 else (0.0 if k == bk else math.exp(ev[k] - ev[fb]) / others)
        if pk * kept >= rival_p or (
                engaged[k] and covered[k] and not misshaped[k]
                and progress[k] >= gone[k] - SHARE_BACK
                and abs(shape[k] - shape[gb]) < lead
                and tc[k, 0] + dims * math.log(size[k]) > spread + BROADER):
            rival = shape[k]
    return rival
