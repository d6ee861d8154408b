"""The end of a gesture in a continuous stream: when the action driving it has ended, how
many samples it still drives, and where the next gesture is anchored (the rules
:meth:`GestureSpotting._spot <behaviors.mop.spotting.GestureSpotting._spot>` applies; the
compiled group's :func:`behaviors.mop.members.conclude` takes the same constants).

Measured back to back (``bench/follow_quality.py``) when an ended action stopped driving only
once the input left by ``accept_distance`` and now (stops as soon as it moves on): among the
six gestures the median longest run of a wrong action driving 13 -> 11.5 samples, median
recognition at 24% -> 24%; among twenty templates gestures never recognised 16% -> 3% (held-out
joints: 16% -> 9%, median recognition 35% -> 25%).

Why an ended action stops driving two samples after its end and not when the input moves on:
every gesture starts eased (within 2 mm of its start for its first 4-7 samples, under the
tracking jitter), so the next gesture cannot be told from resting at the end, and the ended
action drove 3-19 ticks into it (``bench/follow_quality.py``, the six gestures back to back:
longest such run 16, held-out 19; twenty templates 10, 19). The follower's own progress reaches
``end`` 0-5 samples before the performer reaches the last point (it leads on eased ends, lags on
fast ones). Partial runs of the bench's sections (sizes: valid after 30% of gestures at
0.7-1.4x, 0.908 before): no sample after the end 0.882 (the last 3% of each gesture lost),
two 0.901, four 0.906 (runs of the ended action into the next up to 4 samples); two, not
counting samples that came closer to the last point by a still radius 0.903, but the ended
action then drove three samples into the next in 7 of 32 gestures. Kept at two,
the length of ``confirm``: the ended action's runs into the next gesture are then at most two
samples, except where the follower never reached the end (a line whose return was followed
backwards, its size overestimated: 16 ticks; see the bench's notes).

A return followed backwards: a line (out and back along the same stroke) performed at 0.7x,
fast, is followed at about 1x: the follower lags at the turn (the size and the progress along a
straight stroke are one unknown), and the return then matches the outward stroke read backwards,
so the progress never reaches ``end`` and the line drove 7-19 samples of the next gesture, whose
evidence it also kept from starting afresh. So the gesture also ends (:meth:`_returned`) when the
input is back at the template's last point, within :data:`RETURN_RADIUS` of its extent, while
the followed progress has slid back :data:`RETURN_BACK` from its peak since it became ``best``
(a figure eight passes its last point at half of it, going forward: no slide). Measured
with ``bench/follow_quality.py`` (partial runs of its sections; held-out in brackets): six
gestures back to back, the longest wrong-valid run 16 -> 10 samples (19 -> 7), a held-out square
never recognised now at 42%; valid after 30% of gestures at 0.7-1.4x 0.901 -> 0.896 (0.885 ->
0.884): the lines at 0.6-0.85x followed backwards were counted valid (and right) until their
last sample with the progress 0.7 short (RMSE 0.33-0.48); they now end 3-8 samples before their
last (radius 0.15 of the extent: 0.895, 0.08: 0.895, 0.05: 0.896, kept). The peak counted
since the action began driving instead of since it became ``best``: the same without shared
starts (valid after 30% 0.9112 / 0.9033, now 0.9099 / 0.9033), but with them a line held back
until its turn never ended (above).

An ended action whose end the follower reached where the input had already stopped has as
many samples less of grace as the input stood there before (the samples before lying, with the
last, within :data:`ARRIVE_RADIUS` still radii, range per column; at most :data:`END_GRACE`:
:meth:`_arrived`): the grace counts from where the performer stopped. On an eased end the
follower reaches ``end`` one to four samples after the performer, often at the next gesture's
first samples (the same point), and the ended action drove three or more samples into it.
One sample less at most, measured with ``bench/follow_quality.py``'s six gestures back to back
(partial runs; held-out in brackets): runs of the ended action of three samples 7 -> 2 (5 ->
1), median longest wrong run 3 -> 2.5 (3 -> 2.5); valid after 30% of gestures at 0.7-1.4x
0.8959 -> 0.8941 (0.8844 -> 0.8829): where the follower reaches ``end`` a sample before the
performer's last, on the eased approach; with 1 still radius instead of 2 the runs of three
stay (7 and 5). Counted back up to :data:`END_GRACE` samples (``bench/follow_quality.py``, its
sections sized, holds, sequences and unrelated; tuned / held-out): runs of the ended action of
three or more 2 / 1 -> 1 / 0 (the draws for options, 16 sequences: 7 -> 2), median longest
wrong run 2.5 -> 2 / 2.5 -> 2; valid after 30% of gestures at 0.7-1.4x 0.9016 -> 0.9001 /
0.9112 -> 0.9105, unrelated motions mean 0.085 -> 0.084 / 0.098 -> 0.098, holds unchanged.
Left: a wave whose follower reached ``end`` four samples after the performer, who had crept
within 2 mm of it for eight samples (3 and 4 ticks). Measured and not kept: the end
reached once past 0.9 with the input within 2 still radii
of the template's last point (at the estimated size): also runs of at most two, but valid after
30% of gestures at 0.7-1.4x 0.896 -> 0.886 (it ended closed gestures, whose eased approach
lies within that radius, several samples early); the last point instead of the sample before
as the place the input stopped in: the same runs, and on the sized subset of
``tests/mop/test_quality.py`` one tick less of a figure eight. The grace counted from where the
performer came to rest (:func:`~behaviors.mop.tempo.resting`) with the action followed
inside its end hold (a compressed hold in the last 10% of its progress: a kick ankle's at
0.89-0.96, the wave's, the circle's): among twenty templates back to back (seeds 201-210 of
``bench/follow_quality.evaluate``, 80 sequences) ended actions' runs over two ticks 6 -> 5, the
longest 4 -> 3; but valid after 30% of gestures at 0.7-1.4x 0.9147 -> 0.9144, at 0.6 and 1.5x
0.7582 -> 0.7574, raise-hold-return 0.958 -> 0.956 (a wave at 0.6x, a kick ankle at 1.4x and
a lift each lost their last tick: the follower, level with or ahead of the performer there,
reached ``end`` two to four samples after they came to rest). The runs left lie *before* the
end is reached: the follower crosses an eased end at the prior's drift (about a state per
sample), and a kick ankle performed at 1.5 states per sample is followed at 0.92-0.95 at its
last one. A forward that keeps the performer's tempo through such stretches ended those runs
but cost other figures (measured, not kept: :class:`behaviors.mop.hmm.Transitions`); an end at
the tempo followed before the eased stretch ends most of them (:mod:`behaviors.mop.handover`).
Held out (``bench/follow_seeds.py --sections=sequences``, seed 108: six gestures' longest wrong
run 3): the zigzag's end drove the square's first three samples (0-0.019). Its end was fast (the
input moved 2.1-2.7 mm a sample, over two still radii, so neither the tempo rule nor
:meth:`_arrived` applies); the follower was at 0.967 at the performer's last sample (``end``
0.97), reached it one sample later, at the square's first, and the grace added two.
:data:`END_GRACE` 1 instead (follower and compiled group alike; measured, not kept): the
sequences' longest wrong runs, ``bench/follow_seeds.py --sections=sequences``, six gestures
1/2/2/2/2/2 -> 1/1/1/1/1/2 (seeds 101-106) and 2/3/2/2/2/1 -> 1/2/2/1/1/1 (107-112), twenty
templates 4/5/7/2/2/4 -> 3/5/7/1/2/4 and 3/6/4/4/5/4 unchanged, shares within 20% unchanged; but
``bench/follow_quality.py``: valid after 30% at 0.7-1.4x 0.9117 -> 0.9047, held-out 0.9022 ->
0.8978 (under its 0.9 target), holds 0.958 -> 0.951, pauses valid after 0.941 -> 0.929, bent 5%
0.865 -> 0.860, aspect 1.1 0.890 -> 0.880; and
``tests/mop/test_sequences.py``'s crawl handover test fails: with its rule off the run is
2 ticks, no longer over 2.
The grace counted from where the performer's own motion reached the end (follower and compiled
group alike; measured, not kept): one sample less where the sample before lay within 2 still
radii (per column) of the template's last point while the tempo followed would have carried the
action to ``end`` a sample ago (:func:`~behaviors.mop.handover.tempo_ended`, without its slowed
input). ``bench/follow_seeds.py --sections=sequences``: six gestures' longest wrong runs
1/2/2/2/2/2 -> 1/2/2/2/1/2 (seeds 101-106) and 2/3/2/2/2/1 -> 2/2/2/2/2/1 (107-112; seed
108's zigzag drove the square's first two samples), twenty templates unchanged;
``bench/follow_quality.py`` (tuned / held-out): an unrelated stroke after a gesture, worst
0.165 / 0.189 unchanged, mean 0.0639 / 0.0620 -> 0.0639 / 0.0618; but valid after 30% at
0.7-1.4x 0.9117 -> 0.9115 / 0.9022 (``bench/follow_seeds.py``: seed 103 0.9055 -> 0.9050),
pauses valid after 0.9411 -> 0.9397 / 0.9288, bent 10% 0.6208 -> 0.6203 (the figure eight at
1.4x, its performer within 2 still radii of its last point from three samples before the
follower reached ``end``, lost a tick); holds and unrelated motions unchanged, and the
sequences' shares within 20%. The sample before at the last point alone (no tempo): seed 108's
zigzag drove one sample, but valid after 30% 0.9117 -> 0.9103 / 0.9022 -> 0.9009.
The grace less by the samples before the end that already lay within ``R`` still radii (per
column) of the template's last point at its size, up to :data:`END_GRACE` (the performer there
before the follower, whatever the tempo; the follower alone, measured, not kept). Held-out seed
101's twenty-template run of 4: the backflip ankle's performer reached its last point a sample
before the square began (within 2.3 mm of it from then on, the jitter's 1.3-2.6 mm steps over
:data:`ARRIVE_RADIUS`), the follower at 0.95 there reached ``end`` two samples later, at the
square's second, and the grace added two. ``bench/follow_seeds.py --sections=sequences`` (R 3):
twenty templates' longest wrong run on 101 4 -> 2, every other seed of 101-112 unchanged; six
gestures 1/2/2/2/2/2 -> 1/1/1/1/1/2 (101-106) and 2/3/2/2/2/1 -> 1/1/2/1/1/1 (107-112). But
``bench/follow_quality.py --sections=sized`` valid after 30% at 0.7-1.4x 0.9124 -> 0.9097
(held-out 0.9022 -> 0.9003); R 2: 0.9110 / 0.9009, the six example gestures' eased, closed
approaches lying within 2 still radii of their last point 1-3 samples before it (``--debug``: a
zigzag at 1.0x 1.0 -> 0.964, a circle at 0.7x 0.667 -> 0.619, figure eights at 1.0-1.4x 0.01-0.03
each); R 3 counting only samples at which the follower was still below 0.955: 0.9116 / 0.9022 and
no run changed (that backflip's follower was at 0.96 a sample before its end). Where the
performer stops at the last point and where they creep to it, the follower reaching ``end`` at
the same sample, the input looks the same.
The end read from the input where the follower stops at it (the follower alone; measured, not
kept): once the end was reached, the grace is over at the first sample at which the action's
followed state advanced under 0.5 states while the input moved 1 still radius or more in some
column. ``bench/follow_seeds.py --sections=sequences`` (101-112): twenty templates' longest wrong
runs 4/5/7/2/2/4 -> 2/5/7/1/2/4 and 3/6/4/4/5/4 unchanged, six gestures 1/2/2/2/2/2 ->
1/2/2/1/2/2 and 2/3/2/2/2/1 -> 2/2/2/2/2/1, every share within 20% unchanged; but
``--sections=sized`` valid after 30% at 0.7-1.4x 0.9022/0.8858/0.9057/0.8990/0.8903/0.8849 ->
0.8965/0.8796/0.8971/0.8903/0.8829/0.8789 (101-106, mean 0.8946 -> 0.8875);
``bench/follow_quality.py`` (tuned / held-out): twenty templates' longest wrong run 2 / 4 -> 2 /
2, but valid after 30% at 0.7-1.4x 0.9124 / 0.9022 -> 0.9071 / 0.8965, holds 0.958 / 0.963 ->
0.956 / 0.957, pauses valid after 0.941 / 0.929 -> 0.925 / 0.916, bent 5% 0.865 -> 0.863: at a
true end the follower, level with or ahead of its performer, also creeps under half a state a
sample while the performer's last samples (and the jitter, 1-3 still radii a sample) move on.
Traced, the ended runs of 3-4 ticks (101, 106, 107, 109): the follower was not stalled before
its end but 1.5-2 samples behind its performer (0.01-0.025 of progress, 0.5-1.2 states a
sample), reaching ``end`` at the next gesture's first or second sample; after it, it crept
0.15-0.5 states a sample. The input moving *away* from the last point (farther by 1 still
radius in some column than at the sample before) instead of moving at all:
``bench/follow_quality.py --sections=sized,sequences`` held-out twenty longest wrong run 4
unchanged (median 2 -> 1.5), valid after 30% at 0.7-1.4x 0.9124 / 0.9022 -> 0.9110 / 0.9015,
at 0.6 / 1.5x 0.7540 / 0.7001 -> 0.7533 / 0.6978.
The input beyond where the template's end still goes (the follower alone; measured, not kept):
past 0.9 of its progress an action stops driving once the input lay N samples in a row farther
than 3 still radii (RMS per column) from every state between its followed state and its last
(at its size, from the anchor). Those four runs traced per sample first: on 101, 106 and 109 the
next gesture's first samples lie 0.4-2.6 still radii from that remaining path (its eased start,
within the jitter's own steps of 1-3); on 107 the input lay 3.5-6.6 radii off it from the
backflip ankle's own 0.95 on (its performer's end that far off the template's at the estimated
size). ``bench/follow_seeds.py --sections=sequences``: N 2 (101, 107) and N 3 (101, 106, 107,
109): 107's run 3 -> 2, the others unchanged;
``--sections=sized --seeds=105`` valid after 30% at 0.7-1.4x 0.8937 -> 0.8873 (N 2; 19
performances at 0.6-1.5x lost ticks: true ends lie off their template's end at the estimated
size) and 0.8929 (N 3).
The grace counted whole from where the performer stopped (measured, not kept; shown valid only,
follower and compiled group alike): an end reached at the tempo followed
(:func:`~behaviors.mop.handover.tempo_ended`, the follower lagging) where the input had already
stood 4 samples (:func:`arrived` counting up to 4, its radius) not shown driving at that sample.
Held-out seed 107's twenty-template run of 3: the backflip ankle's performer stood at its eased end
(within 1.5 still radii) from the sample before its last, its follower at 0.930 there reached
``end`` at its tempo three samples later, at the wave's third, and drove the wave's first three.
``bench/follow_seeds.py --sections=sized,sequences`` (107-112): twenty templates' longest wrong run
3/5/3/2/4/2 -> 2/5/3/2/4/2, every other figure identical; but on 101-106 no run shorter and valid
after 30% at 0.7-1.4x on 101 0.91304 -> 0.91268. Others (107-112, valid after 30% at 0.7-1.4x mean
0.9048; 101-106 0.9077): stood 3 samples, however the end was reached: 107's run 3 -> 2, six
gestures' 109 and 106 2 -> 1, but 0.9041 / 0.9072, lower on every seed (108 0.8906 -> 0.8888:
performers creep into an eased end within 2 still radii while the follower, level with them,
reaches ``end``); 4 samples (107-112): 0.9046 (108, 111, 112 lower); 5: no run shorter, 0.9047; 3
at the tempo: 0.9048 -> 0.90478 (107 0.91115 -> 0.91098), 0.9076 (101, 105, 106 lower). The end
read from the input turning away from the template's last direction (its last 3 states moving 1.5
or 2.5 still radii a state at the estimated size, the input's step before along it by a cosine over
0.5 and at least a still radius, this one against it), or the grace withheld once the input leaves
the last point by 3 or 5 still radii in a sample: no run shorter on 106-112 (at the next gesture's
first samples the input moves by the jitter alone, 0.1-2.7 still radii a sample: its eased start),
valid after 30% 0.9035 / 0.9040 (turning), 0.9046 / 0.9048 (leaving).
"""

from __future__ import annotations

import numpy as np

#: Samples an action still drives after the one at which it reached its end.
END_GRACE = 2
#: Still radii (in a column) by which the input, farther from an ended template's last point than
#: where the end was reached, has moved on: the next gesture has begun
#: (:meth:`GestureEnd._moved_on`).
MOVE_RADII = 2.0
#: Progress by which a driving action's followed progress must have slid back from its peak,
#: and distance from its last point (share of the template's extent at the estimated size),
#: for the input's return to that point to end the gesture (:meth:`GestureEnd._returned`).
RETURN_BACK = 0.2
RETURN_RADIUS = 0.05
#: An action that reaches its end while the input moved less than this many still radii (per
#: column) since the sample before has one sample less of grace
#: (:meth:`GestureEnd._arrived`): the performer stopped there a sample before.
ARRIVE_RADIUS = 2.0
#: A gesture never recognised (nothing drove since the attempt began) whose likeliest template,
#: neither refused nor valid, is followed to ``end`` ends there, pending as a recognised end is:
#: a new attempt starts once the input moves on from that point (:meth:`GestureEnd._moved_on`),
#: anchored there, and the next gesture is followed afresh, not on the old sums. Only where the
#: template was followed to its end in step (its progress the sample before at least
#: ``TEMPO_END_FROM``, below ``end``); the ended template is shown at its end until the next
#: gesture engages. ``bench/follow_seeds.py --sections=sized,unrelated,sequences`` 101-112: twenty
#: within 20% 104 0.313 -> 0.344, 107 0.281 -> 0.313, 109 0.188 -> 0.219 (the getup at 0.18 of
#: it), longest wrong run 109 4 -> 3, all else unchanged; ``bench/follow_quality.py``: held-out
#: after a stroke recognised 0.333 -> 0.375, all else unchanged. Measured and not kept: without
#: the in-step condition a leap to a spinkick's end on a mirrored dance restarted it and let a
#: zigzag drive (unrelated valid share mean 0.00967 -> 0.00998); without the ended template
#: shown, a bent jump never valid, the input moving on at 0.97 of it, showed 0.02 (held-out bent
#: 5% progress RMSE median 0.02346 -> 0.02359).
UNSEEN_END = True
#: An attempt begun at an end read as a return (:meth:`GestureEnd._returned`), nothing driven since,
#: is anchored again at the mean of its last ``still_samples`` samples where the input comes to rest
#: (:func:`~behaviors.mop.tempo.resting`) farther than this many still radii from its anchor (0:
#: never; follower and group, ``member_spotting.spot``). A return is read where the input passes the
#: template's last point, often at speed: held-out seed 106's dance ankle, followed back down its
#: path, was ended at 0.905 of it and the wave's attempt anchored 13 mm from where the wave began at
#: rest; a crawl ankle (size 0.63) drove 4 ticks of the wave, recognised at 0.717.
#: ``bench/follow_seeds.py --sections=sized,unrelated,sequences`` (101-106): twenty templates'
#: longest wrong run 106 4 -> 3, within 20% 104 0.344 -> 0.375, 106 0.250 -> 0.281 (the wave at
#: 0.263); every other figure identical, and on 107-112 and in ``bench/follow_quality.py``. Traced
#: and not kept: after any end (not only a return), a cartwheel ankle's own start, 5 mm out then a
#: rest, was anchored again there and recognised at 0.384 (0.290; 106's twelfth sequence).
REANCHOR_RADII = 4.0


def arrived(recent: list[np.ndarray], radius: np.ndarray) -> int:
    """How many samples before the last of ``recent`` (oldest first) lie, with it, within
    ``radius`` (range per column, raw units): the samples the input has already stood there,
    at most :data:`END_GRACE`."""
    n = 0
    while n < min(END_GRACE, len(recent) - 1):
        a = np.array(recent[-n - 2:])
        if not np.all(a.max(axis=0) - a.min(axis=0) <= radius):
            break
        n += 1
    return n


def drives(run: np.ndarray | int, confirm: np.ndarray | int,
           after_end: np.ndarray | int) -> np.ndarray | bool:
    """Whether an action drives (``valid``), per follower or for arrays of them: it matched for
    ``confirm`` samples in a row (``run``), and reached its end at most :data:`END_GRACE`
    samples ago (``after_end``: samples since the end was reached, 0 while it was not)."""
    return (run >= confirm) & (after_end <= END_GRACE)


class GestureEnd:
    """Mixin of :class:`~behaviors.mop.follower.ActionFollower` (through
    :class:`~behaviors.mop.spotting.GestureSpotting`): where a gesture ended and the next
    begins."""

    def _last_point(self, k: int) -> np.ndarray:
        """Template ``k``'s last point at its estimated size, from the anchor (raw units)."""
        b = self.bank
        return (self._rel[b.starts[k] + b.lengths[k] - 1] * self._units * self._size[k]
                + self._anchor)

    def _next_anchor(self, x: np.ndarray, k: int) -> np.ndarray:
        """Where the gesture after template ``k``'s (ended, the input now at ``x``) begins: where
        its end was reached, or its last point (as :meth:`_moved_on` takes it) while the input
        was still coming closer to it (the follower reached ``end`` before the performer)."""
        last = self._end_last
        if np.sum((x - last) ** 2) < np.sum((self._end_x - last) ** 2):
            return last
        return self._end_x

    def _departed(self, x: np.ndarray, k: int, distance: float) -> bool:
        """The input left the point where template ``k`` reached its end by ``distance`` sigmas
        (RMS per column, in the template's spread and size)."""
        r = (x - self._end_x) / (self.bank.scale[k] * self._size[k])
        return bool(np.mean(r * r) >= (distance * self.sigma) ** 2)

    def _moved_on(self, x: np.ndarray, k: int, end_x: np.ndarray | None = None,
                  last: np.ndarray | None = None) -> bool:
        """The input moved on from where template ``k`` reached its end: it is farther from the
        template's last point (at the estimated size, from the anchor) than when the end was
        reached, by more than the jitter of a still input (:data:`MOVE_RADII` in a column), so
        the next gesture has begun; the slow final approach to the last point is not moving on.
        ``end_x``, ``last``: another end and its last point (a gesture never recognised,
        :data:`UNSEEN_END`); by default the end reached.
        The template's own onset (0.1 of its spread) let the last action drive the first 13% of
        the next gesture (whose start is slow), and anchored that one too late to be followed.
        The last point is taken where the end was reached (``_end_last``): the size estimate goes
        on adapting to the next gesture, and the point moved with the input (a wave's, at 1.19x
        to 1.24x, along a square's first side until 0.16 of it; the square, anchored there, was
        never recognised). Measured on ``bench/motions.back_to_back``'s six gestures, seeds
        0-39 (240 gestures; the bench's own draws unchanged): never recognised 2 -> 0.
        :data:`MOVE_RADII` 3 -> 2 (``bench/follow_quality.py``, tuned / held-out): twenty
        templates back to back, median recognition 0.303 / 0.236 -> 0.258 / 0.236, longest
        wrong run 3 / 11 -> 2 / 11; six gestures the same but the wave 0.247 -> 0.246 and the
        held-out circle 0.282 -> 0.280; valid after 30% of gestures at 0.7-1.4x 0.9005 / 0.9023
        -> 0.9005 / 0.9014, holds valid after 30% 0.958 / 0.965 -> 0.958 / 0.963, unrelated
        unchanged; seeds 0-39 above: a line's 5 ticks on a square begun late gone. 1.5: sized
        0.9002 / 0.9008, too near the 0.9 target."""
        end_x = self._end_x if end_x is None else end_x
        last = self._end_last if last is None else last
        return bool(np.any(np.abs(x - last)
                           > np.abs(end_x - last) + MOVE_RADII * self._still_radius))

    def _returned(self, x: np.ndarray, k: int, progress: float) -> bool:
        """The input came back to template ``k``'s last point (within :data:`RETURN_RADIUS` of
        its extent, at the estimated size, from the anchor) while its followed progress slid back
        by :data:`RETURN_BACK` from its peak since it became best: a return followed backwards
        along the outward stroke (a line's out-and-back at another size and tempo) whose end the
        progress would never reach.
        Measured and not kept: only where the input arrives there (its last step within 4 or 8
        still radii in every column; follower and compiled group alike). Held-out seed 106's dance
        ankle, followed back down its path (0.53 -> 0.24 while its performer went on, 0.61 ->
        0.905), passed its last point at 20-29 mm a sample and was ended there, so the wave
        after it was anchored four samples before it began and a crawl ankle drove 4 ticks of it.
        ``bench/follow_seeds.py --sections=sequences`` (101-112), twenty templates: 106's longest
        wrong run 4 -> 3, within 20% 0.25 -> 0.281 (at 4 also 104's 0.313 -> 0.344), every other
        figure unchanged; ``bench/follow_quality.py`` identical at 8 (every figure), at 4 sized
        and holds identical but unrelated motions among twenty valid 0.0082 -> 0.0089 of the time
        (mean; over all 0.0105 -> 0.0109); and at either ``tests/mop/test_threshold_lead.py``'s
        mirrored spin ankle no longer restarts part way: the backflip wrist followed back over it
        passes its last point at speed, and the new attempt the test's threshold model is carried
        into never begins. The attempt begun at a return is anchored again where the input comes
        to rest (:data:`REANCHOR_RADII`)."""
        if self._peak - progress < RETURN_BACK:
            return False
        r = (x - self._last_point(k)) / self._units
        return bool(np.sqrt(np.sum(r * r)) <= RETURN_RADIUS * self._size[k] * self._extent[k])

    def _arrived(self) -> int:
        """Samples the input has already stood where it is (its last recent sample), at most
        :data:`END_GRACE`: the samples before it that lie, with it, within :data:`ARRIVE_RADIUS`
        still radii (range per column, as :meth:`_still` measures)."""
        return arrived(self._recent_x, ARRIVE_RADIUS * self._still_radius)
