"""Threshold model: what an action must explain better than before it may drive.

In the spirit of Lee & Kim's HMM threshold model (a garbage model built from the gesture
models' own states), a follower keeps one more model beside its templates: an *ergodic* model
over every state of every loaded template, each state keeping the templates' self weight and
jumping to any state (of any template, uniformly) otherwise. It sees the live sample as every
template does (each in its own map and size), with the same Gaussian, so it explains any path
stitched from pieces of the templates in any order, but pays for every jump what the ordered
templates do not. Its per-sample log-likelihood is summed with the evidence's forgetting and
enters the probabilities as one more, never driving, competitor: an action drives only while
its probability, the threshold model counted, is at least ``min_probability``.

A still input is no evidence either way: the threshold model's state simply stays where the
sample is while an ordered template's prior moves on (a performer pausing mid-gesture), so while
the input has not moved by :data:`STILL_RADII` still radii since the last sample the threshold
model's log-likelihood is at most the best template's.

Measured with ``bench/follow_quality.py``'s sized and unrelated sections (its own random
stream; tuned figures, held-out joints in brackets; "unrelated" = worst / mean valid share over
every motion and 1, 6 and 20 templates; "after 30%" = valid after 30% of gestures at 0.7-1.4x):

=====================================================  =================  =================
threshold model                                        unrelated          after 30%
=====================================================  =================  =================
none (before)                                          0.49 / 0.188       0.908 (0.893)
                                                       (0.60 / 0.200)
ergodic over all templates, still input no evidence    0.43 / 0.153       0.908 (0.893)
  (kept; ``threshold`` 0)                              (0.60 / 0.160)
  same, the threshold model 0.25 nats/sample stronger  0.36 / 0.135       0.905 (0.890)
                                                       (0.58 / 0.142)
  same, 0.5 nats stronger                              0.30 / 0.117       0.897
ergodic, a still input counted                         0.38 / 0.139       0.899
  same, 1 nat stronger                                 0.15 / 0.035       0.760
  same, 0.5 / 1 nat weaker                             0.46 / 0.170       0.905
                                                       0.49 / 0.181       0.908
memoryless (every state, no stay)                      0.49 / 0.186
one per template, its own states only (a per-template  0.46 / 0.172
likelihood ratio, independent of the others)
=====================================================  =================  =================

No share got worse with it; it gained most with twenty templates loaded (a wander 0.47 ->
0.34, a triangle 0.43 -> 0.33, mirrored mocap paths 0.17-0.32 -> 0.04-0.15). Counting a still
input, a performer pausing mid-gesture lost the action (a run's wrist at 1.2x, paused 0.7 s:
valid after 30% 1.0 -> 0.53). Stronger, it costs gestures whose start is shared by several
templates (a 0.7x square, wave, figure eight), whose probability it takes while the templates
split theirs. What it cannot refuse: a path that *is* one template's stretch in that template's
order (the mirrored line's return is the line's outward stroke, then held; a triangle's first
stroke the line's) -- there the ordered template explains the input better than any stitching.

Mirror chains: a template drawn mirrored (x -> -x about its first state, in its own frame: a left
hand doing a right hand's gesture) is followed by some other template's stretch within its
spread, and the ergodic states cannot explain it better, since each of their jumps costs about
ln(N / 0.7) nats (7 with twenty templates) where an ordered template pays about 1. So the model
also holds each template's mirror image as an ordered chain: its weight moves on by
:data:`MIRROR_MOVES`, keeps :data:`MIRROR_KEEP` along the chain per sample (the rest jumps as the
ergodic states' does) and enters only at the chain's first state, where a performance of it
begins (:func:`threshold_model_step`). The group's pass costs about 0.1 ms more per tick
(``bench/mop.py --design``, adjacent runs at load 8-10: 0.808 -> 0.905 and 0.875 -> 0.973 ms
median). Measured on the mirrored paths among twenty (``bench/follow_widened.py``, tuned joints,
seeds 201-210: worst / mean valid share, performances over 0.1 of 540) and
``bench/follow_quality.py`` (tuned; valid after 30% at 0.7-1.4x, bent 10%), "entered anywhere"
meaning jumps land on every chain state too:

=============================================  ===========================  ======  =======
threshold model                                mirrored among twenty        after   bent
                                                                            30%     10%
=============================================  ===========================  ======  =======
ergodic only (before)                          0.239 / 0.0145 / 22          0.9157  0.6315
mirror states, ergodic (jumps to each)         0.310 / 0.0135 / 16
chains entered anywhere, keep 0.9              0.219 / 0.0062 / 4           0.9070
chains entered at their start, keep 0.9        0.228 / 0.0070 / 8           0.9128
  keep 0.7                                     0.228 / 0.0086 / 10          0.9145  0.6013
  keep 0.5 (kept)                              0.228 / 0.0100 / 11          0.9150  0.6315
  keep 0.3                                     0.296 worst (the dance       0.9157  0.6315
                                               wrist at 0.7x)
=============================================  ===========================  ======  =======

Entered anywhere, chains took true gestures part way (a wave at 0.85x: valid after 30% 1.0 ->
0.82); entered at their start, a chain still takes a true performance whose stretch another
template's mirror image shares (a punch wrist at 1.4x by the roll ankle's, 0.90 -> 0.80 at keep
0.9), the less the less weight it keeps. Keep 0.7 cost shapes bent by 10% (0.6315 -> 0.6013);
0.3 let the zigzag take the mirrored dance wrist longer. Sequences back to back unchanged
throughout.

Across a new attempt: spotting starts one where an action ends (a template followed back over
itself too, valid or not) or every template is refused, and the templates' evidence starts
afresh there. The threshold model starts afresh with it but for its lead over the best template
(:meth:`~behaviors.mop.threshold_lead.ThresholdLead._threshold_lead`), while its mirror chains hold
:data:`CARRY_CHAINED` of its weight; none when it is behind, so a gesture after a gesture starts
afresh. Afresh, a mirrored path loses what its chain had explained:
the spin ankle mirrored at 1.4x (seed 203), the chain 73 nats ahead, the backflip wrist followed
back over itself ends about 60% along, and the walk ankle drove 0.228 of the rest. Measured
(``bench/follow_widened.py``, mirrored among twenty, worst / mean / over 0.1 of 540; sequences
back to back, runs over 2 summed; ``bench/follow_quality.py``'s tuned keys):

===============================================  ===========================  =========
threshold model at a new attempt                 mirrored among twenty        sequences
===============================================  ===========================  =========
afresh                                           0.228 / 0.00996 / 11         46
its lead carried, any                            0.162 / 0.00742 / 3          46
its lead carried while the chains hold 0.5       0.162 / 0.00747 / 3          46
  (kept)
chains going on in their own frame (anchor and   0.228 at seed 203 (26 of
  sizes kept while they hold 0.5 of the weight,  114 ticks, as afresh)
  until under 0.01), lead not carried
both                                             0.162 / 0.00688 / 2          46
===============================================  ===========================  =========

With the lead carried, 137 of ``bench/follow_quality.py``'s 144 tuned keys stayed the same (sized
valid after 30% 0.9150, holds, after, pauses, shapes, sequences); the rest are unrelated motions
refused more: worst 0.0681 -> 0.0649, mean 0.0143 -> 0.0131; among twenty templates the mirrored
worst 0.0681 -> 0.0406, the mean over every motion 0.0128 -> 0.0107 (held out, checked once: worst
0.247 unchanged, mean 0.0265 -> 0.0258). It costs the tick nothing but a maximum over a member's
evidence and a sum of its chains' weights when its new attempt starts. Chains in their own frame
follow the spin ankle's rest (holding 0.3-0.94 of the weight) but the walk ankle explains that
stretch better by 10-13 nats (a chain keeps :data:`MIRROR_KEEP` per sample, 0.69 nats); with the
lead carried too they gained only a mean of 0.0005, for a frame per member and a second distance
per chain state in the group kernel: not kept. Any lead carried, one held by the ergodic states
too, took gestures performed back to back without a pause (``tests/mop/test_follower.py``'s four
random templates per member at 1.3x, twice over): valid ticks 114 -> 68, the lead won while the
input jumped to the next gesture carried into it; carried only while the chains hold half the
weight, 114 as afresh. Left: the mirrored figure eight at 0.7x driven by the dance wrist 0.16 of
the time (the chain's keep), the mirrored crawl wrist at 1x by the circle 0.114.

The held-out worst (0.247: the punch's left ankle mirrored among twenty templates, valid 0.05,
0.342 and 0.349 of the time at 0.7, 1 and 1.4x) is no failure of the chains: that mirror image is
the line drawn out 15 cm, held at its far end (3 cm back, a little forward) and taken three
quarters of the way back, 4.5 cm from the line at equal phase but 1.15 cm once aligned in time.
Traced at 1.4x (83 samples; no new attempt began after its onset, so no restart reset the threshold
model): over the outward stroke the punch ankle's chain takes 0.97-0.99 of the threshold model's
weight but explains the stroke no better than the line, which leads it by about 10 nats midway
(samples 22-30) and 5 at the far end (the chain pays ln 2 per sample for its keep); the line drives
from progress 0.35 (sample 27) through its hold at 0.60-0.62; when the input goes back within the
hold the chain overtakes (sample 51, the templates' kept share 0.58 -> 0.0003 by sample 58) and
refuses the return (progress 0.62 -> 0.78); decaying in the final rest (the still input no
evidence) it lets the line drive again at 0.78 (sample 78 on). At 1x the same: the line from 0.43
(sample 33) to 0.64, again in the rest. Every valid tick has the line drawn, held or taken back, as
the raise-hold-return target asks; refusing it would refuse the line held. So
``bench/follow_quality.py`` no longer counts a mirror image within a tenth of the extent of another
template once aligned in time (``bench.motions.mirror_copies``): the mirrored line held out goes
too (0.191, the punch ankle driving it: the same pair), and the dance's right ankle (the walk's
left wrist, 0.0094 apart). Held out, worst 0.247 -> 0.138, mean 0.0258 -> 0.0151 (seed 102: 0.105 /
0.0144, 103: 0.136 / 0.0172); the tuned figures stay the same (no mirror image that close). What is
left worst on those seeds is the diagonal (among six gestures at 0.7x the figure eight's first
stroke, held at 0.22-0.28 of it; among twenty, 0.105-0.136), not a mirror image, and seed 103's
mirrored square at 1.4x (0.169; the roll ankle's first half, :mod:`behaviors.mop.refusal`).

Only the mirror in x is held. Chains for the mirror in y, in both axes and the drawing backwards
(``bench/follow_widened.py --forms=y,xy,r``; each form's distances read once, chain states under
e^-10 of one jump's weight dropped) refused their own forms a little: worst among twenty 0.127 ->
0.125 in y, 0.151 -> 0.131 in both, 0.324 -> 0.315 backwards (means 0.0101 -> 0.0069, 0.0110 ->
0.0085, 0.0274 -> 0.0240), sized 0.9150 -> 0.9143, but took the group tick
(``bench/mop.py --design``, 100 templates x 8 performers, quiet, alternating) from 0.72 to 0.88 ms
median and 1.11 to 1.32 ms p99, most of DESIGN's 1 ms left; not kept.
"""

from __future__ import annotations

import numpy as np

from behaviors.kernel_cache import compiled

# numba's ``njit(cache=True, nogil=True)`` in the shared cache (see tabletop.drawing.dirty.KERNEL)
KERNEL = compiled(None, error_model="python")

#: Self weight of every state of the threshold model (the templates' own ``transitions[0]``).
STAY = 0.3
#: Moving by less than this (in still radii, any column) since the last sample counts as still.
STILL_RADII = 2.0
#: A new attempt's threshold model starts with its lead over the templates, if any (see the
#: module docstring); False: afresh, as the templates.
CARRY_LEAD = True
#: ... only while the mirror chains hold at least this share of its weight (see the module
#: docstring).
CARRY_CHAINED = 0.5


#: The threshold model's states, log-densities and weights are kept in single precision (its
#: sums and its log-likelihood in double): it only weighs the templates against any stitching of
#: them, its log-likelihood within about 1e-6 of the double-precision one's, and its pass over
#: every state (the group's :func:`~behaviors.mop.threshold_kernel.threshold_step`) the tick's
#: largest after the forward step. See :mod:`behaviors.mop.threshold_kernel` for the figures.
PRECISION = np.float32


#: Weight each mirror chain's state keeps along its chain per sample (the rest jumps to any
#: state, as the ergodic states' ``1 - STAY`` does); see the module docstring.
MIRROR_KEEP = 0.5
#: A mirror chain's state weighing less than this (against the whole model's 1) weighs nothing:
#: weight fading down a chain reaches single precision's subnormal numbers, whose rounding
#: differs between the follower's and the group's code.
TINY = np.float32(1e-30)
#: How a mirror chain's weight moves along it per sample: stays, 1, 2, 3 states on (the
#: forward's default transitions).
MIRROR_MOVES = (0.3, 0.35, 0.25, 0.1)


def mirrored_column(z: np.ndarray, first: np.ndarray) -> np.ndarray:
    """``z`` (K, d) with one more column: its first coordinate mirrored about each template's
    first state ``first`` (K, d), as each template's mirror chain sees the sample."""
    return np.ascontiguousarray(np.hstack([z, 2.0 * first[:, :1] - z[:, :1]]))


@KERNEL
def threshold_model_step(z: np.ndarray, means: np.ndarray, lengths: np.ndarray, sigma: float,
                         log_constant: float, log_jacobian: np.ndarray, alpha: np.ndarray,
                         scratch: np.ndarray, fresh: bool, stay: float) -> float:
    """One step of the threshold model, in place on its state ``alpha`` (2N,: the ergodic
    states', then each template's mirror chain's); returns the sample's log-likelihood ``log
    sum_j prior_j b_j``. The ergodic prior is ``stay * alpha_j + r``, a chain state's
    ``MIRROR_KEEP * sum_t MIRROR_MOVES[t] alpha_{j-t}`` (within its chain) plus ``r`` at its
    first state, where ``r`` is the weight that left every state shared among the N ergodic
    states and the K chains' first ones. Fresh, that weight lies on those states evenly.
    ``z`` (K, d + 1): the sample in each template's standardised units, its last column the
    first coordinate mirrored (:func:`mirrored_column`); ``means`` (N, d): the states, template
    after template, ``lengths`` (K,) states each; ``log_jacobian`` (K,): each map's log |dz /
    dx|; ``scratch`` (2N,): room for the log-densities. ``means``, ``alpha`` and ``scratch``
    are of :data:`PRECISION`, and so is the arithmetic on them (the weights' sum in double
    precision)."""
    k_count = z.shape[0]
    d = z.shape[1] - 1
    n = means.shape[0]
    f32 = np.float32
    inv = f32(-0.5 / (sigma * sigma))
    floor = f32(-40.0)
    top = f32(-np.inf)
    j = 0
    for k in range(k_count):
        lj = f32(log_constant + log_jacobian[k])
        for _ in range(lengths[k]):
            s = f32(0.0)
            for c in range(1, d):
                diff = f32(z[k, c]) - means[j, c]
                s += diff * diff
            e0 = f32(z[k, 0]) - means[j, 0]
            m0 = f32(z[k, d]) - means[j, 0]
            v = (e0 * e0 + s) * inv + lj
            vm = (m0 * m0 + s) * inv + lj
            scratch[j] = v
            scratch[n + j] = vm
            top = max(top, max(v, vm))
            j += 1
    entries = n + k_count   # where the jumps land: every ergodic state, each chain's first
    if fresh:
        _entry_weights(alpha, lengths, n, entries)
    chained = 0.0
    for j in range(n, 2 * n):
        chained += alpha[j]
    rest = f32(((1.0 - stay) * (1.0 - chained) + (1.0 - MIRROR_KEEP) * chained) / entries)
    keep, kc = f32(stay), f32(MIRROR_KEEP)
    w0, w1, w2, w3 = (f32(MIRROR_MOVES[0]), f32(MIRROR_MOVES[1]), f32(MIRROR_MOVES[2]),
                      f32(MIRROR_MOVES[3]))
    total = 0.0
    for j in range(n):
        e = scratch[j] - top
        if e < floor:   # under 4e-18 of the likeliest state: no exp (most states are far)
            alpha[j] = 0.0
            continue
        w = (keep * alpha[j] + rest) * np.exp(e)
        alpha[j] = w
        total += w
    first = n
    for k in range(k_count):
        for p in range(lengths[k] - 1, -1, -1):   # downwards: each reads the ones before it
            j = first + p
            moved = w0 * alpha[j]
            if p >= 1:
                moved += w1 * alpha[j - 1]
            if p >= 2:
                moved += w2 * alpha[j - 2]
            if p >= 3:
                moved += w3 * alpha[j - 3]
            e = scratch[j] - top
            if e < floor:
                alpha[j] = 0.0
                continue
            w = (kc * moved + (rest if p == 0 else f32(0.0))) * np.exp(e)
            w = w if w >= TINY else f32(0.0)   # (no subnormal weights down the chain)
            alpha[j] = w
            total += w
        first += lengths[k]
    if total <= 0.0:   # the likeliest states only chain states no weight reached: afresh
        _entry_weights(alpha, lengths, n, entries)
        return float(top + floor)
    for j in range(2 * n):
        alpha[j] = alpha[j] / total
    return float(top) + np.log(total)


@KERNEL
def _entry_weights(alpha: np.ndarray, lengths: np.ndarray, n: int, entries: int) -> None:
    """The threshold model's weights afresh, in place: even on the ``n`` ergodic states and
    each mirror chain's first (``entries`` of them), none on the chains' other states."""
    alpha[:] = 0.0
    alpha[:n] = np.float32(1.0 / entries)
    first = n
    for k in range(lengths.size):
        alpha[first] = np.float32(1.0 / entries)
        first += lengths[k]


def gated(step: float, best_step: float, x: np.ndarray, previous: np.ndarray | None,
          still_radius: np.ndarray) -> float:
    """The threshold model's step, at most ``best_step`` (the best template's) while the input
    stayed within :data:`STILL_RADII` still radii of the ``previous`` sample."""
    if previous is None or not np.any(np.abs(x - previous) > STILL_RADII * still_radius):
        return min(step, best_step)
    return step
