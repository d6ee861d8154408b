"""A follower group's small compiled steps around its per-template pass
(:mod:`behaviors.mop.group_kernel`): the members' samples taken in, mapped into every template's
units for the forward step, each member's likeliest templates among its own (a slice of the
group's), its displacements from its anchor, and what a template a few ahead will read,
fetched. Each equals the numpy operations named in its docstring.
"""

from __future__ import annotations

import math

import numba
import numpy as np

import behaviors.mop.compiled
from behaviors.mop import commitment
from behaviors.mop.commitment import COMMIT_LAGS
from behaviors.mop.compiled import CONTRACT, prefetch
from behaviors.kernel_cache import compiled

# the files whose compiled functions or constants the kernels take in
_CALLS_INTO = (behaviors.mop.compiled, commitment)

_F1, _F2 = numba.float64[::1], numba.float64[:, ::1]
_I1, _B1, _I2 = numba.intp[::1], numba.boolean[::1], numba.intp[:, ::1]
_F3 = numba.float64[:, :, ::1]
_FA1 = numba.float64[:]   # columns of a group's per-template state (group_layout.FLOATS)


@compiled(numba.void(_F2, _F2, _F2, _F2, _FA1, _F2, _I1, _I1, _F2), *_CALLS_INTO, fastmath=CONTRACT)
def map_inputs(x, anchor, tc, mc, size, first, bounds, counts, z) -> None:
    """:meth:`PerformanceFrame._inputs` (without direction of motion) of every member into the
    forward's input ``z`` (K, width; its first D columns): each member's sample ``x`` (M, D) from
    its ``anchor`` (the template's center for "none"), divided by the estimated ``size`` for
    "scale", in the template's spread, plus its ``first`` state (K, D)."""
    d = x.shape[1]
    sc0, ce0 = 5, 5 + d
    for i in range(bounds.size):
        scaled, none = mc[i, 8] > 0.0, mc[i, 16] > 0.0
        for k in range(bounds[i], bounds[i] + counts[i]):
            ssz = size[k] if scaled else 1.0
            for c in range(d):
                r = x[i, c] - (tc[k, ce0 + c] if none else anchor[i, c])
                z[k, c] = r / ssz / tc[k, sc0 + c] + first[k, c]


@compiled(numba.intp(_F2, _F2, _F2, _B1, _F2, _B1), *_CALLS_INTO, fastmath=CONTRACT)
def take_samples(samples, x, anchor, has_anchor, jump, jumped) -> int:
    """Every member's sample (``samples`` (M, D)) into ``x`` when all are finite and none is a
    glitch (in a column farther than ``jump`` (M, D) from its last, ``x``, the last not
    ``jumped``: :meth:`ActionFollower._glitch`), each member without an anchor
    taking its sample as one; returns 0 where they were not (nothing changed), 1 where they
    were, 2 where a member took its anchor too. One call for what cost four numpy calls on 16
    numbers (a sum, a copy, two tests)."""
    for v in samples.ravel():
        if not math.isfinite(v):
            return 0
    for i in range(x.shape[0]):
        if has_anchor[i] and not jumped[i]:
            for c in range(x.shape[1]):
                if abs(samples[i, c] - x[i, c]) > jump[i, c]:
                    return 0
    x[:] = samples
    jumped[:] = False
    taken = 1
    for i in range(x.shape[0]):
        if not has_anchor[i]:
            anchor[i] = x[i]
            has_anchor[i] = True
            taken = 2
    return taken


@compiled(numba.void(_F1, numba.intp, numba.intp, _I1), *_CALLS_INTO, fastmath=CONTRACT)
def top_three(p: np.ndarray, a0: int, a1: int, out: np.ndarray) -> None:
    """The three largest of ``p[a0:a1]`` (indices into ``p``, largest first, ties in index
    order as ``np.argsort(-p, kind="stable")[:3]``) into ``out`` (3,); -1 where fewer."""
    t0 = t1 = t2 = -1
    v0 = v1 = v2 = -np.inf
    for k in range(a0, a1):
        pk = p[k]
        if pk > v0 or t0 < 0:
            t2, v2, t1, v1, t0, v0 = t1, v1, t0, v0, k, pk
        elif pk > v1 or t1 < 0:
            t2, v2, t1, v1 = t1, v1, k, pk
        elif pk > v2 or t2 < 0:
            t2, v2 = k, pk
    out[0], out[1], out[2] = t0, t1, t2


@compiled(numba.intp(_FA1, numba.intp, numba.intp), *_CALLS_INTO, fastmath=CONTRACT)
def first_max(values: np.ndarray, a0: int, a1: int) -> int:
    """The index of the first largest of ``values[a0:a1]`` (``a0 + np.argmax``)."""
    best = a0
    for k in range(a0 + 1, a1):
        if values[k] > values[best]:
            best = k
    return best


@compiled(numba.void(_F2, _I2, _F1, numba.intp), *_CALLS_INTO, fastmath=CONTRACT)
def prefetch_ahead(states: np.ndarray, ti: np.ndarray, mean: np.ndarray, h: int) -> None:
    """Start loading what template ``h`` (a few ahead of the one the group's per-template pass
    works on) will read around its followed state ``mean[h]``: its rows of ``states`` (the
    path's segments among them); no effect on results. ``ti``: as the per-template pass's.
    Inlined into the pass instead of called (the same numbers): update_templates 532, 457, 554
    -> 507, 499, 500 us median, alternating processes at load 11-13, the forward step beside it
    (untouched) 213, 189, 219 -> 200, 202, 201: within the noise, not taken."""
    row0 = int(ti[h, 0] + min(mean[h], ti[h, 1] - 1.0)) + ti[h, 2]
    first_h, end_h = ti[h, 0] + ti[h, 2], ti[h, 0] + ti[h, 1] + ti[h, 2]
    # (the rows its timing offsets read too, commitment.add_lagged, and its last:
    # update_templates p10 788, 793 -> 724, 708 us, add_lagged's share of the
    # tick's perf samples 11% -> 5%, alternating processes at load 25; they hold the path's
    # reach, PATH_REACH, too)
    for r in range(max(row0 - COMMIT_LAGS, first_h), min(row0 + COMMIT_LAGS + 2, end_h)):
        prefetch(states, r)
    prefetch(states, end_h - 1)


@compiled(numba.float64(_F3, _I1, _F2, _F2, _F1, numba.intp, numba.intp, _F1, _F1, _F1),
          *_CALLS_INTO, fastmath=CONTRACT)
def displacements(buf: np.ndarray, nbuf: np.ndarray, x: np.ndarray, anchor: np.ndarray,
                  m: np.ndarray, un0: int, i: int, away: np.ndarray, dx: np.ndarray,
                  dxu: np.ndarray) -> float:
    """Member ``i``'s displacements from its anchor (raw units): ``away``, of the mean of its
    last 3 buffered samples and this one (the engagement's); ``dx``, of this sample; ``dxu``,
    of this sample in its units (``m[un0:]``, its row of the member scalars); returns the
    length of ``dxu`` (the sample's distance from the anchor in units: the reach's least
    size)."""
    s, d = buf.shape[1], x.shape[1]
    n = min(nbuf[i], 3)
    for c in range(d):
        tot = 0.0
        for r in range(s - n, s):
            tot += buf[i, r, c]
        away[c] = (tot + x[i, c]) / (n + 1) - anchor[i, c]
        dx[c] = x[i, c] - anchor[i, c]
        # the same quotient as each template took, once per member; with the rejudging's
        # logarithm taken only near its limit and the displacement's root of the largest
        # (the same numbers to the bit): update_templates, no threshold model, DESIGN's tick,
        # load 5: hot 150 -> 136 us p10, 171 -> 157 median; caches cold 171 -> 158, 201 -> 193
        dxu[c] = dx[c] / m[un0 + c]
    far = 0.0
    for c in range(d):
        far += dxu[c] ** 2
    return math.sqrt(far)
