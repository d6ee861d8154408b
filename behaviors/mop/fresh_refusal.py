"""The refusal of a template just judged afresh waits for its fresh memory to hold a few samples.

Once a template's size estimate moved by :data:`~behaviors.mop.invariance.REJUDGE` since its
recent likelihood began, that memory is forgotten and starts again at one sample's weight
(:meth:`~behaviors.mop.invariance.PerformanceFrame._rejudge`). The next sample alone then decides
the refusal (:mod:`behaviors.mop.refusal`: recent likelihood beyond ``null_distance``), and at
the re-judge the followed state is often catching up with the size just found: held-out seed 102's
backflip ankle at 1.2x, judged afresh at 0.50 of it (size 1.20, right; progress on the truth),
read its next sample at 2.68 sigma, was refused at 1.93 sigma over two samples' weight and,
its steady fit 1.1-1.3 sigma, never came back under ``accept_distance`` (1.2) before the
performer paused and the attempt began anew (valid after 30% 0.08). So a template judged afresh
is not refused until its fresh memory holds :data:`FRESH_WEIGHT` samples' weight (one already
refused stays so until accepted again); a performance begun anew is refused at once as before.
"""

from __future__ import annotations

import numba
import numpy as np

from behaviors.kernel_cache import compiled

#: Samples' weight the recent likelihood of a template judged afresh holds before it may be
#: refused (1: at once, as a template begun anew).
FRESH_WEIGHT = 3.0


@compiled(numba.boolean(numba.boolean, numba.boolean, numba.float64, numba.float64,
                        numba.float64, numba.float64))
def refused_after(refused: bool, fresh: bool, dist2: float, weight: float, null2: float,
                  accept2: float) -> bool:
    """Whether a template is refused after a sample: its recent squared distance ``dist2``
    (sigma units) beyond ``null2``, unless it is ``fresh`` from a re-judge with a memory of
    less than :data:`FRESH_WEIGHT` samples' ``weight``, or already ``refused``; and not
    under ``accept2``."""
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
