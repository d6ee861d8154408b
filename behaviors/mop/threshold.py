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
:data:`CHAIN_MOVES`, keeps :data:`CHAIN_KEEP` along the chain per sample (the rest jumps as the
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
throughout. Left: the walk ankle followed back over itself on the mirrored spin ankle at 1.4x
(0.228), as before.

Chain forms (:data:`CHAINS`): beside the mirror in x, each template's mirror in y, in both (a
half turn about its first state) and its drawing backwards (its states from last to first,
begun at the anchor), each an ordered chain as above. A form's chain sees the sample mirrored or
moved, not its own states, so the group reads each template's states once for all forms
(:mod:`behaviors.mop.threshold_kernel`). Measured on tuned figures only: the mirrored paths among
twenty as above; each template drawn in another form among twenty (``bench/follow_widened.py
--forms=y,xy,r``, seeds 201-205, 0.7, 1 and 1.4x: worst / mean / over 0.1 per form, of 240, 270
and 285 performances); ``bench/follow_quality.py --sections=sized,unrelated,holds`` (valid after
30% at 0.7-1.4x; unrelated worst / mean; holds' figures the same in every row):

================  ===============  ===============  ===============  ======  =============
chains            mirrored (x)     y                xy               after   unrelated
                  among twenty     among twenty     among twenty     30%
================  ===============  ===============  ===============  ======  =============
x only            0.228/0.0100/11  0.127/0.0101/7   0.151/0.0110/2   0.9150  0.0681/0.0143
x, y, xy, r       0.228/0.0101/11  0.125/0.0069/6   0.131/0.0085/1   0.9143  0.0681/0.0143
  (kept)
  keep 0.7        0.228/0.0086/10  0.125/0.0064/5   0.092/0.0055/0   0.9136  0.0649/0.0139
  keep 0.9        0.228/0.0069/8   0.113/0.0054/3   0.091/0.0035/0   0.9099  0.0649/0.0126
================  ===============  ===============  ===============  ======  =============

Backwards: 0.324 / 0.0274 / 24 with the x chains only, 0.315 / 0.0240 / 22 with all four,
0.296 / 0.0209 / 21 at keep 0.7, 0.287 / 0.0177 / 18 at keep 0.9. With x and y
only, or x and xy, or x and r, the mirrored-in-x figures stayed the same (0.228 / 0.0100 / 11;
after 30% 0.9150, 0.9150, 0.9143): a form's chains refuse that form and little else, so they
leave the mirrored paths where they were (what limits those: a chain keeps half its weight a
sample where the template explains the input as well within its spread, and a chain sees the
sample at its template's size, estimated for the template, not its mirror image; and a
performance spotting begins anew midway -- the spin ankle's -- no chain begun at the anchor
explains). Keep 0.7 or 0.9 refused more of every form but cost shapes bent by 10% (0.6315 ->
0.6007, 0.6001), and at 0.9 bent by 5% (0.8741 -> 0.8526) and after 30% -0.005; not taken.
What the chains drawn backwards leave: the punch wrist drawn backwards is the punch again (out
and back), followed by it and the circle (0.30); the run wrist backwards at 0.7x by the
cartwheel (0.21-0.24), its chain's size the run's own estimate (0.8 where 0.7 was drawn).
Every other figure of ``bench/follow_quality.py`` (tuned) stayed the same (106 keys but the
sized ones: 0.6-1.5x 0.7585 -> 0.7581). Held out, checked once at the end: the mirrored
template among twenty 0.247 -> 0.247 (the mirror in x, whose chains did not change). The
group's tick (``bench/mop.py --design``, alternating with the chains in x only, load 4-5): 0.918,
0.922 -> 0.922, 0.904 ms median, CPU p99 1.38, 1.41 -> 1.53, 1.44 ms, its chains left with no
weight costing one distance (:data:`CHAIN_LEAST`; the figures above the same with it).
"""

from __future__ import annotations

import numba
import numpy as np

#: Self weight of every state of the threshold model (the templates' own ``transitions[0]``).
STAY = 0.3
#: Moving by less than this (in still radii, any column) since the last sample counts as still.
STILL_RADII = 2.0


#: The threshold model's states, log-densities and weights are kept in single precision (its
#: sums and its log-likelihood in double): it only weighs the templates against any stitching of
#: them, its log-likelihood within about 1e-6 of the double-precision one's, and its pass over
#: every state (the group's :func:`~behaviors.mop.threshold_kernel.threshold_step`) the tick's
#: largest after the forward step. See :mod:`behaviors.mop.threshold_kernel` for the figures.
PRECISION = np.float32


#: Weight each chain's state keeps along its chain per sample (the rest jumps to any
#: state, as the ergodic states' ``1 - STAY`` does); see the module docstring.
CHAIN_KEEP = 0.5
#: A chain's state weighing less than this (against the whole model's 1) weighs nothing:
#: weight fading down a chain reaches single precision's subnormal numbers, whose rounding
#: differs between the follower's and the group's code.
TINY = np.float32(1e-30)
#: A chain's state weighing less than this share of the weight one jump brings to a state
#: (e^-10) weighs nothing either, so a chain left with none costs one distance a sample, not its
#: template's: in DESIGN's case (``bench/mop.py --design``'s group, 800 templates) 48 % of the
#: chains held some weight at a tick with :data:`TINY` as the least, 30 % with e^-20, 18 % with
#: e^-10 (the group's tick, hot: 1.00, 0.80, 0.73 ms with four chain forms; 0.60 with the x
#: chains alone and :data:`TINY`). No figure of the study below moved with it.
CHAIN_LEAST = np.float32(np.exp(-10.0))
#: How a chain's weight moves along it per sample: stays, 1, 2, 3 states on (the
#: forward's default transitions).
CHAIN_MOVES = (0.3, 0.35, 0.25, 0.1)


#: The threshold model's chains: each template's image in each of these forms, held as an ordered
#: chain (see the module docstring): "x" mirrored x -> -x about its first state, "y" y -> -y,
#: "xy" both; "r" drawn backwards (from its last state to its first, begun where the performance
#: begins).
CHAINS: tuple[str, ...] = ("x", "y", "xy", "r")


def chain_forms(dims: int, chains: tuple[str, ...] = CHAINS) -> tuple[np.ndarray, np.ndarray]:
    """Each chain form's sign of each of ``dims`` coordinates (C, dims) and whether it runs
    backwards (C,)."""
    signs = np.ones((len(chains), dims))
    for c, kind in enumerate(chains):
        for axis, name in enumerate("xy"):
            if name in kind and axis < dims:
                signs[c, axis] = -1.0
    return signs, np.array(["r" in kind for kind in chains], dtype=np.bool_)


@numba.njit(cache=True, nogil=True)
def threshold_model_step(z: np.ndarray, first: np.ndarray, last: np.ndarray, means: np.ndarray,
                         lengths: np.ndarray, signs: np.ndarray, backward: np.ndarray,
                         sigma: float, log_constant: float, log_jacobian: np.ndarray,
                         alpha: np.ndarray, scratch: np.ndarray, fresh: bool, stay: float,
                         chain_keep: float) -> float:
    """One step of the threshold model, in place on its state ``alpha`` ((1 + C) N,: the
    ergodic states', then each chain form's, each chain's states in its template's order);
    returns the sample's log-likelihood ``log sum_j prior_j b_j``. The ergodic prior is ``stay *
    alpha_j + r``, a chain state's ``chain_keep * sum_t CHAIN_MOVES[t] alpha_{j-t}`` (within
    its chain; ``j+t`` for one running backwards) plus ``r`` at the state where it begins
    (its template's first, or last), where ``r`` is the weight that left every state shared
    among the N ergodic states and the C K chains' beginnings. Fresh, that weight lies on
    those states evenly. A chain of form ``c`` sees the sample as ``signs[c] * (z - first) +
    o``, ``o`` its template's ``last`` state if it runs ``backward``, else its ``first``: its
    template mirrored about its first state, and run backwards begun at the anchor. ``z`` (K,
    d): the sample in each template's standardised units; ``means`` (N, d): the states,
    template after template, ``lengths`` (K,) states each; ``log_jacobian`` (K,): each map's
    log |dz / dx|; ``scratch`` ((1 + C) N,): room for the log-densities. ``means``,
    ``alpha`` and ``scratch`` are of :data:`PRECISION`, and so is the arithmetic on them (the
    weights' sum in double precision)."""
    k_count, d = z.shape
    n = means.shape[0]
    c_count = signs.shape[0]
    f32 = np.float32
    inv = f32(-0.5 / (sigma * sigma))
    floor = f32(-40.0)
    top = f32(-np.inf)
    zc = np.empty(d, dtype=np.float32)
    for c in range(c_count + 1):
        j = 0
        for k in range(k_count):
            length = lengths[k]
            for col in range(d):   # the sample as this form of the template sees it
                zc[col] = f32(z[k, col]) if c == 0 else f32(
                    signs[c - 1, col] * (z[k, col] - first[k, col])
                    + (last[k, col] if backward[c - 1] else first[k, col]))
            lo, hi = j, j + length
            if c > 0 and not fresh and not np.any(alpha[c * n + j:c * n + hi] > 0.0):
                # a chain holding no weight can take some only where it begins: its other
                # states are left out (of the likeliest too)
                scratch[c * n + j:c * n + hi] = -np.inf
                lo = j + (length - 1 if backward[c - 1] else 0)
                hi = lo + 1
            lj = f32(log_constant + log_jacobian[k])
            for i in range(lo, hi):
                s = f32(0.0)
                for col in range(d):
                    diff = zc[col] - means[i, col]
                    s += diff * diff
                v = s * inv + lj
                scratch[c * n + i] = v
                top = max(top, v)
            j += length
    entries = n + c_count * k_count   # where the jumps land: every ergodic state, chains' first
    if fresh:
        _entry_weights(alpha, lengths, backward, n, entries)
    chained = 0.0
    for j in range(n, alpha.size):
        chained += alpha[j]
    rest = f32(((1.0 - stay) * (1.0 - chained) + (1.0 - chain_keep) * chained) / entries)
    keep, kc = f32(stay), f32(chain_keep)
    least = max(TINY, rest * CHAIN_LEAST)   # a chain's state weighing less weighs nothing
    w0, w1, w2, w3 = (f32(CHAIN_MOVES[0]), f32(CHAIN_MOVES[1]), f32(CHAIN_MOVES[2]),
                      f32(CHAIN_MOVES[3]))
    total = 0.0
    for j in range(n):
        e = scratch[j] - top
        if e < floor:   # under 4e-18 of the likeliest state: no exp (most states are far)
            alpha[j] = 0.0
            continue
        w = (keep * alpha[j] + rest) * np.exp(e)
        alpha[j] = w
        total += w
    for c in range(1, c_count + 1):
        first_j = c * n
        back = backward[c - 1]
        for k in range(k_count):
            length = lengths[k]
            for i in range(length):   # each reads the ones before it along the chain, not yet
                p = i if back else length - 1 - i   # updated: from the chain's far end
                j = first_j + p
                step = 1 if back else -1   # the states before it: further on in its template
                moved = w0 * alpha[j]
                if 0 <= p + step < length:
                    moved += w1 * alpha[j + step]
                if 0 <= p + 2 * step < length:
                    moved += w2 * alpha[j + 2 * step]
                if 0 <= p + 3 * step < length:
                    moved += w3 * alpha[j + 3 * step]
                e = scratch[j] - top
                if e < floor:
                    alpha[j] = 0.0
                    continue
                begins = p == (length - 1 if back else 0)
                w = (kc * moved + (rest if begins else f32(0.0))) * np.exp(e)
                w = w if w >= least else f32(0.0)   # (CHAIN_LEAST; no subnormal weights)
                alpha[j] = w
                total += w
            first_j += length
    if total <= 0.0:   # the likeliest states only chain states no weight reached: afresh
        _entry_weights(alpha, lengths, backward, n, entries)
        return float(top + floor)
    for j in range(alpha.size):
        alpha[j] = alpha[j] / total
    return float(top) + np.log(total)


@numba.njit(cache=True, nogil=True)
def _entry_weights(alpha: np.ndarray, lengths: np.ndarray, backward: np.ndarray, n: int,
                   entries: int) -> None:
    """The threshold model's weights afresh, in place: even on the ``n`` ergodic states and
    the state where each chain begins (``entries`` of them), none on the chains' others."""
    alpha[:] = 0.0
    alpha[:n] = np.float32(1.0 / entries)
    for c in range(backward.size):
        first = (c + 1) * n
        for k in range(lengths.size):
            alpha[first + (lengths[k] - 1 if backward[c] else 0)] = np.float32(1.0 / entries)
            first += lengths[k]


def gated(step: float, best_step: float, x: np.ndarray, previous: np.ndarray | None,
          still_radius: np.ndarray) -> float:
    """The threshold model's step, at most ``best_step`` (the best template's) while the input
    stayed within :data:`STILL_RADII` still radii of the ``previous`` sample."""
    if previous is None or not np.any(np.abs(x - previous) > STILL_RADII * still_radius):
        return min(step, best_step)
    return step
