"""Refusal against each template's own spread and path: the recent likelihood, the path misfit
and coverage (what was tried beside them too). Part of the rules of :mod:`behaviors.mop.validity`
(when a followed template may drive its character); :class:`Refusal` is a mixin of
:class:`~behaviors.mop.follower.ActionFollower`.

Refusal (null rejection), per template against its own spread (:mod:`behaviors.mop.hmm`):
per-step log-likelihoods forgotten with ``null_memory`` samples, read as an RMS distance in
``sigma`` units. Beyond ``null_distance`` the template is refused; it is accepted again below
``accept_distance`` (hysteresis, not a permanent latch: with the bird alone in
``tests/mop/test_live.py`` the latch and the hysteresis took the same 3 of 17 other gestures
at 60% with one spread per template, and the hysteresis takes 0 with one per column).
Tighter limits did not separate unrelated motion from true performances: null 1.4 / accept
1.05 cut true validity after 30% from 0.90 to 0.75 while unrelated motion stayed 0.55-0.62
valid; 1.1 / 0.85: 0.65 and 0.51.
Measured and not kept: refused only once past its onset state or engaged (before it, the template's
first states are a small slow blob): on the tuned joints, seeds 201-210
(``bench/follow_widened.py``), mirrored paths among twenty valid over 0.1 of the time 22 -> 19 of
540 (mean 0.0146 -> 0.0134, worst 0.338 both), gestures back to back among twenty unchanged;
``bench/follow_quality.py`` puck figures identical, but the ``follow`` command's defaults (features
as recorded) recognised fewer gestures back to back (never recognised among the six 0.531 -> 0.563,
median recognition among twenty 0.520 -> 0.600).

Two rules on the template's *path* (its states joined by segments), each measured against the
template's own spread, whatever the other templates:

- Coverage: a template drives only once its followed progress has covered ``coverage`` of its
  path's length since it engaged (path length in its spread, RMS per column; kept until the
  performance begins anew, but not while the followed state runs far ahead of the input; less
  where the template set tells its start from every other's, while the input keeps to its path:
  :mod:`behaviors.mop.coverage`). The start of every template is a small, slow blob that any
  small wiggle matches at a small size: an aimless wander drove the circle alone 75-86% of the
  time at 15-23% of its progress. Recognition comes a little later (at 30% of gestures at
  0.7-1.4x: 0.73 -> 0.68 of them).
- Path misfit: the distance of the input, mapped as the forward algorithm sees it, from the
  path's segments within :data:`~behaviors.mop.validity.PATH_REACH` states of the followed
  state, as an RMS over the last ``shape_memory`` samples in ``sigma`` units; refused beyond
  ``shape_distance``, accepted again below ``shape_accept``. The predictive likelihood carries
  the transitions' uncertainty (about 1 sigma on exact copies); the distance to the joined
  states does not (a time-warped copy sits at 0.12 sigma median), so a diagonal line along a
  circle's chord (0.3 of its radius off at the middle) shows. The remembered samples are read at
  the current size estimate: read at the size each had when it came, a 0.7x circle, whose size
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

The coverage rule's studies (gestures back to back, why recognition lags the observer's
reach, coverage lowered where the path bends, arc the input went along):
:mod:`behaviors.mop.coverage`.
An action the input goes on past while its progress lags (the diagonal the figure eight's first
stroke drives) is not shown valid: :mod:`behaviors.mop.overrun`
(:meth:`~behaviors.mop.follower_validity.Validity._overruns`).

Misfit limits again, with the rules of :mod:`behaviors.mop.validity` and
:mod:`behaviors.mop.invariance` in place (``bench/follow_quality.py --sections=sized,unrelated``,
tuned / held-out: unrelated worst / mean, valid after 30% of gestures at 0.7-1.4x): 1.4 / 1.2
0.258 / 0.0650, 0.418 / 0.0754, 0.9112 / 0.9033; 1.2 / 1.0 0.228 / 0.0547, 0.418 /
0.0706, 0.9047 / 0.9008: with the circle alone, a diagonal (its chord at 0.8-0.95x) 0.258 ->
0.095, a spiral 0.145 -> 0.070, a wander 0.112 -> 0.097 (held-out diagonal 0.132 -> 0.089); on
track after 30% 0.8927 -> 0.8863 (0.8769 -> 0.8744); holds unchanged. 1.3 / 1.0: 0.231 /
0.0578, 0.9066 / 0.9018 (the diagonal 0.164); 1.2 / 0.9: 0.0543, 0.9009 / 0.9001;
``shape_memory`` 10: 0.0534, 0.9039 / 0.8998. Not kept either: the recent likelihood's limits
1.5 / 1.1 (0.0559, 0.8895 / 0.8905), and accepting a refused or misshaped template again only
once its memory holds 4 samples' weight (after :data:`~behaviors.mop.invariance.REJUDGE` it
holds one, and the circle was accepted again at once on the diagonal): 0.233 / 0.0805, 0.9058 /
0.8879, since a refused best hands the performer to the next template (mirrored gestures with
twenty loaded 0.12 -> 0.22). Features as recorded (``invariance="none"``, the ``follow``
command's default): there a gesture at another size is off its path by its size, and 1.2 / 1.0
cost valid after 30% at 0.7-1.4x 0.644 -> 0.606 (unrelated mean 0.144 -> 0.120). With shared
starts on (``share_radius`` 3, :mod:`behaviors.mop.spotting`) 1.2 / 1.0 took valid after 30% of
gestures at 0.7-1.4x below its 0.90 target (tuned / held-out 0.8941 / 0.8989; 1.3 / 1.0 0.8959 /
0.9000; 1.3 / 1.1 0.8979 / 0.9008; 1.4 / 1.0 0.8995 / 0.9007; 1.4 / 1.2 0.9005 / 0.9014,
unrelated worst / mean 0.2577 / 0.0588, held-out 0.4141 / 0.0657, against 0.2284 / 0.0485 and
0.4141 / 0.0610 at 1.2 / 1.0): the defaults stayed 1.4 / 1.2 until a gesture's size was
judged with more margin.

With the size taken at the input's reversal (:data:`~behaviors.mop.invariance.REVERSAL_FIT`)
that margin came, so with "scale" invariance the limits are now 1.2 / 1.0
(:data:`SCALED_SHAPE_LIMITS`; :func:`shape_limits`), 1.4 / 1.2 otherwise (features as recorded:
a gesture at another size is off its path by its size there). ``bench/follow_quality.py
--sections=sized,sequences,unrelated`` (tuned / held-out): valid after 30% of gestures at
0.7-1.4x 0.9184 / 0.9056 -> 0.9131 / 0.9038; unrelated worst 0.258 / 0.414 -> 0.228 / 0.414,
mean 0.0576 / 0.0607 -> 0.0481 / 0.0556: the diagonal with the circle alone 0.258 -> 0.095
(1.4x: 0.289 -> 0.039; never judged afresh there, its chord at size 0.87-1.0 stayed within
1.4 sigma for 16 samples), a spiral with it 0.145 -> 0.070, a wander 0.052 -> 0.036; gestures
back to back among the six, wrong action valid at most 2 samples both. 1.3 / 1.1: 0.9175, worst
0.231, mean 0.0519 (tuned). What is left: the mirrored square among twenty templates (the roll
ankle's start), 0.228, and the spiral among six, 0.181, whose second turn the circle follows at
misfit 0.56-0.74 (below).

Measured since and not kept (``--sections=sized,holds,sequences,unrelated``, tuned / held-out;
before: valid after 30% 0.9005 / 0.9014, unrelated worst 0.258 / 0.414, mean 0.0588 / 0.0657):
``scale_prior`` 2 with misfit 1.2 / 1.0, 0.9021 / 0.9052, 0.231 / 0.410, 0.0471 / 0.0594, but
the held-out told worst 0.239 -> 0.253, and the prior alone lets the bird's wave take zigzags at
0.8x (``tests/mop/test_live.py``: valid at 0.52-0.92 of the wave for 27 samples, 2 of 17 other
gestures at 60%, 0 before); ``turn_limit`` 1.6: mean 0.0540, diagonal unchanged, 0.9004 /
0.8928; :data:`~behaviors.mop.tempo.CRAWL_SAMPLES` 5: 0.0578 / 0.0640, 0.9003 / 0.8993;
:data:`~behaviors.mop.invariance.REJUDGE` 1.25: 0.0573 / 0.0655, 0.9023 / 0.9072, but on
``tests/mop/test_refusal.py``'s own draws a mirrored line's rest 28 -> 60 valid samples and a
wander 101 -> 153 (1.3: mean 0.0639); ``PATH_REACH`` (2, 2): 0.0577 / 0.0657, 0.8987 / 0.9000;
``shape_memory`` 12: 0.0566 / 0.0655, 0.8995 / 0.9012. The input's bulge (its farthest sample
from the chord anchor -> now) against the template's near the followed state: a diagonal on the
circle's path differs by at most 0.85 sigma within ``PATH_REACH``, true performances at 0.7x by
up to 3.5 sigma (their size not yet known). What is left is told apart only by more than the
path within its spread: the diagonal with the circle alone (at 1x: 6 samples to misfit 1.4, then
the size shrinking along the chord, 1.0 -> 0.83, judges it afresh and it drives 12 more at
misfit 0.8-1.3); a mirrored square is the first half of the roll ankle (left, up, right; within
1 cm at 15 cm) at misfit 0.3-0.8. A spiral's second turn, begun anew at its start, is a closed
loop the circle's way round, 15 cm high against its 16 (within 8 mm of the circle's start at
half of it): the circle follows it at misfit 0.6-0.7 as a performer expects. The bench counts
those ticks against it (its ``told`` figure reads the motion from the spiral's first start);
left so: read from the loop's own start, the loop strays 8-11 mm from the circle from half of it
on, beyond the 4 mm within which the bench calls a motion a performance of an action
(``PERFORMS_M``), and the circle drives from 0.52 of it: a lopsided circle, followed within its
spread, not one the bench's observer would name. Aligned in time (``bench.motions.aligned_gap``)
the loop lies 9.1 mm RMS from the circle at 0.95x, a circle redrawn bent by 10% of its extent
(``bench/follow_shapes.py``) 9.3 mm (median of 20): no shape test refuses one and follows the other.
What tells them apart is where the loop begins: at full pace inside the spiral, where no gesture
begins (:mod:`behaviors.mop.under_way`).

Mirrored paths among twenty templates (``bench/follow_widened.py``, tuned joints, seeds 201-210),
traced: a template's stretch followed forward and back over itself within its own spread (the
zigzag on a mirrored dance wrist at 0.7x, 0.24 -> 0.34 -> 0.24; the walk ankle on a mirrored spin
ankle at 1.4x, 0.13 -> 0.27 -> 0.09; recent likelihood 0.7-1.4 sigma, misfit 0.2-0.6, probability
1). On the worst the zigzag, taken at its corner, was strained (recent likelihood 1.31 -> 1.69)
when the input turned there: the reversal sized it 1.06 -> 1.36
(:data:`~behaviors.mop.invariance.REVERSAL_FIT`), which judged it afresh
(:data:`~behaviors.mop.invariance.REJUDGE`) and it drove 20 samples more. So the action driving
takes no size at a reversal while strained (:meth:`Refusal._recent_dist2`, recent likelihood
beyond ``accept_distance``; :meth:`~behaviors.mop.invariance.PerformanceFrame._reversal_sizes`
and the group kernel): at the reversals met by the action driving (seeds 201-202) true performances
at 0.7-1.4x were strained at 69 of 857 (recent likelihood 0.91 median, 1.19 at 90%), mirrored paths
at 4 of 6. Widened: worst 0.338 -> 0.239, mean 0.0146 -> 0.0145, over 0.1 22 of 540 both, sequences
identical; ``bench/follow_quality.py`` (every non-held-out figure): valid after 30% at 0.7-1.4x
0.9147 -> 0.9157, 0.6 / 1.5x 0.7581 -> 0.7585, progress RMSE median 0.01897 -> 0.01905, 241 others
identical. Not kept: refusal limits 1.5 / 1.2 with "scale" (widened worst 0.296, but valid after
30% 0.9122 and the spiral with the circle alone 0.004 -> 0.174, refused sooner and taken again),
1.4 / 1.1 (0.296; wrong runs over 2 samples 14 -> 17), 1.6 / 1.2 (0.310, mean 0.0148); an action
judged afresh while it drives taken anew: the zigzag's last samples fit at 1.36, and 2755 of 8485
true valid ticks follow such a judgement (62 of 798 mirrored); nor do the misfit's sums re-read at
the new size tell them. Left: a stretch followed back over itself unstrained (the walk ankle),
as a performer going back along a gesture or a line's return followed backwards at a wrong size
is (going back: :mod:`behaviors.mop.validity`).
Measured and not kept (widened, then ``bench/follow_quality.py --sections=sized,holds,sequences,
unrelated,after,pauses``, tuned): no *new* action taken while strained (the action driving drives
on): widened worst 0.239 -> 0.296: the zigzag on seed 208's mirrored dance wrist at 0.7x, held at
its corner (strained 1.3-1.7 sigma), took the reversal's size there (1.06 -> 1.36) once it was not
driving, was judged afresh (recent likelihood 0.0, misfit 0.06) and drove 21 samples instead of
17. With no reversal size for *any* strained template as well: widened worst 0.239 -> 0.228 (the
walk ankle's), mean 0.0145 -> 0.0116, over 0.1 22 -> 18 of 540, sequences identical; after a
gesture mean 0.0730 -> 0.0686 (worst 0.198 the same), unrelated mean 0.0154 -> 0.0133 (worst 0.068
the same); but valid after 30% at 0.7-1.4x 0.9157 -> 0.9019, at 0.6 / 1.5x 0.7585 -> 0.6910, twenty
templates back to back never recognised 0 -> 0.031 (median 0.298 -> 0.316): true takes are
strained while their size is still unknown. Strained beyond 1.5 sigma instead of 1.2: widened
identical to the digit; no reversal size for any strained template alone: worst 0.239, mean 0.0149,
over 0.1 25. Again on held-out seeds 103 / 104 / 106 (``--sections=unrelated,sized``; tuned valid
after 30% at 0.7-1.4x 0.9121, held-out 0.9055 / 0.8871 / 0.8744): no new take while strained,
0.9023, 0.8834 / 0.8581; only a re-take of the action that drove last, 0.9069, 0.8740 on 104,
0.8622 on 106; both end 104's worst, a wander the zigzag re-takes strained after a reversal's
size (0.111 -> 0.074; :mod:`behaviors.mop.overrun`), at that cost to true takes.
Measured and not kept either: the action driving stops once strained for 6 samples in a row
(``bench/follow_quality.py --sections=sized,holds``, tuned, and the widened cases): beyond 1.2
sigma, widened worst 0.239 -> 0.228, mean 0.0134, but valid after 30% at 0.7-1.4x 0.9157 ->
0.8835 and twenty back to back runs over 2 samples 14 -> 16 (true performances are strained that
long while their size converges); beyond 1.44 sigma 0.228 / 0.0142, sequences identical, but
0.9152; beyond 1.56 sigma 0.228 / 0.01445 (over 0.1 22 unchanged), sized, holds and sequences
identical: it ends only the zigzag on seed 208 (1.57-1.69 sigma from its second valid sample),
the worst left being the walk ankle's unstrained return (0.228) and the held-out worst of that
kind, so it would also need the compiled group's counterpart (a strained flag per template and
a run per member in :func:`behaviors.mop.members.conclude`) for a gain of 0.011 on one tuning
case.

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
"""

from __future__ import annotations

import numpy as np

from behaviors.mop import coverage
from behaviors.mop.misfit_size import reread
from behaviors.mop.path_kernel import nearest_on_paths
from behaviors.mop.spotting import SHARE_SIZES
from behaviors.mop.straight_start import straight_start_arc
from behaviors.mop.threshold_lead import ThresholdLead
from behaviors.mop.validity import unjudged


def path_lengths(bank) -> np.ndarray:
    """Per state of ``bank``, the length of its template's path from the first state to it
    (segments between states, RMS per column in the template's own spread)."""
    out = []
    for k in range(len(bank.names)):
        z = bank.template(k)
        seg = np.sqrt(np.sum(np.diff(z, axis=0) ** 2, axis=1) / z.shape[1])
        out.append(np.concatenate([[0.0], np.cumsum(seg)]))
    return np.concatenate(out)


#: The path misfit's limits (``shape_distance``, ``shape_accept``; sigma) by default with "scale"
#: invariance, where the size is estimated; 1.4 / 1.2 otherwise (see the module docstring).
SCALED_SHAPE_LIMITS = (1.2, 1.0)
#: ... and without it.
SHAPE_LIMITS = (1.4, 1.2)


def shape_limits(invariance: str, distance: float | None,
                 accept: float | None) -> tuple[float, float]:
    """The path misfit's refusal and acceptance limits (sigma): those given, the defaults for
    ``invariance`` (:data:`SCALED_SHAPE_LIMITS` with "scale", else :data:`SHAPE_LIMITS`) where
    None."""
    d, a = SCALED_SHAPE_LIMITS if invariance == "scale" else SHAPE_LIMITS
    d = d if distance is None else float(distance)
    return d, min(a, d) if accept is None else float(accept)


class Refusal(ThresholdLead):
    """Mixin of :class:`~behaviors.mop.follower.ActionFollower`: refusal, path misfit and
    coverage (see the module docstring)."""

    def _setup_refusal(self) -> None:
        """Constants and per-template state of the shape rules (after the bank is built)."""
        b = self.bank
        self._arc = path_lengths(b)
        self._means_t = np.ascontiguousarray(b.means.T)   # (D, S): nearest_on_paths' layout
        ends = b.starts + b.lengths - 1
        self._arc_need = self.coverage * self._arc[ends]
        self._arc_full = self._arc_need.copy()
        self._arc_col = np.ascontiguousarray(self._arc[:, None])   # (coverage.arc_ahead)
        self._read_ahead = np.zeros(len(self.names), dtype=bool)
        if self.invariance == "scale":
            # ... or less, where the template set tells the template's start from every other's
            # (coverage.told_apart_arc: the sizes shared starts try, the misfit's accept limit)
            lo, hi = self.scale_range
            sizes = np.geomspace(lo / hi, hi / lo, SHARE_SIZES)
            rel = np.ascontiguousarray(self._rel * self._units)
            told = coverage.told_apart_arc(rel, b.starts, b.lengths, self._arc, b.scale, sizes,
                                           self.shape_accept * self.sigma)
            # ... or where the ideal observer tells it apart, though never on the template's
            # own straight start (coverage.OBSERVER, straight_start.straight_start_arc)
            seen = coverage.told_apart_arc(rel, b.starts, b.lengths, self._arc,
                                           np.ones_like(b.scale), sizes, coverage.OBSERVER)
            straight = straight_start_arc(rel, b.starts, b.lengths, self._arc, coverage.OBSERVER)
            # (a need set by the own straight start is read at the best timing offset ahead:
            # coverage.arc_ahead)
            self._read_ahead = (straight >= seen) & (straight < told) & (straight < self._arc_need)
            np.minimum(self._arc_need, np.minimum(told, np.maximum(seen, straight)),
                       out=self._arc_need)
        # covered sooner, held to its path until it has gone on past ``coverage`` by
        # coverage.LATE_UNTIL times the arc it was let off (-inf: asked all of it, never held)
        let_off = self._arc_full - self._arc_need
        self._late_until = np.where(let_off > 0.0, self._arc_full + coverage.LATE_UNTIL * let_off,
                                    -np.inf)
        self._misfit_decay = 1.0 - 1.0 / self.shape_memory
        self._shape2 = self.shape_distance ** 2
        self._shape_accept2 = self.shape_accept ** 2
        k = len(self.names)
        # (|u|^2, u.v, |v|^2 and the size last read at: misfit_size.reread)
        self._misfit, self._misfit_w = np.zeros((k, 4)), np.zeros(k)
        self._misshaped, self._covered = np.zeros(k, dtype=bool), np.zeros(k, dtype=bool)
        self._reached = np.zeros(k)   # the input's farthest reach (coverage.RUN_AHEAD)
        self._setup_threshold()

    def _forget_shape(self, which: np.ndarray | slice = slice(None)) -> None:
        """Forget the misfit and coverage of the templates ``which`` (all by default)."""
        self._misfit[which] = 0.0
        self._misfit_w[which] = 0.0
        self._misshaped[which] = False
        self._covered[which] = False
        self._reached[which] = 0.0

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
        joining the states within :data:`~behaviors.mop.validity.PATH_REACH` of its followed
        state ``g`` (bank index): :func:`behaviors.mop.path_kernel.nearest_on_paths`."""
        b = self.bank
        out = np.empty_like(z)
        nearest_on_paths(self._means_t, b.starts, b.lengths, z, g, out)
        return out

    def _judge_shape(self, x: np.ndarray, g: np.ndarray, new: np.ndarray, rests: bool) -> None:
        """After a sample: each template's path misfit (forgotten over ``shape_memory``
        samples, refused beyond ``shape_distance``, accepted again below ``shape_accept``) and
        whether its followed progress has covered ``coverage`` of its path since it engaged.
        ``g``: followed states (bank index); ``new``: templates whose performance began anew.
        The misfit of the remembered samples is read at the current size estimate (the
        residual ``u / size - v`` is kept as sums of ``|u|^2``, ``u.v`` and ``|v|^2``), so a size
        that converges late does not leave the early samples counted as strays; one that moves
        at once reads them no worse than before it moved (:mod:`behaviors.mop.misfit_size`)."""
        if np.count_nonzero(new):
            self._forget_shape(new)
        u, c = self._mapped(x)
        size = self._size if self.invariance == "scale" else np.ones(len(self.names))
        v = self._nearest_on_path(u / size[:, None] + c, g) - c
        decay = self._misfit_decay
        sums, w = self._misfit, self._misfit_w
        if self.invariance == "scale":   # a size moved at once (misfit_size)
            reread(sums, 0, len(self.names), self._size)
        upd = w <= 0 if unjudged(rests) else slice(None)
        sums[upd, :3] *= decay
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
        last = self.bank.starts + self.bank.lengths - 1
        nxt = np.minimum(gi + 1, last)
        covered = self._arc[gi] + (g - gi) * (self._arc[nxt] - self._arc[gi])
        met = covered >= self._arc_need
        # ... read at the best timing offset ahead where the need is the own straight start
        for k in np.flatnonzero(self._read_ahead & ~met & self._engaged):
            met[k] = coverage.arc_ahead(self._shape_lag, k, g[k], self.bank.starts[k],
                                        last[k], self._arc_col, 0, 0) >= self._arc_need[k]
        self._covered |= met & self._engaged
        # ... and not while it runs far ahead of where the input went (coverage.RUN_AHEAD)
        reach = self._displacement(np.mean(self._recent_x[-3:] + [x], axis=0))
        np.maximum(self._reached, reach, out=self._reached)
        self._covered &= covered <= coverage.RUN_AHEAD * self._reached
        # ... and, covered sooner, not while it is off its path by more than coverage.EARLY_FIT
        # short of ``coverage`` of its path, nor by more than LATE_FIT past it until it has gone
        # on by LATE_UNTIL times the arc it was let off
        fit2 = np.where(covered < self._arc_full, coverage.EARLY_FIT, coverage.LATE_FIT) ** 2
        self._covered &= (covered >= self._late_until) | (m2 <= fit2)

    def _recent_dist2(self, k: int) -> float:
        """Template ``k``'s recent likelihood as a squared distance in its own spread (the
        group kernel's expression, bit for bit); strained beyond ``accept_distance``."""
        return (self._log_constant - self._recent[k] / self._recent_weight[k]) * (2.0 / self._zdim)

    def _shaped(self, k: int) -> bool:
        """Template ``k`` may drive as far as its path is concerned."""
        return bool(self._covered[k] and not self._misshaped[k])
