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


@numba.njit(cache=True, nogil=True)
def threshold_model_step(z: np.ndarray, means: np.ndarray, lengths: np.ndarray, sigma: float,
                         log_constant: float, log_jacobian: np.ndarray, alpha: np.ndarray,
                         scratch: np.ndarray, fresh: bool, stay: float) -> float:
    """One step of the ergodic threshold model, in place on its state ``alpha`` (N,) (uniform
    when ``fresh``); returns the sample's log-likelihood ``log sum_j prior_j b_j``, the prior
    ``stay * alpha_j + (1 - stay) / N``. ``z`` (K, d): the sample in each template's standardised
    units; ``means`` (N, d): their states, template after template, ``lengths`` (K,) states
    each; ``log_jacobian`` (K,): each map's log |dz / dx|; ``scratch`` (N,): room for the states'
    log-densities. ``means``, ``alpha`` and ``scratch`` are of :data:`PRECISION`, and so is
    the arithmetic on them (the weights' sum in double precision). The cost is one distance and
    one exp per state, the tick's largest after the forward step (8 performers x 100 templates:
    80,000 states)."""
    k_count, d = z.shape
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
            for c in range(d):
                diff = f32(z[k, c]) - means[j, c]
                s += diff * diff
            v = s * inv + lj
            scratch[j] = v
            if v > top:
                top = v
            j += 1
    keep, jump = f32(stay), f32((1.0 - stay) / n)
    total = 0.0
    for j in range(n):
        e = scratch[j] - top
        if e < floor:   # under 4e-18 of the likeliest state: no exp (most states are far)
            alpha[j] = 0.0
            continue
        a = f32(1.0 / n) if fresh else alpha[j]
        w = (keep * a + jump) * np.exp(e)
        alpha[j] = w
        total += w
    for j in range(n):
        alpha[j] = alpha[j] / total
    return float(top) + np.log(total)


def gated(step: float, best_step: float, x: np.ndarray, previous: np.ndarray | None,
          still_radius: np.ndarray) -> float:
    """The threshold model's step, at most ``best_step`` (the best template's) while the input
    stayed within :data:`STILL_RADII` still radii of the ``previous`` sample."""
    if previous is None or not np.any(np.abs(x - previous) > STILL_RADII * still_radius):
        return min(step, best_step)
    return step
