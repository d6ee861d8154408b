"""The lead a template's evidence held over the threshold model's while its size stayed near the
one it was judged at (:data:`~behaviors.mop.invariance.HELD_LEAD`), taken back when it is judged
afresh with the most evidence (follower and group kernel alike).

Both evidences were gathered under the old size: while the size estimate slides to the new one
(a square drawn 1.4x, its first side followed at size 0.97, 0.97 -> 1.38 at the corner), the
template's per-sample likelihood pays for the slide and the threshold model, stitching any
template's pieces, does not, so a template judged afresh starts under it (the square's lead
+0.9 nats before the corner, -16 when judged afresh, the templates' share 0.000-0.35 for 10
samples). Taking back the lead held at the old size (evidences in nats), never more, puts it
where it was before the slide.
"""

from __future__ import annotations

import math

import numba
import numpy as np


@numba.njit(cache=True, nogil=True)
def held_lead(ev: np.ndarray, size: np.ndarray, judged: np.ndarray, held: np.ndarray, a0: int,
              a1: int, first: int, rejudged: bool, thr: float, band: float) -> float:
    """The threshold model's evidence ``thr`` after template ``first`` (the first of most
    evidence ``ev`` among ``a0:a1``), judged afresh this sample (``rejudged``), took back its
    ``held`` lead: ``min(thr, ev[first] - held[first])``. In place, ``held[k]`` becomes
    ``ev[k]`` minus that for every template whose size lies within ``band`` (log) of the size
    it was ``judged`` at."""
    if rejudged:
        thr = min(thr, ev[first] - held[first])
    for k in range(a0, a1):
        if abs(math.log(size[k] / judged[k])) <= band:
            held[k] = ev[k] - thr
    return thr
