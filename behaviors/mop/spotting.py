"""Gesture spotting in a continuous stream: where one gesture ends and the next begins.

Once ``best`` reached ``end`` progress while valid, the gesture has ended: it drives at most
:data:`END_GRACE` samples more (the character then holds its last pose for the puppet's
``hold_s``), and none once the input moved on from that point; the next gesture starts when
the input rests or moves on from where it ended, or stops matching; it is anchored where the
last one ended, and forward, evidence and sizes start afresh. A valid action resting at 90% or
more has ended too.
When every template has been refused for ``lost_samples`` samples the attempt is abandoned and
a new one starts at the current sample. While nothing is engaged and the input is still
(``still_samples`` within a quarter of the onset), the anchor follows it.

That reset makes a template's refusal depend on the others (it restarts them all once every
one is refused): on a spiral the circle alone restarts at its 30th sample; among the six the
wave, zigzag and eight keep the attempt open to the 33rd and the circle then follows the second
loop unrefused (23 of 76 ticks differ; 861 of 3457 over the unrelated motions, 135 without the
reset). A per-template form needs an anchor per template. The reset left out (tuned / held-out):
sized, holds, pauses, back to back unchanged, after a gesture 0.0718 -> 0.0684, unrelated mean
0.0131 -> 0.0137 / 0.0151 -> 0.0160 (spiral, circle alone 0.004 -> 0.030), a gesture right
after an unrelated motion recognised among six 0.37 -> 0.25 (60 draws): kept.

An unrelated stroke straight after a gesture (``bench/follow_after.py``) is refused as it is from
rest: nothing of the gesture just ended carries over into it. Its 72 tuned performances replayed
with the gesture replaced by 0.5 s still at its last point (the same stroke samples, counted as the
bench counts them, from the stroke's third tick): worst motion 0.198 -> 0.202, mean 0.0730 ->
0.0770. The worst, the diagonal after the square, wave, circle and zigzag (0.16-0.20 of its ticks;
0.11 after the figure eight), is the figure eight taken on it as from rest: all 158 valid ticks
of the 18 diagonals are its own, taken at 0.21-0.25 of itself and driving to 0.24-0.28 (5-15
samples; after the square it becomes ``best`` 4-11 samples into the stroke, at 0.11-0.21), until
the drift rule (:mod:`~behaviors.mop.shape_lead`) stops it; up to 0.22 of it the diagonal *is* the
figure eight's first stroke, where true figure eights are taken (0.22-0.24). The
ended square drives none of the stroke after its first sample. Measured and not kept
(``bench/follow_quality.py --sections=after,unrelated,sized,sequences``, tuned): a new action
not taken while its path up to the followed state bends off its chord (start to there, at its
size) by more than 2 mm and the input's since the anchor by less than half that: after a
gesture worst 0.198 -> 0.189 (the diagonal 0.151 -> 0.140: the eight is taken before its own
path bends, where the diagonal is its start); not taken either before its path bends so (a
template that never does exempt): worst 0.155 (diagonal 0.118, mean 0.073 -> 0.044), but valid
after 30% of gestures at 0.7-1.4x 0.915 -> 0.898, the zigzag back to back 0.257 -> 0.296, the
line 0.455 -> 0.575: every gesture waits for its first bend, and a straight stroke shows one
too (the tracking jitter alone puts 15 samples of a 3 cm stroke 1.2-2.3 mm off its chord,
10th-90th percentile).

Where the next gesture is anchored: where the last one's end was reached or, when the input was
still coming closer to the ended template's last point (at its estimated size, from the anchor)
as the new attempt began, that last point. The follower reaches ``end`` (97% of the progress)
before the performer on a fast end (a crawl ankle moves 2.6-2.8 cm over its last 3%), and the
next gesture, anchored centimetres short of where it began, was never recognised; its attempt
stayed open (a template at the size range's limit, off its path but not refused, kept it from
being abandoned) and the gestures after it began inside it. ``bench/follow_quality.py
--sections=sequences`` (tuned / held-out): twenty templates back to back never recognised
0.031 / 0.156 -> 0 / 0, within 20% 0.344 / 0.281 -> 0.344 / 0.344, median recognition 0.279 /
0.302 -> 0.247 / 0.225, the ended action's longest run into the next 3 / 12 -> 2 / 4, longest
wrong run 7 / 12 unchanged; six gestures: recognition medians (0.269 / 0.279), longest wrong
runs (10 / 7) and the avoidable ones (2 / 2) unchanged, the line 0.311 -> 0.331 tuned;
``--sections=sized,holds,unrelated``: valid after 30% of gestures at 0.7-1.4x 0.9112 / 0.9033
unchanged, progress RMSE median 0.0196 -> 0.0191 / 0.0211, holds and unrelated motions
unchanged. Measured and not kept: always the last point (the same twenty-template figures but
the held-out longest wrong run 12 -> 14, and on ``tests/mop/test_spotting.py``'s subset the
line drove 3 ticks of a circle's start that an observer could tell: an estimated size off
moves that anchor with it); the sample at which the new attempt begins: never recognised
0.062 / 0.125, within 20% 0.219 / 0.313; the slowest sample among the next 3 / 6 (a new
attempt each time the input slows further): never recognised 0.344 / 0.094 and 0.375 /
0.156; the attempt abandoned when every template is refused *or off its path* (instead of
refused): held-out never recognised 0.156 -> 0.125 (the next gesture's anchor still short),
but unrelated motions valid more (mean 0.0734 -> 0.0828 / 0.0814 -> 0.0939, worst 0.306 ->
0.422): each fresh attempt in an unrelated motion gives every template a new start.
Measured and not kept: after an end, every template started where the forward weights take it
in the samples since the end was reached (at most :data:`END_GRACE`; none while the input
rests or still comes closer to the ended template's last point): the next gesture's follower
lags its start by those samples, and a roll ankle's, summing 624 in shape against a walk
ankle's 150 by 0.21 of it, let the walk drive 0.24-0.29 of the roll. Twenty templates back to
back (seeds 201-210 of ``bench/follow_quality.evaluate``), the longest run of an action other
than the one just ended 2, 3, 2, 4, 1, 0, 0, 1, 0, 2 -> 1, 0, 0, 4, 1, 0, 0, 1, 0, 2; but an
unrelated stroke right after a gesture valid 0.0730 -> 0.0761 of its ticks (every template
gets the head start); started so also while the input was still coming closer to the last
point, progress RMSE p90 at 0.7-1.4x 0.0405 -> 0.0423 (a fast-ending crawl wrist's 0.019 ->
0.144: the performer was still finishing it). Nor the samples since the end was reached (1-8
into the next gesture, 0.02-0.13 of it) stepped again through the new attempt (up to 12):
``bench/follow_quality.py --sections=sequences`` (tuned / held-out) twenty within 20% 0.344 /
0.344 unchanged, tuned the kick ankle 0.392 -> 0.357, the spin ankle 0.398 -> 0.336, the line
0.427 -> 0.449, held-out the wave 0.269 -> 0.379, longest wrong run 2 / 4 -> 2 / 6.

A gesture never recognised leaves no end: no new attempt begins and the next gesture is followed
on the old sums (held-out twenty back to back, seeds 101-112: 14 gestures begun after one never
recognised, their attempt open 1-124 ticks before them, 11 of them never recognised; seed 109's
punch, never valid, followed to 0.99 of it, drove 4 ticks of the getup after it). Measured and
not kept: a new attempt where the likeliest template, neither refused nor valid, with nothing
driven since the attempt began, is followed to ``end`` (follower and group). ``bench/
follow_seeds.py --sections=sized,unrelated,sequences`` 101-112: twenty within 20% 104 0.313 ->
0.344, 107 0.281 -> 0.313, 109 0.188 -> 0.219 (the getup recognised at 0.18), longest wrong run
109 4 -> 3 (after one never recognised: 4 never recognised of 12), all else unchanged; but
``bench/follow_quality.py`` sized at 0.6 / 1.5x recognised 0.975 -> 0.950 (a roll wrist at 0.6x
is followed to its end before it is valid), progress RMSE p90 0.078 -> 0.088. With the ended
template shown at its end after it (as after a recognised end) and the attempt begun only once
the input rests or moves on (as after a recognised end, ``not ok`` or a step off the null
model): sized unchanged and 104/107/109 as above, but held-out bent 10% progress RMSE median
0.0405 -> 0.0411 (a spin wrist never valid, bent, followed to its end before the performer's:
0.029 -> 0.107). Without ``not ok`` 109 is lost again. Kept instead:
:data:`~behaviors.mop.gesture_end.UNSEEN_END`, an end of its own pending until the input moves
on from it. Not kept either: the same end where another template drove earlier in the attempt
(a sized walk at 0.7x, valid, lost, valid at its last sample again, lost that sample: 104
0.9028 -> 0.9025).

Shared starts (``ActionFollower(share_radius=...)``, :meth:`_shares`): a new action does not
drive while its start is still the start of another template the input fits; the rule and its
figures are in :mod:`behaviors.mop.sharing`.

What is out of reach here (``bench/follow_quality.py``'s sequences): recognising every gesture
within 20% of it. An ideal observer (noise-free paths, any size 0.46-2.25x, any tempo) tells
the zigzag from every other of the six gestures at 9% of it, the figure eight at 11%, the wave
at 13%, the circle at 20%, the line at 35% and the square at 37% (paths within 2 mm; at 4 mm:
11, 14, 16, 22, 54, 38%); in the bench's sequences that leaves 56% of the gestures (held-out
50%) that any follower could recognise by 20%; what holds each back: below.
Which of the six are ambiguous by construction at 20% (``bench/follow_quality.py
--sections=sequences``, per gesture, ``bench/follow_sequences.py``'s construction figures, the same
observer at 2 mm): pairwise, only the line and the square stay starts of each other past 20% (the
line until 0.35 of it, the square 0.37; every other pair is told apart by 0.06-0.21, the circle
from the line at 0.20 and from the square at 0.19); the figure eight's start is the diagonal
until 0.21 of it and the line's and the square's the triangle's first stroke until 0.28 and
0.25, so recognised by 20% the eight drives the diagonal (the ``after`` and ``unrelated``
sections' worst: ``after_diagonal_figure_eight_valid_share`` 0.151 is every valid tick of the
diagonals); and every one of the six is still a straight stroke (within 2 mm of its chord at
1.2x) at 0.20-0.37 of it (the eight 0.20, the circle 0.22, the zigzag and the wave 0.25, the line
0.27, the square 0.37), told from any straight stroke only by its direction. Open at 20% are the
circle, the zigzag and the wave; within 20% among them (``..._within_20pct_open_share``) 0.235:
the zigzag, whose start no other of the six shares past 2.6% of its path, needs only that much
covered while the input keeps to its path (:mod:`~behaviors.mop.coverage`, per template) and is
recognised within 20% of it 0.67 of the time (median 0.183).
Where the next gesture begins costs nothing: per gesture, those begun where another ended are
recognised as late as those begun from rest (medians; 16 sequences of four drawn with seed 29,
the bench's draws for options, against 48 single gestures drawn with it: circle 0.279 / 0.275,
zigzag 0.251 / 0.247, figure eight 0.234 / 0.243, line 0.475 / 0.433, square 0.410 / 0.421,
wave 0.247 / 0.242; the bench's ``..._from_rest_median`` and ``..._after_a_gesture_median``
mix which gestures come first). Less coverage than 8%, measured: :mod:`~behaviors.mop.coverage`.
Among the held-out twenty templates back to back (``bench/follow_seeds.py --sections=sequences``,
seeds 101-112, 384 gestures traced per tick with ``bench.spotting_reach.gate_state``): within 20%
0.375 of those begun from rest and 0.247 of those begun where another ended, against 0.271 had each
kept its own template's rate from rest, so the previous gesture costs 0.024 of the latter. A new
attempt begun 0.08 or more into the gesture (the last one's end reached late; 97 of 288) changes
the same template's median recognition by 0-0.06 (the line 0.36 -> 0.39, the circle 0.43 both): it
falls on templates recognised late from rest too (the six gestures' eased starts, the cartwheel,
jump and crawl ankles). 11 templates (0.53 of the gestures) are never recognised within 20%; the
last rule to clear for the 277 late ones (ties counted in each): coverage 138 (alone 78, at a
median 0.22), probability 98, best 98, the lead 76, the shared start 65.
Measured with every template asked 8% of its path (``bench/spotting_reach.py``, tuned): the last
rule to clear (``bench.spotting_reach.GATES``) is coverage for the zigzag (0.23 of it) and the
figure eight (0.22), coverage, probability and best within a sample of each other for the circle
(0.25) and the wave (0.22-0.23), the shared start for the line (0.45), the lead for the square
(0.39); recognised (medians, ``bench/follow_quality.py --sections=sequences``) at 0.26, 0.26, 0.24,
0.45, 0.41, 0.23: none within 20% or by its reach. The gestures ease in (their first 2% of path
takes 11-15% of their progress), so 8% of the path lies at 0.22-0.24 of it (6%: 0.19-0.22; 4%:
0.16-0.19), and with ``confirm`` nothing drives before about 0.24. Their starts are also starts of
unrelated motions (``bench/motions.unrelated_motions``, within 2 mm at any size and tempo,
``bench/spotting_reach.told_from_unrelated``): the figure eight's of the diagonal until 0.21 of
it, the circle's of the triangle's first stroke until 0.18 (the zigzag's 0.08, the wave's 0.12):
recognised by 20%, the eight drives a diagonal and the circle a triangle. So within 20% is out of
reach for the line (0.35) and the square (0.37), at the edge for the circle (0.20), and open to
the zigzag, the figure eight and the wave only at 4-6% of their path, where coverage refuses what
it refuses (tuned, figures not named unchanged): coverage 8% -> 7 / 6 / 5 / 4%, the zigzag 0.257
-> 0.250 / 0.232 / 0.230 / 0.210, the figure eight 0.244 -> 0.222 / 0.214 / 0.214 / 0.214, the
wave 0.225 -> 0.216 / 0.210 / 0.210 / 0.210; within 20% (or by reach) among six 0 -> 0 / 0.031 /
0.031 / 0.063, within 20% among twenty 0.344 -> 0.344 / 0.375 / 0.406 / 0.406; but unrelated
worst 0.068 -> 0.098 / 0.142 / 0.160 / 0.164 (the diagonal among six, driven by the figure eight),
mean 0.0154 -> 0.0179 / 0.0208 / 0.0242 / 0.0271, a wander with the circle alone 0.009 -> 0.016 /
0.020 / 0.083 / 0.125, after a gesture worst 0.198 -> 0.234 / 0.276 / 0.293 / 0.298. Not kept
either: ``confirm`` counted over the other rules with coverage (a flag that cannot flash) asked of
the last sample only: the zigzag 0.241, the figure eight 0.222, within 20% unchanged, unrelated
worst 0.091, after a gesture worst 0.216; shared starts at 2.5 / 2 still radii (the line's start
shared with the square up to 0.39 of it instead of 0.45): the line 0.455 -> 0.452 (then held by the
lead), the circle 0.262 -> 0.248, valid after 30% at 0.7-1.4x 0.9147 -> 0.9153 / 0.9238, but the
triangle among six 0.042 -> 0.054, after a triangle 0.036 -> 0.051 (2: longest wrong run among
twenty 2 -> 3, unrelated worst 0.107); ``shape_lead.LEAD`` 3: sequences unchanged, the diagonal
among twenty 0.042 -> 0.049; ``min_probability`` 0.5: sequences unchanged, valid after 30% 0.9158,
after a gesture's told worst 0.077 -> 0.089; ``switch_margin`` 0.5: sequences unchanged, after a
gesture's told worst 0.077 -> 0.082; ``shape_lead.COMMIT_FIT`` 2.5: median recognition among twenty
0.298 -> 0.267 (within 20% unchanged), but unrelated worst 0.068 -> 0.077 and a pause's wrong valid
share 0 -> 0.013.
The wave waits for probability because the figure eight, whose first stroke leaves at 45 degrees
where the wave's leaves at 62, keeps 0.4-0.55 of it up to 0.23 of the wave (at 0.6 needed). The
line and the square share the line's outward stroke at any size in the size range until the line
turns back or the square turns its corner (the observer, 0.35 and 0.37), so one of two targets
gives: the line drives the square's first side (wrong runs of 3-10 ticks), or it waits for
its turn (shared starts, above: valid after 30% of gestures at 0.7-1.4x under 0.9). An end
declared also where a valid action at 90% or more of its
progress finds the input stood still :data:`END_GRACE` samples before (:meth:`_arrived`; before
the follower reaches ``end``): no ended action's run over 2 left on either, but valid after 30%
0.9001 -> 0.8816 / 0.9105 -> 0.9015 (performers creep into eased ends for several samples); from
95%: 0.8944 / 0.9072, one run of 3 left on the draws for options. The end reached where the
followed progress is within one standard deviation of ``end`` (the posterior piles against the
template's last state, so its mean lags the bulk): a wave the follower ended three samples late
ends at the performer's last sample, but valid after 30% 0.8798 / 0.8920; half a deviation
0.8885 / 0.9044. Every rule that ends sooner costs the sized performances their eased last
samples, which look the same.

Where a gesture ends (its end reached, a return followed backwards, the grace it still
drives, where the next one is anchored) and the figures behind those rules:
:mod:`behaviors.mop.gesture_end`.

Which action may drive while a gesture is under way (it must lead every rival in shape, or be
committed to by shape) and the figures behind those rules: :mod:`behaviors.mop.shape_lead`.
"""

from __future__ import annotations

import numpy as np

from behaviors.mop.forward import WindowedForward
from behaviors.mop.under_way import step_length, underway
from behaviors.mop.gesture_end import (ARRIVE_RADIUS, END_GRACE, MOVE_RADII,  # noqa: F401
                                       REANCHOR_RADII, RETURN_BACK, RETURN_RADIUS,
                                       UNSEEN_END, GestureEnd, arrived, drives)
from behaviors.mop.handover import (TEMPO_END_FROM, TEMPO_END_KEEP, finished, nearest, slowed,
                                    tempo_ended)


#: Shared starts (:mod:`behaviors.mop.sharing`, ``ActionFollower(share_radius=...)`` in still
#: radii per column): sizes tried between the size range's extremes' ratio and its inverse, and
#: states another template may run ahead per state.
SHARE_SIZES = 25
SHARE_SKIP = 3
#: A template whose followed progress fell this far below its highest since the gesture began
#: is going back: no start read forwards, so it keeps no other action from driving.
SHARE_BACK = 0.03


class GestureSpotting(GestureEnd):
    """Mixin of :class:`~behaviors.mop.follower.ActionFollower`: onsets and ends of gestures
    (the ends' own rules: :class:`~behaviors.mop.gesture_end.GestureEnd`)."""

    def _restart_here(self, x: np.ndarray, forward: WindowedForward, offset: int,
                      still: bool = False) -> None:
        """A new attempt starts at this sample (``still``: at the mean of the still input):
        anchor there, every template at its first state, no evidence; the threshold model
        afresh but for its lead over the templates (:meth:`ThresholdLead._threshold_lead`)."""
        # Measured and not kept: the forward's transitions flatter for the attempt's first
        # samples, so that the followed state catches up with a fast start (onset found a few
        # states late: a kick ankle's followed progress 0.02 at 0.12 of it). bench/follow_quality
        # .py --sections=sequences, twenty templates, tuned / held-out: for 8 samples (0.1, 0.3,
        # 0.3, 0.3, none back) within 20% 0.406 / 0.375 -> 0.375 / 0.313, past the reach 0.101 /
        # 0.087 -> 0.090 / 0.081, held-out longest wrong run 4 -> 6; 4 and 15 samples (0.2, 0.3,
        # 0.3, 0.2, 0.05 back) within 20% 0.344 / 0.344 and 0.375 / 0.344: sooner on the mean,
        # but rivals catch up as fast and fewer gestures are recognised within 20%.
        # An attempt begun after an end once the next gesture was 0.05 or more under way was
        # recognised within 20% on none of 11 (twenty templates, tuned and held-out 101-103). Not
        # kept either (same bench, per seed, tuned / held-out): every template's followed state
        # at such a restart seeded at the state of its first window nearest the input (at its
        # size, from the anchor; the input 4 still radii RMS or more from it; the state within
        # 2 radii and below 0.15 of the template): twenty within 20% 0.406 / 0.375 unchanged,
        # held-out 101-106 mean 0.281 -> 0.286 (102 and 106 up one gesture, 104 down one), but
        # tuned by the reach + 0.05 0.281 -> 0.219 (a walk ankle seeded at 0.081 of it, best on
        # a jump wrist's start: recognised 0.081 -> 0.118); waiting at the end of each
        # template's first run of states within a still radius at a still input: six gestures
        # sooner by 0.01-0.02 (no share moved), twenty 0.406 / 0.375 -> 0.375 / 0.344.
        forward.reset_templates(offset + np.arange(len(self.names)))
        entries = self._entries.copy()
        lead = self._threshold_lead()
        self._forget()
        self._threshold_ev = lead
        self._entries[:] = entries
        if still:
            self._anchor = np.mean(self._recent_x, axis=0)
        else:
            self._anchor = x.copy()
            self._recent_x = [x]

    def _shares(self, k: int, g: float, progress: np.ndarray) -> bool:
        """Whether template ``k``'s followed state ``g`` (bank index) is still within its start
        shared with another template that is neither refused nor off its path nor going back
        (:func:`behaviors.mop.sharing.shared_until`; ``progress``: every template's followed
        progress, ``_gone`` its highest since the gesture began): the input cannot yet tell
        them apart."""
        if self._shared is None:
            return False
        i = int(g) - int(self.bank.starts[k])
        rivals = ((self._shared[k] >= i) & ~self._refused & ~self._misshaped
                  & (progress >= self._gone - SHARE_BACK))
        rivals[k] = False
        return bool(rivals.any())

    def _still(self, x: np.ndarray) -> bool:
        """The input stayed within the still radius for ``still_samples`` samples."""
        buf = self._recent_x
        buf.append(x)
        if len(buf) > self.still_samples:
            del buf[0]
        if len(buf) < self.still_samples:
            return False
        a = np.array(buf)
        return bool(((a.max(axis=0) - a.min(axis=0)) <= 2.0 * self._still_radius).all())

    def _spot(self, valid: bool, ok: bool, engaged: bool, still: bool, bi: int, progress: float,
              step_ll: float, x: np.ndarray, forward: WindowedForward, offset: int,
              rests: bool) -> None:
        """After a sample: start afresh when the gesture of ``bi`` ended (its end reached, or it
        rests near its end) or every template refused it; a still input waiting for a gesture
        anchors it. ``ok``: ``bi`` matched at this sample; ``progress`` and ``step_ll``: its
        progress and this step's log-likelihood; ``rests``: the performer rests
        (:func:`~behaviors.mop.tempo.resting`)."""
        # the highest progress of the action driving since it began (for _returned)
        self._peak = max(self._peak, progress) if bi == self._peak_k else progress
        # the action's progress over its last samples (handover.tempo_ended)
        if bi != self._peak_k:
            self._end_history.clear()
        self._end_history.append(progress)
        del self._end_history[:-TEMPO_END_KEEP]
        self._peak_k = bi
        done = (self._end_x is None and self._drive_k == bi
                and finished(self._drive_peak, progress, self._crawl > 0))
        # the follower lags on an eased end the performer went through at their tempo
        lagged = (self._end_x is None and valid and TEMPO_END_FROM <= progress < self.end
                  and not done and slowed(self._recent_x, self._still_radius)
                  and tempo_ended(self._end_history, self.end))
        if self._end_x is None and ((valid and progress >= self.end) or done or lagged
                                    or self._returned(x, bi, progress)):
            self._end_last = self._last_point(bi)
            # finished short of the end: it ended where the input came nearest its last point
            self._end_x = nearest(self._recent_x, self._end_last) if done else x.copy()
            # the performer had already stopped there: the grace counts from where they stopped
            self._after_end = self._arrived()
            self._lagged = lagged
            # (read as a return: gesture_end.REANCHOR_RADII)
            self._end_returned = not ((valid and progress >= self.end) or done or lagged)
            self._end_near, self._end_nearing = self._end_x.copy(), True
        elif self._end_x is not None:
            near = np.sum((x - self._end_last) ** 2)
            if self._lagged and near < np.sum((self._end_x - self._end_last) ** 2):
                # ended at its tempo: the end is where the input comes nearest its last point
                self._end_x = x.copy()
            # where the input came nearest that point until it first went away from it
            # (take_rule.TAKE_FROM_NEAREST)
            if self._end_nearing and near < np.sum((self._end_near - self._end_last) ** 2):
                self._end_near = x.copy()
            else:
                self._end_nearing = False
        if (UNSEEN_END and self._end_x is None and self._unseen_x is None and self._drive_k < 0
                and not valid and not self._refused[bi] and progress >= self.end
                and len(self._end_history) > 1
                and TEMPO_END_FROM <= self._end_history[-2] < self.end):
            # never recognised, its likeliest template followed to its end: pending there
            self._unseen_x, self._unseen_last = x.copy(), self._last_point(bi)
        step_d2 = (self._log_constant - step_ll) * (2.0 / self._zdim)
        # the input's step here and its path since the anchor (under_way.underway)
        self._step_prev, self._step_last = self._step_last, step_length(
            self._recent_x, self._still_radius)
        self._walk += self._step_last
        self._walk_n += 1
        self._lost = self._lost + 1 if bool(self._refused.all()) else 0
        if self._end_x is not None and (still or step_d2 > self._null2 or not ok or
                                        self._departed(x, bi, self.accept_distance)):
            # the end was reached and the performer rests there or moves on: a new gesture
            # starts where the last one ended: its template's last point at its size. (Back to
            # back the end is mostly reached 1-6 samples before the next gesture begins and this
            # comes 2-10 samples into its eased start. Measured and not kept: the departure at
            # 0.6 of accept_distance, bench/follow_quality.py --sections=sequences, tuned and
            # held-out 101-103: no within-20% share moved, a tuned figure eight 0.284 -> 0.428.)
            # Measured and not kept: the new attempt begun at the end itself (where a valid action
            # reached ``end``, not a tempo or return end; anchored there) and again at each sample
            # the input still comes closer to the ended template's last point (anchored there),
            # the ended action shown at its end until the input moves on or another drives (it
            # drives up to END_GRACE samples). bench/follow_quality.py, tuned / held-out: twenty
            # within 20% 0.406 / 0.375 -> 0.375 / 0.406 (six unchanged), sized and pauses
            # unchanged; follow_seeds.py 101-106: twenty within 20% mean 0.281 -> 0.323 (every
            # seed up), six 0.104 -> 0.125; but after a gesture told worst 0.072 -> 0.089 (a
            # wander 0.031 -> 0.037), tuned twenty by the reach + 0.05 0.50 -> 0.469, held-out
            # longest wrong run 4 -> 6 (seeds 4/5/3/2/2/4 -> 6/5/3/6/3/4). Shown only until
            # another template engages: progress RMSE p90 at 0.7-1.4x 0.040 -> 0.113 (the
            # performer's last samples engage others). The tuned roll ankle that went late (0.189
            # -> 0.208) began after a figure eight the follower ended 4 samples before its
            # performer; waiting for the input to stand (ARRIVE_RADIUS) first did not bring it
            # back and lost a held-out gesture. On the rules since, anchored at the mean of the
            # samples the input stood there (arrived, 2 still radii; at one sample 101's run: 6-7)
            # and begun again while the input goes on forward along the ended template's last
            # fifth of path (within 3 still radii, short of its last point; without it a line
            # after a spin ended 7 samples early was anchored 3.7 mm off, never recognised):
            # bench/follow_quality.py --sections=sequences per seed, twenty templates, within 20%
            # held-out 101-106 mean 0.281 -> 0.323 (every seed up), six 102 and 106 up one; but
            # tuned 0.406 -> 0.375 and 102's longest wrong run 3 -> 5: the punch ankle leads a
            # getup wrist in shape (shape_lead) at 0.105-0.14 of it, on the samples the attempt
            # now holds (the cartwheel's last one, the getup's still start), at the anchor of
            # before. The tuned roll ankle (0.189 -> 0.208): the eight's last 2 samples go
            # neither nearer its last point nor forward along its path; begun again while within
            # 3 still radii of that path whichever way the input goes, the roll is back at 0.189,
            # but a closed figure's next gesture runs along it (anchors 7-11 mm off, a walk
            # ankle after the eight never recognised).
            # On the rules since (bench/follow_seeds.py --sections=sequences per seed, twenty
            # templates within 20%, tuned; held-out 101-106 / 107-112 mean; longest wrong run of
            # each seed): 0.375; 0.323 / 0.318 (without it 0.406; 0.281 / 0.313), runs 4/5/3/2/3/4
            # and 2/5/3/2/3/3 (without 4/3/3/2/2/4 and 3/5/3/2/4/2): 105, a line's end reached at
            # a crawl ankle's first sample, then shown its grace; 112, the punch ankle over a
            # getup wrist, whose attempt began 4 samples sooner in its still start. Begun once
            # more where the input stops coming closer or going forward (anchored as after any
            # end, _next_anchor): the roll back at 0.189 (tuned 0.406), but 0.313 / 0.323, runs
            # 4/3/3/3/3/4 and 4/4/3/2/3/3, and (bench/follow_quality.py, as without it) after a
            # gesture told worst 0.072 -> 0.089 (a wander). The shape sums alone (not the
            # forward's evidence) begun again at the first still or departed sample after that,
            # nothing driven yet:
            # 102's run 5 -> 2, but tuned 0.375, 0.313 / 0.318, runs 4/2/3/2/3/4 and 4/3/3/2/3/3,
            # sized valid after 30% at 0.7-1.4x on 102 0.9036 -> 0.9020. Both: 0.406; 0.302.
            anchor, near = self._next_anchor(x, bi), self._end_near
            returned = self._end_returned
            self._restart_here(x, forward, offset)
            self._anchor = anchor
            self._take_shift = anchor - near
            self._ended = bi
            self._begun_at_return = returned
        elif valid and still and progress >= 0.9:
            self._restart_here(x, forward, offset)
            self._ended = bi
        elif (self._unseen_x is not None and self._drive_k < 0
              and self._moved_on(x, bi, self._unseen_x, self._unseen_last)):
            anchor = self._unseen_x
            self._restart_here(x, forward, offset)
            self._anchor = anchor
            self._ended = bi   # shown at its end until the next gesture engages
        elif self._lost >= self.lost_samples:
            # the input's way here (validity.unbegun): over the attempt abandoned, from its anchor
            came = x - self._anchor   # (the anchor is set at the first sample: _inputs)
            under = underway(self._step_prev, self._step_last, self._walk, self._walk_n)
            self._restart_here(x, forward, offset)
            self._abandoned, self._came = True, came
            self._underway = under
        elif still and not engaged:
            self._restart_here(x, forward, offset, still=True)
        elif (REANCHOR_RADII > 0 and self._begun_at_return and rests and self._drive_k < 0
              and bool(np.any(np.abs(np.mean(self._recent_x, axis=0) - self._anchor)
                              > REANCHOR_RADII * self._still_radius))):
            self._restart_here(x, forward, offset, still=True)
