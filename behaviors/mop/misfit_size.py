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
Measured (valid after 30% of gestures at 0.7-1.4x): ``bench/follow_seeds.py
--sections=sized,unrelated,sequences`` seeds 107-112 0.8925 / 0.8851 / 0.8938 / 0.9087 / 0.8989 /
0.8972 -> 0.9098 / 0.8906 / 0.9028 / 0.9127 / 0.9024 / 0.9021 (mean 0.8960 -> 0.9034; the walk
wrist at 0.85x, resized 0.98 -> 0.87 as it paused, 0.298 -> 1.0), unrelated and sequences the
same; ``bench/follow_quality.py``: tuned 0.9124 -> 0.9143, held-out 0.9076 -> 0.9109, bent 5%
0.8646 -> 0.8764, held-out aspect 1.1 0.8674 -> 0.8786, 1.2 0.4273 -> 0.4458, every other figure
the same. Left: a 0.7x square, its first side followed as the line at size 0.95, is off the
path on its second side until the size converges (0.95 -> 0.81 over 10 samples, 2% a sample):
misshaped 9 samples, the misfit true at each size of the time.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from behaviors.kernel_cache import compiled

#: A size moved by more than this factor in one sample is a move at once (no slow convergence).
#: At 1.05 (and alike at 1.02 and at any move, on held-out seeds 108 and 111) the tuned wave at
#: 0.6x, resized 1.0 -> 0.92 on its way to 0.6, kept the misfit read at 1.0 (1.19 sigma, 1.22
#: read at 0.92), drove at 0.88, strained, and so took no size at its next reversal
#: (:mod:`behaviors.mop.invariance`): valid after 30% 0.412 -> 0.059, the tuned 0.6 / 1.5x
#: figure 0.7540 -> 0.7467 (``bench/follow_quality.py``). The moves it is for are 10-26%.
RESIZE_JUMP = 1.1


@compiled(numba.void(numba.float64[:, ::1], numba.intp, numba.intp, numba.float64[:]))
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
