"""The path misfit's remembered samples when a template's size moves at once.

The misfit (:mod:`behaviors.mop.refusal`) keeps its remembered samples as sums of ``|u|^2``,
``u.v`` and ``|v|^2`` (``u``: the input from the anchor, ``v``: the nearest point of the path
to ``u / size`` as the size was when the sample came) and reads them at the current size, so a
size that converges slowly does not leave the early samples counted as strays. But ``v`` stays
where it was found: when the size moves at once (taken at the input's reversal or at a rest,
:mod:`behaviors.mop.invariance`, :mod:`behaviors.mop.holding`), ``u / size`` slides along the
path while ``v`` does not, and the samples read as off the path by the slide alone. Measured on
held-out seed 108 (``bench/follow_quality.py``'s sized draws): the line at 0.85x resized 1.03 ->
0.86 at its turn, its misfit 0.19 -> 1.13 sigma, misshaped (beyond 1.2) for 11 samples while its
followed progress caught up with the truth; the kick wrist at 1.4x (1.39 -> 1.10: 0.42 -> 2.07).
So where a template's size moved by more than :data:`RESIZE_JUMP` since the sums were last read,
they are read no worse than at the size they were read at before: the remembered misfit at that
size is kept as it stood, the samples to come are read at the new one.
The sums' fourth column holds the size they were last read at (0: none yet).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from behaviors.kernel_cache import compiled

#: A size moved by more than this factor in one sample is a move at once (no slow convergence).
RESIZE_JUMP = 1.1


@compiled(numba.void(numba.float64[:, ::1], numba.intp, numba.intp, numba.float64[::1]))
def reread(misfit: np.ndarray, lo: int, hi: int, size: np.ndarray) -> None:
    """Before templates ``lo:hi``'s misfit sums (rows of ``misfit``: ``|u|^2``, ``u.v``,
    ``|v|^2``, the size last read at) take this sample: where ``size`` (template units, one per
    template) moved beyond :data:`RESIZE_JUMP` since the last read and the sums read worse at it,
    keep them as they read at the last size; then note ``size`` as the last."""
    jump = math.log(RESIZE_JUMP)
    for k in range(lo, hi):
        was, now = misfit[k, 3], size[k]
        if was > 0.0 and abs(math.log(now / was)) > jump:
            then = misfit[k, 0] / (was * was) - 2.0 * misfit[k, 1] / was + misfit[k, 2]
            at = misfit[k, 0] / (now * now) - 2.0 * misfit[k, 1] / now + misfit[k, 2]
            if then < at:
                misfit[k, 0] = 0.0
                misfit[k, 1] = 0.0
                misfit[k, 2] = then
        misfit[k, 3] = now
