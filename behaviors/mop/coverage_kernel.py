"""A template's coverage over one sample, compiled for the group's kernel
(:func:`behaviors.mop.group_kernel.update_templates`; the follower's array code:
:meth:`Refusal._judge_shape <behaviors.mop.refusal.Refusal._judge_shape>`): covered once engaged
and its followed arc passed its need (:mod:`behaviors.mop.coverage`), not while that arc runs
:data:`~behaviors.mop.coverage.RUN_AHEAD` times past where the input went, and, covered sooner,
not while off its path (``EARLY_FIT`` short of ``coverage`` of it, ``LATE_FIT`` past it until it
has gone on ``LATE_UNTIL`` times the arc it was let off)."""

from __future__ import annotations

import math

import numba
import numpy as np

from behaviors.kernel_cache import compiled
from behaviors.mop import coverage
from behaviors.mop.compiled import CONTRACT
from behaviors.mop.coverage import RUN_AHEAD, arc_ahead

_F1, _F2, _FA2 = numba.float64[::1], numba.float64[:, ::1], numba.float64[:, :]


@compiled(numba.void(_F2, _FA2, _F1, _F1, numba.intp, numba.float64, numba.intp, numba.intp,
                     numba.intp, numba.intp, numba.intp, numba.intp, numba.boolean, _F1,
                     numba.intp, numba.float64, numba.intp, numba.float64, numba.float64,
                     numba.boolean[:], numba.float64[:]),
          coverage, fastmath=CONTRACT)
def cover(states: np.ndarray, lags: np.ndarray, t: np.ndarray, m: np.ndarray, k: int, g: float,
          gf: int, start: int, last: int, off: int, arc: int, ahead: int, engaged: bool,
          away: np.ndarray, sc0: int, sk: float, d: int, dims: float, m2: float,
          covered: np.ndarray, reached: np.ndarray) -> None:
    """Template ``k``'s ``covered`` and ``reached`` (the input's farthest reach from the anchor,
    in its spread at size ``sk``) after a sample. ``states``: the group's rows (``arc``: the
    arc's column, the template's states ``start`` .. ``last`` from row ``off``); ``g``, ``gf``:
    its followed state (bank index) and its floor; ``lags``: its shape sums per timing offset;
    ``t``, ``m``: its row of ``tc`` (``ahead``: the column of its own straight start's need,
    :func:`~behaviors.mop.coverage.arc_ahead`) and its member's of ``mc``
    (:mod:`~behaviors.mop.group_layout`); ``away`` (``d`` columns of ``dims``): the input from
    the anchor; ``m2``: its path misfit (sigma squared)."""
    at = states[gf + off, arc]
    at += (g - gf) * (states[min(gf + 1, last) + off, arc] - at)
    # ... read at the best timing offset ahead where the need is the own straight start
    # (tc's last column: coverage.arc_ahead)
    if engaged and (at >= t[3] or t[ahead] > 0.0 and arc_ahead(
            lags, k, g, start, last, states, off, arc) >= t[3]):
        covered[k] = True
    # ... and not while it runs far ahead of where the input went (coverage.RUN_AHEAD)
    acc = 0.0
    for c in range(d):
        r = away[c] / t[sc0 + c] / sk
        acc += r * r
    reached[k] = max(reached[k], math.sqrt(acc / dims))
    if at > RUN_AHEAD * reached[k]:
        covered[k] = False
    # ... and, covered sooner, not while off its path by > EARLY_FIT short of
    # ``coverage`` of it, nor by > LATE_FIT past it until it has gone on by LATE_UNTIL
    # times the arc it was let off (m[33], m[37]: coverage.EARLY_FIT, LATE_FIT squared;
    # m[38]: LATE_UNTIL)
    full = m[24] * states[last + off, arc]
    if (t[3] < full and at < full + m[38] * (full - t[3])
            and m2 > (m[33] if at < full else m[37])):
        covered[k] = False
