"""The emissions of a template's window states (MOP section 3.2's observation probability
``b_i``, as each state's prescaled squared distance from the sample), compiled and inlined into
:func:`behaviors.mop.window_kernel.step_windows`: a point state's plain distance, a stretched
state's (:mod:`behaviors.mop.stretch`) less the part along its path up to its half-length."""

from __future__ import annotations

import numba
import numpy as np

import behaviors.mop.compiled
from behaviors.mop.compiled import CONTRACT
from behaviors.kernel_cache import compiled

_CALLS_INTO = (behaviors.mop.compiled,)   # the files whose compiled functions the kernels take in
# an index never negative that the compiler cannot prove so, cast to unsigned (as the window
# kernel's: :mod:`behaviors.mop.window_kernel`)
_U = numba.uintp


@compiled(None, *_CALLS_INTO, fastmath=CONTRACT, inline="always")
def distances(means: np.ndarray, first: int, z: np.ndarray, n: int, out: np.ndarray) -> float:
    """Squared distances (prescaled) of ``n`` states from ``first`` on to z; returns the least.
    A puck's two features in one pass without the loop over features (the forward step 13 %
    faster, hot and cold: ``bench/mop.py``'s group, same process). The least taken in four
    interleaved parts (one chain of minima waits for each state's distance): this loop's share
    of step_windows' perf samples 14 -> 11 %, but step_windows' share of the tick 19.4 -> 19.8 %
    and its thread time p10 175, 185, 193 -> 184, 181, 183 us (alternating processes, load
    16): not taken."""
    best = np.inf
    if z.size == 2:
        z0, z1 = z[0], z[1]
        for r in range(n):
            u = _U(first + r)
            d0 = means[u, 0] - z0
            d1 = means[u, 1] - z1
            acc = d0 * d0 + d1 * d1
            out[r] = acc
            best = min(best, acc)
        return best
    for r in range(n):
        acc = 0.0
        for i in range(z.size):
            d = means[first + r, i] - z[i]
            acc += d * d
        out[r] = acc
        if acc < best:
            best = acc
    return best


@compiled(None, *_CALLS_INTO, fastmath=CONTRACT, inline="always")
def stretched_distances(means: np.ndarray, first: int, z: np.ndarray, n: int,
                          out: np.ndarray, tangent: np.ndarray, half: np.ndarray,
                          lift: np.ndarray) -> float:
    """:func:`distances` of a template with stretched states (only those: read for every
    template, the stretch doubled the forward's median in DESIGN's group, 0.38 -> 0.71 ms): a
    state stretched along its path (:mod:`behaviors.mop.stretch`: unit ``tangent``, prescaled
    ``half``-length) is a segment: the part of the distance along it, up to ``half``, is not
    counted (``c (2a - c)`` with ``c`` that part: exactly 0 for a point state), and its density
    is spread over its length (``lift``: minus its log normaliser over a point's, 0 for a point).
    """
    best = np.inf
    if z.size == 2:
        z0, z1 = z[0], z[1]
        for r in range(n):
            u = _U(first + r)
            d0 = means[u, 0] - z0
            d1 = means[u, 1] - z1
            a = abs(d0 * tangent[u, 0] + d1 * tangent[u, 1])
            c = min(half[u], a)
            acc = d0 * d0 + d1 * d1 - c * (2.0 * a - c) + lift[u]
            out[r] = acc
            best = min(best, acc)
        return best
    for r in range(n):
        acc = 0.0
        a = 0.0
        for i in range(z.size):
            d = means[first + r, i] - z[i]
            acc += d * d
            a += d * tangent[first + r, i]
        a = abs(a)
        c = min(half[first + r], a)
        acc += lift[first + r] - c * (2.0 * a - c)
        out[r] = acc
        if acc < best:
            best = acc
    return best
