"""A sample's sums toward a template's size estimate at its followed state, compiled for the
group's kernel (:meth:`PerformanceFrame._estimate_size
<behaviors.mop.invariance.PerformanceFrame._estimate_size>`, whose array code the follower runs)."""

from __future__ import annotations

import numba
import numpy as np

from behaviors.kernel_cache import compiled
from behaviors.mop import invariance
from behaviors.mop.compiled import CONTRACT
from behaviors.mop.invariance import ALONG


@compiled(numba.types.UniTuple(numba.float64, 2)(
    numba.float64[::1], numba.float64[::1], numba.float64, numba.intp, numba.float64[::1],
    numba.intp), invariance, fastmath=CONTRACT)
def estimate_sums(row: np.ndarray, nrow: np.ndarray, frac: float, rel0: int, r: np.ndarray,
                  d: int) -> tuple[float, float]:
    """The sums ``q . r`` and ``q . q`` of the template's state ``q`` (``frac`` of the way from
    ``row`` to ``nrow``, from column ``rel0``, template units) and the input ``r`` (d,: from the
    anchor, units), less :data:`~behaviors.mop.invariance.ALONG`'s share of what lies along the
    path there."""
    qr = 0.0
    qq = 0.0
    qt = 0.0
    rt = 0.0
    tt = 0.0
    for c in range(d):
        seg = nrow[rel0 + c] - row[rel0 + c]
        q = row[rel0 + c] + frac * seg
        qr += q * r[c]
        qq += q * q
        qt += q * seg
        rt += r[c] * seg
        tt += seg * seg
    if ALONG < 1.0 and tt > 1e-12:   # invariance.ALONG: less along the path
        qr -= (1.0 - ALONG) / tt * qt * rt
        qq -= (1.0 - ALONG) / tt * qt * qt
    return qr, qq
