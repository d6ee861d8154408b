"""When a followed template may drive its character: refusal, path misfit, coverage (and what
was tried beside them). The input's turning: :mod:`behaviors.mop.turning`.

Refusal (null rejection), per template against its own spread (:mod:`behaviors.mop.hmm`):
per-step log-likelihoods forgotten with ``null_memory`` samples, read as an RMS distance in
``sigma`` units. Beyond ``null_distance`` the template is refused; it is accepted again below
``accept_distance`` (hysteresis, not a permanent latch: with the bird alone in
``tests/mop/test_live.py`` the latch and the hysteresis took the same 3 of 17 other gestures
at 60% with one spread per template, and the hysteresis takes 0 with one per column).
Tighter limits did not separate unrelated motion from true performances: null 1.4 / accept
1.05 cut true validity after 30% from 0.90 to 0.75 while unrelated motion stayed 0.55-0.62
valid; 1.1 / 0.85: 0.65 and 0.51.

Two rules on the template's *path* (its states joined by segments), each measured against the
template's own spread, whatever the other templates:

- Coverage: a template drives only once its followed progress has covered ``coverage`` of its
  path's length since it engaged (path length in its spread, RMS per column; kept until the
  performance begins anew). The start of every template is a small, slow blob that any small
  wiggle matches at a small size: an aimless wander drove the circle alone 75-86% of the time
  at 15-23% of its progress. Recognition comes a little later (at 30% of gestures at
  0.7-1.4x: 0.73 -> 0.68 of them).
- Path misfit: the distance of the input, mapped as the forward algorithm sees it, from the
  path's segments within :data:`PATH_REACH` states of the followed state, as an RMS over the
  last ``shape_memory`` samples in ``sigma`` units; refused beyond ``shape_distance``,
  accepted again below ``shape_accept``. The predictive likelihood carries the transitions'
  uncertainty (about 1 sigma on exact copies); the distance to the joined states does not (a
  time-warped copy sits at 0.12 sigma median), so a diagonal line along a circle's chord
  (0.3 of its radius off at the middle) shows. The remembered samples are read at the
  current size estimate: read at the size each had when it came, a 0.7x circle, whose size
  converges from 1 to 0.76 between 30% and 45% of it, was refused for a third of its length.

Measured with ``bench/follow_quality.py`` partial runs (sizes and unrelated sections, seed 13
and the held-out joints, seed 101; "unrelated" = worst / mean valid share over every motion
and template count; "after 30%" = valid after 30% of gestures at 0.7-1.4x):

==============================================  ===============  ===============  =====  =====
rules                                           unrelated        held-out         after  held
==============================================  ===============  ===============  =====  =====
neither (before)                                0.82 / 0.33      0.75 / 0.34      0.916  0.912
misfit 1.0 / 0.7, memory 10, per-sample size    0.54 / 0.22                       0.862
  same with sizes 0.8-1.25x the estimate tried  0.63 / 0.29                       0.914
misfit 1.2 / 0.8, memory 16 (per-sample size)   0.59 / 0.26                       0.912
misfit 1.5 / 1.0 (per-sample size)              0.82 / 0.32                       0.916
coverage 0.6 spread units (absolute)            0.63 / 0.25                       0.915
coverage 10%                                    0.60 / 0.18                       0.911
coverage 10% + misfit 1.2 / 0.8                 0.53 / 0.14                       0.906
coverage 15% + misfit 1.2 / 0.8                 0.50 / 0.08                       0.892
coverage 12% + misfit 1.1 / 0.75                0.50 / 0.11                       0.884
coverage 10% + misfit 1.0 / 0.7                 0.49 / 0.11                       0.870
coverage 10% + misfit 1.4 / 1.2                 0.58 / 0.18      0.74 / 0.21      0.910  0.897
coverage 4% + misfit 1.4 / 1.2, current size    0.72 / 0.29
coverage 6% + misfit 1.4 / 1.2, current size    0.63 / 0.25                       0.915  0.905
coverage 8% + misfit 1.4 / 1.2                  0.61 / 0.22      0.74 / 0.23      0.914  0.901
  (kept; misfit read at the current size)
coverage 8% + misfit 1.25 / 1.05, current size  0.58 / 0.19      0.68 / 0.21      0.913  0.897
==============================================  ===============  ===============  =====  =====

(Rows without "current size" read each sample's misfit at the size estimated when it came;
memory 16 unless said.) Coverage delays recognition a little, which gestures back to back
feel: among the six, recognised within 20% of each gesture 0.31 of them with the misfit alone,
0.28 at coverage 4%, 0.03 at 6%, 0 at 8% (median recognition 0.24 -> 0.26); set ``coverage``
lower where that matters more than refusal. Sizes tried around the estimate let a triangle's
stroke cutting a square's corner fit the square's side at 0.8x, hence worse. What is left:
motions that *are* a stretch of some template at some size and tempo: the triangle's first
stroke is the line's outward half (valid from 8% of the line's path to its far end), a
diagonal is the figure eight's first stroke and then a chord of the circle that stays within
1.4 sigma, a mirrored mocap path's slow start is another's.

Tried beside the likelihood before, measured with ``bench/follow_quality.py`` and left out,
since the unrelated motions still find stretches of some template that match them in every
respect these rules see (a diagonal line is the chord of a circle's first quarter at 1.5x; a
stroke of a triangle is the outward half of the line):

- Direction of motion at the followed state (``1 - |cos|`` of the angle between the input's
  velocity and the template's, going back allowed, averaged over the recent moving samples):
  over 2 samples with the input moving above a quarter of the template's median speed it cut
  the worst unrelated share from 0.76 to 0.58, but valid after 30% of gestures at 0.7-1.4x fell
  from 0.92 to 0.89 and a puck's jitter during a vertical lift's hold read as crossing motion
  (hold RMSE max 0.06 -> 0.44); over 4 samples with the input above 3x that speed it changed
  nothing measurable (unrelated 0.664 with and without), above 1.5x it made it 0.69.
- Pace: the template path covered by the followed progress against the input's displacement
  over 8 samples (true performances 0.61-1.36 in 96% of samples, unrelated ones below 0.38 in
  10%): unrelated 0.664 -> 0.637 while valid after 30% fell to 0.895; stricter, 0.59 but
  0.85 and holds lost.
- Distance at the followed state instead of the predictive likelihood (which carries the
  transitions' uncertainty, about 1 sigma even on exact copies): exact copies 0.64 sigma
  (median), unrelated motions while valid 0.87: no threshold separates them, since a state is
  0.7 sigma from the next on a 61-sample circle at sigma 0.2.
- Pace, signed (decayed sums over 8 samples of the input's motion and of the followed state's,
  in the template's units at the current size): on the bench's valid ticks the followed state
  explained less than 0.3 of the input's motion (its motion projected on the input's) in 14-19%
  of the unrelated ones and 0.4-0.9% of true ones. Refused while below 0.3 with the input moving
  at least 0.3 sigma (back from 0.5): unrelated worst / mean 0.49 / 0.188 -> 0.38 / 0.151, but
  valid after 30% of gestures at 0.7-1.4x 0.908 -> 0.887 (mocap paths whose followed state lags
  on fast segments, the line's turn); 0.5 sigma, 0.3 / 0.5: 0.40 / 0.170; 6 samples, 0.6 / 0.8:
  0.40 / 0.140; judged only before the action drives: 0.46 / 0.182.
- No going back behind where the action began driving (by more than 4% of its path): 0.44 /
  0.172, but valid after 30% 0.897: a line's return is followed backward while its size is
  still wrong (the line at 0.7x: 0.9 -> 0.3).
- Rivals: letting a template drive only while no other engaged, unrefused template explained
  the recent samples about as well (within 0.5 sigma) stopped the line from driving the start
  of a square, but with twenty templates some other template nearly always fits as well: valid
  after 30% of gestures at 0.7-1.4x fell from 0.92 to 0.59 (margin 0.1: 0.73). Checked only
  before a template is recognised (once valid it stays so): 0.91 -> 0.82 at margin 0.3 (0.72
  at 0.6), while the longest wrong-valid run back to back fell from 11 to 5 samples (median);
  recognition at 30% of gestures 0.73 -> 0.47.

Not back before forward (:func:`backs_first`): an action that has not yet carried its
performer forward (its progress never passed where it began driving by :data:`FORWARD_FIRST`)
stops driving once its progress falls :data:`BACK_FIRST` behind where it began, and is not taken
again until it goes forward (the last action that drove keeps where it began until another one
drives or the gesture starts anew). A performer going back along a gesture they performed still
drives it backwards; what this refuses is a path that is a template's stretch gone *backwards*:
the triangle's last two strokes are the wave's first hump reversed (the wave was taken at its
hump and drove the triangle back to the wave's start, 62 ticks at 0.7x), a mirrored line is the
end of another clip's path gone backwards. Measured with ``bench/follow_quality.py``'s sized and
unrelated sections (tuned; held-out in brackets; unrelated worst / mean, valid after 30% of
gestures at 0.7-1.4x): before 0.435 / 0.153, 0.9008 (0.595 / 0.161, 0.8854); kept (forward
2%, back 2%) 0.367 / 0.145, 0.9008 (0.565 / 0.151, 0.8853); back 3%: 0.367 / 0.147, 0.9008
(0.565 / 0.153, 0.8853); forward 4%, back 3%: 0.367 / 0.147, 0.8948. Screened on recorded
ticks: forward 5%, back 3% (the line at 0.7x, its return followed backwards while its size was
still wrong, lost 18 ticks). Stopped only while it drives (a stopped action was taken again 2
samples later, one step further back): tuned 0.415 / 0.151 only.

Carried forward before it holds (:func:`stalls`): an action that drove while the performer
moved, without its progress passing where it began driving by :data:`CARRY_FIRST`, stops
driving once the performer rests (:func:`resting`: the net motion of the last samples within
:data:`RESTING_RADII` still radii), and drives again when they move on. The input moved it on
the spot, so nothing specific to it was seen: a wander hovering at the circle's start (the
circle taken at 0.23, still there 47 samples later), a diagonal stopped on the circle's chord or
on the figure eight's first stroke, the triangle's stroke stopped in the square's first side.
A gesture carried forward keeps driving through a pause (the performer expects the character to
wait with them). Measured with ``bench/follow_quality.py``'s sized and unrelated sections (as
above): unrelated 0.367 / 0.145 -> 0.301 / 0.123 (held-out 0.565 / 0.151 -> 0.476 / 0.132), valid
after 30% 0.8959 -> 0.8928 (held-out 0.8844 -> 0.8844): a 0.7x kick paused 0.6 s whose followed
progress lagged the performer by 0.2 is no longer valid through the pause, a 0.85x spin paused
right after its recognition loses 4 samples, and a 0.7x line (its return followed backwards)
gains 3 (the full bench: 0.6x/1.5x valid after 30% 0.619 -> 0.603, held-out unchanged; holds,
gestures back to back and streams unchanged to the last digit). Measured and not kept: the
follower's still test (every sample within 2 still radii over
6 samples) instead of net motion: 0.316 / 0.130 (0.551 / 0.147; with twenty templates loaded the
still radius is about the tracking jitter, so a resting puck rarely read as still); the rule only
after 6 moving samples (a gesture paused just after its recognition spared): 0.367 / 0.133
(0.537 / 0.140) at the same 0.8927; :data:`CARRY_FIRST` 0.08: 0.291 / 0.116 at 0.8928 but held-out
0.476 / 0.129 at 0.8796; and no *new* action taken while the performer rests (there is no evidence
then either): 0.301 / 0.108 (0.476 / 0.126) but valid after 30% 0.8886 (0.8838): gestures whose
recognition fell in a pause waited for the performer to move on.

Tempo (:func:`slow_take`): a new action is taken only if, over the last :data:`TEMPO_SAMPLES`
samples, its followed state moved at least :data:`LEAST_TEMPO` states per sample (either way),
or the input moved less than the onset (in the template's spread at its size) meanwhile. Much of
unrelated motion's residue is a template stretched over the input: its followed state crawls (a
diagonal held in the figure eight's first turn, 0.22 -> 0.28 over 26 samples) while the input
sweeps on; a performer goes at 0.5-2x the recorded tempo (the bench 0.6-1.6x). Judged at the
take only: a taken action keeps driving at any tempo (pauses, holds, a slow end). Measured with
``bench/follow_quality.py --sections=sized,unrelated`` (tuned; held-out in brackets; unrelated
worst / mean, valid after 30% of gestures at 0.7-1.4x): before 0.305 / 0.105, 0.9021 (0.572 /
0.122, 0.9115); kept (10 samples, 0.3) 0.305 / 0.085, 0.9016 (0.515 / 0.098, 0.9112): triangle
with twenty templates 0.30 -> 0.13, diagonal 0.18 -> 0.06, held-out wander 0.30 -> 0.15; holds
and gestures back to back unchanged to the digit. 15 samples: 0.305 / 0.085, 0.9016 (0.468 /
0.095, 0.9110), but among twenty templates back to back recognised within 20% 0.344 -> 0.281
(0.313 -> 0.281). Signed (a state going back never taken): 0.305 / 0.083, 0.9016 (0.511 / 0.097,
0.9112), but a line's return followed backwards (size overestimated) is not taken again after a
pause at its turn, so its end (:meth:`GestureSpotting._returned`) is never seen and it drives
the next gesture's first samples (``tests/mop/test_quality.py``, 4 samples). At 0.4 signed:
0.305 / 0.076, 0.8994 (0.472 / 0.091, 0.9108); 0.5: 0.305 / 0.070, 0.8958 (0.472 / 0.087,
0.9073), unsigned 0.8992 (0.9073): the sized cost is mostly that 0.7x line's return, valid off
track (valid 0.70 -> 0.17, on track 0.07 both). An upper tempo (2x) refused no unrelated take.
What is left is taken at a performer's tempo: the mirrored line's return is the line's outward
stroke, then rests at its turn (a line paused there); a triangle's base is the square's first
side.

Crawling (:func:`crawls`): an action, taken or not, stops driving once the tempo test above
found it crawling :data:`CRAWL_SAMPLES` samples in a row; it is then taken again only at tempo.
Taken at tempo, a template's stretch still crawls once the input leaves what it explains (a
diagonal held at the circle's 0.38 along its chord). ``bench/follow_quality.py
--sections=sized,holds,unrelated`` (tuned; held-out in brackets; unrelated worst / mean, valid
after 30% at 0.7-1.4x): before 0.305 / 0.0846, 0.9016 (0.515 / 0.0977, 0.9112); kept (6) 0.305
/ 0.0803, 0.9016 (0.488 / 0.0925, 0.9025), holds unchanged: the held-out loss is mostly valid
*off track* (a 0.85x punch ankle 0.97 -> 0.63, on track 0.28 both), beside a 1.4x line (on
track 0.49 -> 0.39). 4: 0.294 / 0.0773, 0.8997 (0.473 / 0.0887, 0.8992); 5: 0.305 / 0.0794,
0.9014 (0.480 / 0.0907, 0.9009); 8: 0.305 / 0.0822, 0.9016 (0.504 / 0.0948, 0.9063); 10:
0.305 / 0.0833 (0.515 / 0.0963, 0.9081). Back to back unchanged but for twenty templates
(never recognised 0.031 -> 0). Most gained: a diagonal, six templates 0.165 -> 0.088; held-out
diagonal with twenty 0.293 -> 0.183, wander 0.186 -> 0.117.

Resting behind where it began (:func:`rests_behind`): an action does not hold a performer
resting :data:`REST_BEHIND` behind where it began driving (back within what had not yet told
it): the held-out mirrored line with twenty templates, a punch ankle taken at 0.2, followed to
0.37, back to 0.07 and resting there. As above, after crawls: 0.305 / 0.0803 -> 0.305 / 0.0788
(0.488 / 0.0925 -> 0.488 / 0.0911): a mirrored kick ankle, twenty templates, 0.7x 0.443 ->
0.273, the held-out mirrored line 0.7x 0.595 -> 0.417; valid after 30% and holds unchanged to
the digit (no true performance of the bench rests there); 0.05 the same. Back to back: tuned
identical; held-out, twenty templates, the longest wrong run 17 -> 12, six gestures 7 both.

Not judged at rest (:data:`UNJUDGED_AT_REST`): while the performer rests (:func:`resting`),
every template's recent likelihood (refusal) and path misfit stay as they were. A still input
tells nothing new about the path: a pause refused gestures as the transitions' prior moved on
past the rest, and a refused stretch of unrelated motion was accepted again while its still
tail sat on some state. ``bench/follow_quality.py --sections=sized,holds,unrelated`` (tuned;
held-out in brackets; valid after 30% at 0.7-1.4x, unrelated worst / mean), with
:data:`~behaviors.mop.invariance.ALONG` 0.5: before 0.9138, 0.336 / 0.0758 (0.9033, 0.418 /
0.0863); the refusal alone 0.9112, 0.306 / 0.0745 (0.9033, 0.418 / 0.0834); with the misfit
(kept) 0.9112, 0.306 / 0.0734 (0.9033, 0.418 / 0.0814): a mirrored line, six templates, 1.4x
0.12 -> 0, held-out mirrored cartwheel ankle 0.12 -> 0; the cost is a 0.7x spin ankle paused
after a misfit (0.44 -> 0.18); holds unchanged. The threshold model kept to at most the best
template's step while resting changed nothing. Without ``ALONG`` (1): the refusal alone
0.8976, 0.315 / 0.0783 (0.9013, 0.451 / 0.0858); refusal, misfit and the threshold model
0.8978, 0.315 / 0.0779 (0.8999, 0.451 / 0.0849). It buys no margin on gestures paused at a
wrong size: a 1.4x spinkick stopping at 0.41 at size 1.13 is refused as it stops, before the
rest shows (a few samples), and the threshold model keeps its probability through the pause.
Tried after it and not kept: no action driving its performer back behind where it began
(0.02, moving or not): unrelated mean 0.0734 -> 0.0724 (held-out 0.0814 -> 0.0783, a
mirrored line with twenty templates 0.31 -> 0.23), worst unchanged, valid after 30% 0.9112 ->
0.9062 (held-out 0.9033 both; the loss all off track: a 0.7x line's return followed
backwards), but a line's end seen on its way back (:meth:`GestureSpotting._returned`) was no
longer reached; 0.05: 0.0726 (0.0787), 0.9069.

Not begun at a turn (:func:`unbegun`): once every template was refused ``lost_samples`` in a
row, spotting abandons the attempt and anchors the next at that sample, where the input moves.
If the input then goes back the way it came (its way from the anchor against its net motion
over the ``still_samples`` before, cosine below -:data:`REVERSED`), that anchor is a turn inside
one unexplained motion, not an onset: no new action is taken there until the performer rests.
A mirrored line, abandoned near its turn, came back along the line's outward stroke. No true
performance of the bench drove from an abandoned attempt; 186 / 193 (tuned / held-out) of the
unrelated motions' 953 / 975 valid ticks did. ``bench/follow_quality.py
--sections=sized,holds,sequences,unrelated`` (tuned / held-out): unrelated mean 0.0734 ->
0.0688 / 0.0814 -> 0.0771, worst 0.306 -> 0.258 / 0.418 both (a mirrored line, six templates,
0.306 -> 0.122 / 0.257 -> 0.079); valid after 30%, holds and back to back unchanged to the
digit. :data:`REVERSED` 0: 0.0682 / 0.0771; 0.8 as 0.5. Measured and not kept: no take at all
in an abandoned attempt, 0.0568 / 0.0656 (worst 0.235), but a gesture performed right after an
unrelated motion, no rest between, was recognised 0.55 -> 0.20 of the time (six templates, 20
draws; twenty templates 0.39 -> 0.27 of 44), after a 1 s rest 0.75 -> 0.50 (a template left
engaged keeps the anchor); the same until a rest, 0.0628 / 0.0718, 0.55 -> 0.50 and 0.75 ->
0.70. Back the way it came until a rest (kept): 0.55, 0.39, 0.75 unchanged.
"""

from __future__ import annotations

import math

import numpy as np

from behaviors.mop import threshold

#: States before and after the followed state whose joining segments make up the path the
#: input is measured against (the followed state lags or leads a fast performer by a few).
PATH_REACH = (3, 3)


#: An action that drives has carried its performer forward once its progress passed where it
#: began driving by this much (progress units).
FORWARD_FIRST = 0.02
#: Before that, it stops driving once its progress fell this far behind where it began.
BACK_FIRST = 0.02


def backs_first(began: float, peak: float, progress: float) -> bool:
    """Whether a driving action goes back before it went forward: its progress ``progress``
    is :data:`BACK_FIRST` behind ``began`` (where it began driving) while its highest since
    then, ``peak``, never passed ``began`` by :data:`FORWARD_FIRST`."""
    return peak - began < FORWARD_FIRST and progress < began - BACK_FIRST


#: An action that drove while the performer moved carries them forward by this much (progress
#: units) before it may hold them while they stop (:func:`stalls`).
CARRY_FIRST = 0.05


def stalls(began: float, peak: float, moved: bool, still: bool) -> bool:
    """Whether a driving action holds a performer who stopped without having been carried
    forward: the input is ``still``, it ``moved`` while the action drove, and the action's
    highest progress since it began driving, ``peak``, never passed ``began`` by
    :data:`CARRY_FIRST`. Such an action was moved on the spot by the input (a wander hovering
    at a template's start, a chord stopped part way): no evidence specific to it."""
    return still and moved and peak - began < CARRY_FIRST


#: An action resting this far (progress) behind where it began driving does not drive
#: (:func:`rests_behind`; negative: never).
REST_BEHIND = 0.02


def rests_behind(began: float, progress: float, rests: bool) -> bool:
    """Whether the performer rests with the action's progress ``progress`` :data:`REST_BEHIND`
    behind ``began``, where it began driving: back within what did not yet tell the action."""
    return rests and 0 <= REST_BEHIND < began - progress


#: While the performer rests (:func:`resting`), every template's recent likelihood (refusal)
#: and path misfit stay as they were (see the module docstring).
UNJUDGED_AT_REST = True


def unjudged(rests: bool) -> bool:
    """Whether a sample taken while the performer ``rests`` leaves every template's refusal and
    path misfit as they were (:data:`UNJUDGED_AT_REST`)."""
    return rests and UNJUDGED_AT_REST

#: An attempt begun by abandonment takes no new action while the input's way from its anchor
#: points back the way it came, the cosine below minus this (:func:`unbegun`; above 1: never).
REVERSED = 0.5


def unbegun(abandoned: bool, way: np.ndarray, came: np.ndarray) -> bool:
    """Whether the input goes back the way it came to the anchor of an attempt begun by
    ``abandoned`` (every template refused, :meth:`~behaviors.mop.spotting.GestureSpotting._spot`):
    its way from the anchor ``way`` against its net motion ``came`` over the samples before the
    anchor, cosine below -:data:`REVERSED`. Such an anchor is a turn within one unexplained motion,
    not an onset (see the module docstring)."""
    dot = float(way @ came)
    return abandoned and dot < -REVERSED * math.sqrt(float(way @ way) * float(came @ came))

#: Tempo (:func:`slow_take`): samples over which a new action's tempo is read...
TEMPO_SAMPLES = 10
#: ... and the least tempo (template states per sample) at which a moving input may take it
#: (0: no limit).
LEAST_TEMPO = 0.3


def slow_take(advance: float, moved: float, onset: float) -> bool:
    """Whether a new action is taken too slowly to be performed: over the last
    :data:`TEMPO_SAMPLES` samples its followed state moved ``advance`` states (either way), fewer
    than :data:`LEAST_TEMPO` per sample, while the input moved ``moved`` (RMS per column, in the
    template's spread at its estimated size) by at least ``onset``. A performer goes at 0.5-2x the
    recorded tempo; a template whose followed state crawls while the input sweeps on is being
    stretched over a path that is not its own (see the module docstring)."""
    return LEAST_TEMPO > 0 and moved >= onset and abs(advance) < LEAST_TEMPO * TEMPO_SAMPLES


#: Crawling (:func:`crawls`): samples in a row an action may be followed at a crawl while it
#: drives (0: no limit).
CRAWL_SAMPLES = 6


def crawls(run: int) -> bool:
    """Whether an action has been followed at a crawl (:func:`slow_take` true for it) for
    ``run`` samples in a row, :data:`CRAWL_SAMPLES` or more: taken or not, it does not drive (a
    template stretched over a path not its own, see the module docstring)."""
    return 0 < CRAWL_SAMPLES <= run


#: The performer rests when the mean of their last samples moved less than this many still
#: radii (every column) from the mean of the samples before (:func:`resting`).
RESTING_RADII = 2.0


def resting(recent: list[np.ndarray], radius: np.ndarray) -> bool:
    """Whether the performer rests: the mean of the later half of the ``recent`` samples (at
    least 4, oldest first) is within :data:`RESTING_RADII` ``radius`` (per column, raw units) of
    the earlier half's. Net motion, not the samples' spread, so the tracking jitter (about one
    still radius with many templates loaded) does not read as moving."""
    n = len(recent) // 2
    if n < 2:
        return False
    d = np.mean(recent[-n:], axis=0) - np.mean(recent[:n], axis=0)
    return bool(np.all(np.abs(d) <= RESTING_RADII * radius))



def path_lengths(bank) -> np.ndarray:
    """Per state of ``bank``, the length of its template's path from the first state to it
    (segments between states, RMS per column in the template's own spread)."""
    out = []
    for k in range(len(bank.names)):
        z = bank.template(k)
        seg = np.sqrt(np.sum(np.diff(z, axis=0) ** 2, axis=1) / z.shape[1])
        out.append(np.concatenate([[0.0], np.cumsum(seg)]))
    return np.concatenate(out)


class Validity:
    """Mixin of :class:`~behaviors.mop.follower.ActionFollower`: refusal, path misfit and
    coverage (see the module docstring)."""

    def _setup_validity(self) -> None:
        """Constants and per-template state of the shape rules (after the bank is built)."""
        b = self.bank
        self._arc = path_lengths(b)
        # each state's segment to the next (none from a template's last state), 1 / its length^2
        seg = np.diff(b.means, axis=0, append=b.means[-1:])
        seg[b.starts + b.lengths - 1] = 0.0
        self._seg = seg
        self._seg_inv = 1.0 / np.maximum((seg * seg).sum(axis=1), 1e-12)
        self._reach = np.arange(-PATH_REACH[0], PATH_REACH[1] + 1)[None, :]
        ends = b.starts + b.lengths - 1
        self._arc_need = self.coverage * self._arc[ends]
        self._misfit_decay = 1.0 - 1.0 / self.shape_memory
        self._shape2 = self.shape_distance ** 2
        self._shape_accept2 = self.shape_accept ** 2
        k = len(self.names)
        self._misfit, self._misfit_w = np.zeros((k, 3)), np.zeros(k)
        self._misshaped, self._covered = np.zeros(k, dtype=bool), np.zeros(k, dtype=bool)
        self._threshold_alpha = np.zeros(len(b.means))
        self._threshold_scratch = np.zeros(len(b.means))
        self._threshold_means = np.ascontiguousarray(b.means, dtype=float)
        self._threshold_lengths = np.ascontiguousarray(b.lengths, dtype=np.int64)
        self._threshold_const = -b.dim * np.log(self.sigma) - 0.5 * b.dim * np.log(2.0 * np.pi)

    def _forget_shape(self, which: np.ndarray | slice = slice(None)) -> None:
        """Forget the misfit and coverage of the templates ``which`` (all by default)."""
        self._misfit[which] = 0.0
        self._misfit_w[which] = 0.0
        self._misshaped[which] = False
        self._covered[which] = False

    def _refuse(self, dist2: np.ndarray) -> None:
        """Refusal with hysteresis from the recent squared distances (sigma units), in place on
        ``_refused``."""
        self._refused |= dist2 > self._null2
        self._refused &= ~(dist2 < self._accept2)

    def _mapped(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """x as the forward algorithm sees it, split as ``u / size + c`` (K, d) each: with
        "scale" invariance u is x relative to the anchor in each template's spread, c its first
        state; otherwise u is the mapped sample and c zero (size 1)."""
        b = self.bank
        if self.invariance == "none":
            return (x - b.center) / b.scale, np.zeros_like(b.scale)
        u = (x - self._anchor)[None, :] / b.scale
        if self.invariance == "scale":
            return u, self._first_z
        return u + self._first_z, np.zeros_like(b.scale)

    def _nearest_on_path(self, z: np.ndarray, g: np.ndarray) -> np.ndarray:
        """The point (K, d) of each template's path nearest to z (K, d) among the segments
        joining the states within :data:`PATH_REACH` of its followed state ``g`` (bank index)."""
        b = self.bank
        before, after = PATH_REACH
        c = np.floor(g).astype(np.intp)
        # segments start at these states (clipped: a repeated segment changes no minimum)
        idx = np.clip(c[:, None] + self._reach, b.starts[:, None],
                      (b.starts + b.lengths - 1)[:, None])
        a, ab = b.means[idx], self._seg[idx]                         # (K, m, d)
        az = z[:, None, :] - a
        t = np.clip((az * ab).sum(axis=2) * self._seg_inv[idx], 0.0, 1.0)
        off = az - t[..., None] * ab
        j = np.argmin((off * off).sum(axis=2), axis=1)
        rows = np.arange(len(j))
        return a[rows, j] + t[rows, j, None] * ab[rows, j]

    def _judge_shape(self, x: np.ndarray, g: np.ndarray, new: np.ndarray, rests: bool) -> None:
        """After a sample: each template's path misfit (forgotten over ``shape_memory``
        samples, refused beyond ``shape_distance``, accepted again below ``shape_accept``) and
        whether its followed progress has covered ``coverage`` of its path since it engaged.
        ``g``: followed states (bank index); ``new``: templates whose performance began anew.
        The misfit of the remembered samples is read at the current size estimate (the
        residual ``u / size - v`` is kept as sums of ``|u|^2``, ``u.v`` and ``|v|^2``), so a size
        that converges late does not leave the early samples counted as strays."""
        if np.count_nonzero(new):
            self._forget_shape(new)
        u, c = self._mapped(x)
        size = self._size if self.invariance == "scale" else np.ones(len(self.names))
        v = self._nearest_on_path(u / size[:, None] + c, g) - c
        decay = self._misfit_decay
        sums, w = self._misfit, self._misfit_w
        upd = w <= 0 if unjudged(rests) else slice(None)
        sums[upd] *= decay
        sums[upd, 0] += (u * u).sum(axis=1)[upd]
        sums[upd, 1] += (u * v).sum(axis=1)[upd]
        sums[upd, 2] += (v * v).sum(axis=1)[upd]
        w[upd] = w[upd] * decay + 1.0
        m2 = (sums[:, 0] / size ** 2 - 2.0 * sums[:, 1] / size + sums[:, 2]) / w
        m2 *= 1.0 / (self.sigma ** 2 * self.dim)
        self._misfit2 = m2
        self._misshaped |= m2 > self._shape2
        self._misshaped &= ~(m2 < self._shape_accept2)
        gi = np.floor(g).astype(np.intp)
        nxt = np.minimum(gi + 1, self.bank.starts + self.bank.lengths - 1)
        covered = self._arc[gi] + (g - gi) * (self._arc[nxt] - self._arc[gi])
        self._covered |= (covered >= self._arc_need) & self._engaged

    def _threshold_evidence(self, x: np.ndarray, anchor: np.ndarray, lead_ll: float) -> float:
        """Step the threshold model (:mod:`behaviors.mop.threshold`) with sample ``x`` seen from
        ``anchor`` and return its evidence, forgotten as the templates' (``lead_ll``: this
        sample's raw log-likelihood under the template of most evidence). Started afresh with
        the evidence."""
        b = self.bank
        if self.invariance == "none":
            z = (x - b.center) / b.scale
            jac = -self._jacobian
        else:
            z = (x - anchor)[None, :] / b.scale
            jac = -self._jacobian
            if self.invariance == "scale":
                z /= self._size[:, None]
                jac = jac - self.dim * np.log(self._size)
            z += self._first_z
        step = threshold.threshold_model_step(
            np.ascontiguousarray(z), self._threshold_means, self._threshold_lengths, self.sigma,
            self._threshold_const, np.ascontiguousarray(jac, dtype=float), self._threshold_alpha,
            self._threshold_scratch, self._threshold_x is None, threshold.STAY)
        step = threshold.gated(step - self.threshold, lead_ll, x, self._threshold_x,
                               self._still_radius)
        self._threshold_x = x
        self._threshold_ev = self._threshold_ev * self._decay + step
        return self._threshold_ev

    def _slow_take(self, k: int, g: np.ndarray, x: np.ndarray) -> bool:
        """Template ``k`` (followed states ``g``, bank index) is taken too slowly by sample ``x``
        (:func:`slow_take`) against the oldest of the last :data:`TEMPO_SAMPLES` samples."""
        if LEAST_TEMPO <= 0 or len(self._tempo_past) < TEMPO_SAMPLES:
            return False
        then, x0 = self._tempo_past[0]
        r = (x - x0) / (self.bank.scale[k] * self._size[k])
        moved = math.sqrt(float(np.mean(r * r)))
        advance = float(g[k] - self.bank.starts[k] - then[k])
        return slow_take(advance, moved, self.onset * self.sigma)

    def _remember_tempo(self, states: np.ndarray, x: np.ndarray) -> None:
        """Keep the followed ``states`` (K,) and sample ``x`` of the last :data:`TEMPO_SAMPLES`."""
        self._tempo_past.append((states, x))
        if len(self._tempo_past) > TEMPO_SAMPLES:
            del self._tempo_past[0]

    def _shaped(self, k: int) -> bool:
        """Template ``k`` may drive as far as its path is concerned."""
        return bool(self._covered[k] and not self._misshaped[k])
