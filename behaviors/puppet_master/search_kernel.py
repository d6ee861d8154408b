"""The searches of similarity.py compiled: one step of the situation search in one pass, and the
coherence search's scoring of its few proposed windows.

``E_k[j] = |x_k - y_j|^2`` is computed in single precision as
``(|x|^2 + |y_j|^2) + sum_c (-2 x_c) y_jc`` (terms added in that order) from the training
table ``aug`` ((d + 2, N): y, |y|^2, 1; similarity.augmented) and the query (-2x and |x|^2,
rounded to single). The window distances, in double, advance along their diagonals:
``D'[j] = (lam D[j - 1] + E_new[j]) - lam^n E_old[j - n]``. ``E_old`` is recomputed from the
query leaving the window (its training rows were read n samples earlier in the same pass and
are still in the L1 cache), so no ring of n + 1 E rows is kept and written. The distances
live at ``buf[o: o + N]`` and a step moves ``o`` back by one (D[j - 1] already sits where
D'[j] goes). The pass runs in blocks of ``BLOCK`` window ends: the block's two E rows, its
distances, then its least distance, all while they are in L1 (blocks of 1,024 were no faster,
of 2,048 slower).

Each value's arithmetic is fixed (no fast-math on it: no reordering, no fused multiply-adds),
so a value is the same whether a loop runs in vector lanes or not: the same inputs give the
same distances to the last bit, whatever the machine's vector width.

Gated columns (the situation vectors' room, features.room_gate): a query's part of E from
column ``g0`` on is weighed by its own gate g, ``(|x_<g0|^2 + g |x_>=g0|^2) + (|y_<g0|^2 +
g |y_>=g0|^2) + sum_c q_c y_c`` with q = -2x (times g from ``g0`` on); the table then holds
the two parts of |y|^2 (similarity.augmented) and each query keeps its gate for when it
leaves the window. The eight columns of the situation vectors with the room run in one
pass as the six without it do (a push at 3,200 samples, CPU time median on a loaded
machine: the room off 6.3-8.1 us, the room ungated through the general loop 10.4 us, gated in
one pass 8.0-10.2 us, the gate worked out in Python included). The least value is
found with four running minima (a minimum does not depend on the order); ties take the
earliest window end.

Coherence (:func:`coherence_best`): the distinct proposed window ends are the distinct
"bases" (source minus the step it was pushed at) plus the step count; each is scored
``sum|y|^2 - 2 sum_a sum_c y[c - n + 1 + a, c] x[a, c]`` (the cross term summed in that
order, one term at a time, in double), then ``+ sum|x|^2``. Four windows' sums run side by
side, each in that order (the same bits): 0.77-0.82x the time of one sum after another
(tools: coherence states from a live reactor, 10 windows on average, 3,200 and 24,000
samples), most on the steps with many proposals, the step's slowest.
"""

from __future__ import annotations

import numba
import numpy as np

from behaviors.kernel_cache import compiled

BLOCK = 512

_F1, _F2, _S1, _S2 = (numba.float64[::1], numba.float64[:, ::1], numba.float32[::1],
                      numba.float32[:, ::1])
_I = numba.int64


# (numba's ``njit(cache=True, nogil=True)``, in the shared cache: see tabletop.drawing.dirty.KERNEL)
@compiled(numba.void(_S2, _S1, numba.float32, _I, _I, _S1, numba.float32, _I), error_model="python")
def energies(aug: np.ndarray, q: np.ndarray, xx: float, j0: int, j1: int,
             out: np.ndarray, g: float, g0: int) -> None:
    """``out[i]`` = E of the query (``q`` = -2x (d,), ``xx`` = |x|^2) against training vector
    j0 + i, for j0 + i < j1 (single precision). Columns from ``g0`` on (``g0`` = d: none) are
    gated: their part of E is weighed by the query's gate ``g`` (``q`` and ``xx`` carry it,
    the training table's |y|^2 of those columns is ``aug[d + 1]``, the rest's ``aug[d]``)."""
    d = q.size
    m = j1 - j0
    o = out[:m]
    yy = aug[d, j0:j1]
    if g0 < d:
        yr = aug[d + 1, j0:j1]
        if d == 8:  # the situation vectors with the room: one pass, the terms in order
            y0, y1, y2 = aug[0, j0:j1], aug[1, j0:j1], aug[2, j0:j1]
            y3, y4, y5 = aug[3, j0:j1], aug[4, j0:j1], aug[5, j0:j1]
            y6, y7 = aug[6, j0:j1], aug[7, j0:j1]
            q0, q1, q2, q3, q4, q5, q6, q7 = q[0], q[1], q[2], q[3], q[4], q[5], q[6], q[7]
            for i in range(m):
                o[i] = (((((((((xx + (yy[i] + g * yr[i])) + q0 * y0[i]) + q1 * y1[i])
                             + q2 * y2[i]) + q3 * y3[i]) + q4 * y4[i]) + q5 * y5[i])
                         + q6 * y6[i]) + q7 * y7[i])
            return
        for i in range(m):
            o[i] = xx + (yy[i] + g * yr[i])
    elif d == 6:    # the situation vectors': one pass, the same terms in the same order
        y0, y1, y2 = aug[0, j0:j1], aug[1, j0:j1], aug[2, j0:j1]
        y3, y4, y5 = aug[3, j0:j1], aug[4, j0:j1], aug[5, j0:j1]
        q0, q1, q2, q3, q4, q5 = q[0], q[1], q[2], q[3], q[4], q[5]
        for i in range(m):
            o[i] = (((((((xx + yy[i]) + q0 * y0[i]) + q1 * y1[i]) + q2 * y2[i]) + q3 * y3[i])
                     + q4 * y4[i]) + q5 * y5[i])
        return
    else:
        for i in range(m):
            o[i] = xx + yy[i]
    for c in range(d):
        row = aug[c, j0:j1]
        qc = q[c]
        for i in range(m):
            o[i] += qc * row[i]


@compiled(numba.float32(_F1, numba.float64, _I, _S2, _S1, _S1, _I), error_model="python")
def query(x: np.ndarray, g: float, g0: int, queries: np.ndarray, norms: np.ndarray,
          gates: np.ndarray, slot: int) -> float:
    """Store the live vector ``x`` (d,) as a query in ``slot``: -2x (its columns from ``g0``
    on times the gate ``g``), |x|^2 (those columns' part times ``g``) and ``g``; returns the
    gate as stored (single precision)."""
    d = x.size
    xx = 0.0
    for c in range(min(g0, d)):
        queries[slot, c] = -2.0 * x[c]
        xx += x[c] * x[c]
    if g0 < d:
        xr = 0.0
        for c in range(g0, d):
            queries[slot, c] = -2.0 * g * x[c]
            xr += x[c] * x[c]
        xx += g * xr
    norms[slot] = xx
    gates[slot] = g
    return gates[slot]


@compiled(numba.float64(_F1, _I, _I), error_model="python")
def least(buf: np.ndarray, p0: int, p1: int) -> float:
    """Least of buf[p0: p1] (inf if empty), with four running minima."""
    b = buf[p0:p1]
    m0 = m1 = m2 = m3 = np.inf
    n4 = b.size // 4 * 4
    for p in range(0, n4, 4):
        v0, v1, v2, v3 = b[p], b[p + 1], b[p + 2], b[p + 3]
        m0 = v0 if v0 < m0 else m0
        m1 = v1 if v1 < m1 else m1
        m2 = v2 if v2 < m2 else m2
        m3 = v3 if v3 < m3 else m3
    for p in range(n4, b.size):
        v0 = b[p]
        m0 = v0 if v0 < m0 else m0
    m0 = m1 if m1 < m0 else m0
    m2 = m3 if m3 < m2 else m2
    return m2 if m2 < m0 else m0


@compiled(_I(_F1, _I, _I, numba.float64), error_model="python")
def first(buf: np.ndarray, p0: int, p1: int, value: float) -> int:
    """First p in p0 .. p1 - 1 with buf[p] == value (p1 if none)."""
    for p in range(p0, p1):
        if buf[p] == value:
            return p
    return p1


@compiled(numba.types.Tuple((_I, _I, numba.float64))(
    _S2, _F1, _I, _I, _S2, _S1, _I, _F1, numba.float64, numba.float64, _I, _I, _S1, _S1,
    _S1, numba.float64, _I), error_model="python")
def situation_push(aug: np.ndarray, buf: np.ndarray, o: int, n: int, queries: np.ndarray,
                   norms: np.ndarray, k: int, x: np.ndarray, lam: float, lam_n: float,
                   lo: int, hi: int, e_new: np.ndarray, e_old: np.ndarray, gates: np.ndarray,
                   g: float, g0: int) -> tuple[int, int, float]:
    """Advance the distances ``buf[o: o + N]`` by the k-th live vector ``x`` (d,).

    ``queries`` (n + 1, d), ``norms`` (n + 1,): -2x and |x|^2 of the last n + 1 live vectors
    by k mod (n + 1); slot (k + 1) mod (n + 1) holds the one leaving the window. ``lam``,
    ``lam_n``: the recency weight per step and its n-th power (1, 1: the paper's window).
    ``e_new``, ``e_old``: scratch (BLOCK); their size is the block. ``gates`` (n + 1,): each
    query's gate, ``g`` this one's, for its columns from ``g0`` on (:func:`energies`; ``g0``
    = d: none). Returns the new offset,
    and the window end in lo .. hi - 1 with the least distance and that distance (-1, inf if
    lo >= hi)."""
    d = x.size
    N = aug.shape[1]
    slot = k % (n + 1)
    old = (k + 1) % (n + 1)
    g_new = query(x, g, g0, queries, norms, gates, slot)
    g_old = gates[old]
    q_new, q_old = queries[slot], queries[old]
    xx_new, xx_old = norms[slot], norms[old]
    if o == 0:
        buf[N:] = buf[:N]
        o = N
    o -= 1                      # D'[j] goes to buf[o + j], where D[j - 1] is
    best_j, best = -1, np.inf
    block = min(e_new.size, e_old.size)
    j0 = 0
    while j0 < N:
        j1 = min(j0 + block, N)
        energies(aug, q_new, xx_new, j0, j1, e_new, g_new, g0)
        if j0 == 0:
            buf[o] = e_new[0]
        a, b = max(j0, 1), min(j1, n)
        if a < b:                            # window ends before n: nothing leaves yet
            seg = buf[o + a:o + b]
            en = e_new[a - j0:b - j0]
            for i in range(b - a):
                seg[i] = lam * seg[i] + np.float64(en[i])
        a = max(j0, n)
        if a < j1:
            energies(aug, q_old, xx_old, a - n, j1 - n, e_old, g_old, g0)
            seg = buf[o + a:o + j1]
            en = e_new[a - j0:j1 - j0]
            for i in range(j1 - a):
                seg[i] = (lam * seg[i] + np.float64(en[i])) - lam_n * np.float64(e_old[i])
        a, b = max(j0, lo), min(j1, hi)
        if a < b:
            m = least(buf, o + a, o + b)
            if m < best:
                best = m
                best_j = first(buf, o + a, o + b, m) - o
        j0 = j1
    return o, best_j, best


@compiled(numba.void(_S2, _F1, _I, _S2, _S1, _F2, numba.float64, _S1, _S1, _F1, _I),
      error_model="python")
def situation_reset(aug: np.ndarray, dist: np.ndarray, n: int, queries: np.ndarray,
                    norms: np.ndarray, window: np.ndarray, lam: float, e: np.ndarray,
                    gates: np.ndarray, window_gates: np.ndarray, g0: int) -> None:
    """Distances ``dist`` (N,) of the live window (n, d), oldest first, from scratch:
    ``D[j] = sum_a lam^a E_{n-1-a}[j - a]`` (a ascending; lam^a as repeated products); its
    queries into slots 0 .. n - 1, with their gates ``window_gates`` (n,) (see
    situation_push). ``e``: scratch of at least N."""
    N = aug.shape[1]
    for a in range(n):
        query(window[a], window_gates[a], g0, queries, norms, gates, a)
    dist[:] = 0.0
    w = 1.0
    for a in range(min(n, N)):
        energies(aug, queries[n - 1 - a], norms[n - 1 - a], 0, N - a, e, gates[n - 1 - a], g0)
        for j in range(a, N):
            dist[j] = dist[j] + w * np.float64(e[j - a])
        w *= lam


NO_SOURCE = np.iinfo(np.int64).min   # a base of a live vector not generated from the training


@compiled(numba.types.Tuple((_I, numba.float64))(
    _F2, _F2, numba.int64[::1], numba.int64[::1], numba.boolean[::1], _F1, _F1),
    error_model="python")
def coherence_best(y: np.ndarray, buf: np.ndarray, bases: np.ndarray, ik: np.ndarray,
                   valid: np.ndarray, sy: np.ndarray, sx: np.ndarray) -> tuple[int, float]:
    """Best proposed training window for the live window ``buf[i + 1: i + 1 + n]`` (n, d)
    (``buf``: (2n, d), the live ring written twice; ``ik``: i and the step count k): the
    window end ``b + k`` of each distinct base b in ``bases`` (n,) (NO_SOURCE: none) that is
    allowed (``valid``), scored against the training vectors ``y`` (N, d) with the window
    sums ``sy`` of |y|^2 and the live window's ``sx[0]`` = sum |x|^2. Returns (window end,
    distance), (-1, inf) if none; ties take the earliest window end."""
    i, k = ik[0], ik[1]
    n = bases.size
    N, d = y.shape
    order = np.sort(bases)
    ends = np.empty(n, dtype=np.int64)      # the allowed proposed window ends, ascending
    m = 0
    prev = NO_SOURCE
    for r in range(n):
        b = order[r]
        if b == NO_SOURCE or b == prev:
            continue
        prev = b
        c = b + k
        if c < 0 or c >= N or not valid[c] or c - n + 1 < 0:
            continue
        ends[m] = c
        m += 1
    # the cross terms of four windows at once: four independent sums, each in its own fixed
    # order (the same bits as one at a time; a single running sum waits on every addition)
    cross = np.zeros(m)
    r = 0
    while r + 4 <= m:
        s0, s1, s2, s3 = ends[r] - n + 1, ends[r + 1] - n + 1, ends[r + 2] - n + 1, \
            ends[r + 3] - n + 1
        x0 = x1 = x2 = x3 = 0.0
        for a in range(n):
            live = buf[i + 1 + a]
            y0, y1, y2, y3 = y[s0 + a], y[s1 + a], y[s2 + a], y[s3 + a]
            for e in range(d):
                v = live[e]
                x0 += y0[e] * v
                x1 += y1[e] * v
                x2 += y2[e] * v
                x3 += y3[e] * v
        cross[r], cross[r + 1], cross[r + 2], cross[r + 3] = x0, x1, x2, x3
        r += 4
    for r in range(r, m):
        start = ends[r] - n + 1
        x0 = 0.0
        for a in range(n):
            row = y[start + a]
            live = buf[i + 1 + a]
            for e in range(d):
                x0 += row[e] * live[e]
        cross[r] = x0
    best_c, best = -1, np.inf
    for r in range(m):
        c = ends[r]
        cost = sy[c] - 2.0 * cross[r]
        if best_c < 0 or cost < best:
            best_c, best = c, cost
    if best_c < 0:
        return -1, np.inf
    return best_c, max(best + sx[0], 0.0)


@compiled(numba.void(_F2, _F1, numba.int64[::1], _F1, numba.int64[::1], _F1, _I),
      error_model="python")
def coherence_push(buf: np.ndarray, sq: np.ndarray, bases: np.ndarray, sx: np.ndarray,
                   ik: np.ndarray, x: np.ndarray, source: int) -> None:
    """Add the newest live vector ``x`` (d,) to the coherence ring (see coherence_best) with
    the training index ``source`` it was generated from (-1: none): |x|^2 summed term by
    term, the window's sum ``sx[0]`` kept as a running sum (the newest in, the oldest out)."""
    n = sq.size
    i = (ik[0] + 1) % n
    ik[0] = i
    q = 0.0
    for e in range(x.size):
        q += x[e] * x[e]
    sx[0] += q - sq[i]
    for e in range(x.size):
        buf[i, e] = x[e]
        buf[i + n, e] = x[e]
    sq[i] = q
    k = ik[1] + 1
    ik[1] = k
    bases[i] = source - k if source >= 0 else NO_SOURCE
