"""The refusal of the action driving, just judged afresh, waits for its fresh memory to hold a
few samples.

Once a template's size estimate moved by :data:`~behaviors.mop.invariance.REJUDGE` since its
recent likelihood began, that memory is forgotten and starts again at one sample's weight
(:meth:`~behaviors.mop.invariance.PerformanceFrame._rejudge`). The next sample alone then decides
the refusal (:mod:`behaviors.mop.refusal`: recent likelihood beyond ``null_distance``), and at
the re-judge the followed state is often catching up with the size just found: held-out seed
102's backflip ankle at 1.2x, driving, judged afresh at 0.50 of it (size 1.20, right; progress
on the truth), read its next sample at 2.68 sigma, was refused at 1.93 sigma over two samples'
weight and, its steady fit 1.1-1.3 sigma, never came back under ``accept_distance`` (1.2) before
the performer paused and the attempt began anew (valid after 30% 0.08). So the action driving,
judged afresh, is not refused until its fresh memory holds :data:`FRESH_WEIGHT` samples' weight
(refused already, it stays so until accepted again); other templates, and a performance begun
anew, are refused at once as before. Measured (valid after 30% at 0.7-1.4x,
``bench/follow_seeds.py --sections=sized,unrelated,sequences``): seeds 101-106 mean 0.9058 ->
0.9062 (102 0.8976 -> 0.9002, the backflip 0.08 -> 0.36; a 1.2x circle 0.875 -> 0.859, taken a
sample later: the spin wrist driving on its start, judged afresh, not refused at once), 107-112
and every unrelated and sequences figure identical; ``bench/follow_quality.py`` tuned 0.9143 ->
0.9152, held-out aspect 1.1 0.8786 -> 0.8798, the other 540 figures identical (2 timing).
Measured and not kept, every template judged afresh waiting so: sized 107-112 mean 0.9036 ->
0.9044 (107 0.9102 -> 0.9151), 101-106 0.9058 -> 0.9063, unrelated worst on 103 0.1030 ->
0.0974, but a motion partly performing an action driven longer (``told``) on 101 0.0234 ->
0.0315, 110 0.0453 -> 0.0490, 112 0.0392 -> 0.0436: wrong templates judged afresh on unrelated
motion were spared as the true ones. The action driving or best (the 0.85x backflip ankle on
107, best and not yet driving when judged afresh, 0.317 -> 0.805): 107-112 mean 0.9036 -> 0.9044,
but ``bench/follow_quality.py`` held-out unrelated mean 0.0110 -> 0.0114 (a wander among six
0 -> 0.015), told mean 0.0040 -> 0.0044, a gesture after a stroke recognised 0.375 -> 0.361.
"""

from __future__ import annotations

import numba
import numpy as np

from behaviors.kernel_cache import compiled

#: Samples' weight the recent likelihood of the action driving, judged afresh, holds before it
#: may be refused (1: at once, as a template begun anew). At 3 the backflip ankle above (its
#: samples after the re-judge 2.68, 1.59, 1.08 sigma) is never refused; at 2 it still is.
FRESH_WEIGHT = 3.0


@compiled(numba.boolean(numba.boolean, numba.boolean, numba.float64, numba.float64,
                        numba.float64, numba.float64))
def refused_after(refused: bool, fresh: bool, dist2: float, weight: float, null2: float,
                  accept2: float) -> bool:
    """Whether a template is refused after a sample: its recent squared distance ``dist2``
    (sigma units) beyond ``null2``, unless it is ``fresh`` (driving when judged afresh) with a
    memory of less than :data:`FRESH_WEIGHT` samples' ``weight``, or already ``refused``; and
    not under ``accept2``."""
    waits = fresh and weight < FRESH_WEIGHT
    return (refused or (dist2 > null2 and not waits)) and not dist2 < accept2


@compiled(numba.void(numba.boolean[::1], numba.boolean[::1], numba.float64[::1],
                     numba.float64[::1], numba.float64, numba.float64))
def refuse(refused: np.ndarray, fresh: np.ndarray, dist2: np.ndarray, weight: np.ndarray,
           null2: float, accept2: float) -> None:
    """:func:`refused_after` for every template, in place on ``refused``; ``fresh`` ends once
    the memory holds :data:`FRESH_WEIGHT` samples' weight."""
    for k in range(refused.size):
        refused[k] = refused_after(refused[k], fresh[k], dist2[k], weight[k], null2, accept2)
        fresh[k] = fresh[k] and weight[k] < FRESH_WEIGHT
