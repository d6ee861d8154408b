"""A follower group's threshold models (:mod:`behaviors.mop.threshold`), compiled: one
member's step over every state of its templates, as :func:`behaviors.mop.group_kernel.update_templates`
left the sample mapped by each template.
"""

from __future__ import annotations

import math

import numba
import numpy as np

import behaviors.mop.compiled
from behaviors.mop import threshold
from behaviors.mop.compiled import CONTRACT, exp_neg32
from behaviors.mop.threshold import CHAIN_KEEP, CHAIN_LEAST, CHAIN_MOVES, TINY
from behaviors.mop.threshold import STAY as THRESHOLD_STAY
from behaviors.kernel_cache import compiled

# the files whose compiled functions or constants the kernels take in
_CALLS_INTO = (behaviors.mop.compiled, threshold)

#: Log-weights below the threshold model's likeliest state by more than this weigh nothing
#: (as :func:`behaviors.mop.threshold.threshold_model_step`).
THRESHOLD_FLOOR = -40.0

_F1, _F2, _I2 = numba.float64[::1], numba.float64[:, ::1], numba.intp[:, ::1]
_S1, _S2 = numba.float32[::1], numba.float32[:, ::1]

# single-precision constants (a float64 one would widen every operation it meets)
_F32 = np.float32
_FLOOR32, _NEG_INF32, _ZERO32 = _F32(THRESHOLD_FLOOR), _F32(-np.inf), _F32(0.0)
_TINY32, _LEAST32 = _F32(TINY), _F32(CHAIN_LEAST)
_W0, _W1, _W2, _W3 = (_F32(w) for w in CHAIN_MOVES)
# the chain forms (threshold.CHAINS): how many, each one's sign of x and of y, and which run
# backwards
_FORMS = len(threshold.CHAINS)
_SIGNS, _BACKWARD = threshold.chain_forms(2)
_SX, _SY = _SIGNS[:, 0].copy(), _SIGNS[:, 1].copy()


_U = numba.uintp   # an index known to be >= 0: no wrap-around of negative indices


@compiled(None, *_CALLS_INTO, fastmath=CONTRACT, inline="always")
def _largest(v: np.ndarray, lo: int, hi: int) -> float:
    """The largest of ``v[lo:hi]``, in eight interleaved parts (exact in any order) kept in
    eight locals, which stay in registers; kept in an array of eight (a call per template)
    they went through memory value by value, and so did the sum's parts in
    :func:`threshold_step` (now :func:`_summed`): with both in locals, update_templates 0.545
    -> 0.428 and 0.596 -> 0.492 ms, DESIGN's tick 1.168 -> 0.971 and 1.285 -> 1.073 ms
    (median thread time, interleaved in one process, load 19; the same numbers to the bit)."""
    t0 = t1 = t2 = t3 = t4 = t5 = t6 = t7 = _NEG_INF32
    end = hi - (hi - lo) % 8
    for j in range(lo, end, 8):
        u = _U(j)
        t0 = max(t0, v[u])
        t1 = max(t1, v[u + _U(1)])
        t2 = max(t2, v[u + _U(2)])
        t3 = max(t3, v[u + _U(3)])
        t4 = max(t4, v[u + _U(4)])
        t5 = max(t5, v[u + _U(5)])
        t6 = max(t6, v[u + _U(6)])
        t7 = max(t7, v[u + _U(7)])
    for j in range(end, hi):
        t0 = max(t0, v[j])
    return max(max(max(t0, t1), max(t2, t3)), max(max(t4, t5), max(t6, t7)))


@compiled(numba.float64(_S1), *_CALLS_INTO, fastmath=CONTRACT | {"reassoc"})
def _summed(v: np.ndarray) -> float:
    """The sum of the float32 ``v`` in double precision, in any order (``reassoc``: the loop
    vectorises; the same to about 1e-16). Called for each template of :func:`threshold_step`
    with any weight, the others' being zeros: 8 members on DESIGN's real state, interleaved in
    one process, 119 -> 103 us median hot (another run: 129 -> 121 hot, 149 -> 144 cold)
    against one pass over every state in eight interleaved parts (as :func:`_largest`; half
    of it zeros); a reassociating maximum in :func:`_largest`'s place was slower (103 -> 138
    us)."""
    total = 0.0
    for j in range(v.size):
        total += v[j]
    return total


@compiled(None, *_CALLS_INTO, fastmath=CONTRACT, inline="always")
def _entry_weights(a, alpha, s_all, base, n, ti, a0, a1, entries) -> None:
    """A member's threshold weights afresh (:func:`behaviors.mop.threshold._entry_weights`):
    ``a`` its ergodic states', each chain form's ``s_all`` further on each (templates
    ``a0..a1``; its states from ``base``, ``n`` of them)."""
    a[:] = _F32(1.0 / entries)
    for c in range(_FORMS):
        alpha[(c + 1) * s_all + base:(c + 1) * s_all + base + n] = _ZERO32
        for k in range(a0, a1):
            at = ti[k, 2] + ti[k, 0] + (ti[k, 1] - 1 if _BACKWARD[c] else 0)
            alpha[(c + 1) * s_all + at] = _F32(1.0 / entries)


@compiled(numba.float64(_S2, _I2, _F1, numba.intp, numba.intp, _F2, _F1, _S1, _S1,
                        numba.boolean, _F1, numba.intp, _F1), *_CALLS_INTO, fastmath=CONTRACT)
def threshold_step(means, ti, m, a0, a1, zs, ljs, alpha, ll, fresh, totals, i, tops_k) -> float:
    """:func:`behaviors.mop.threshold.threshold_model_step` of one member (templates
    ``a0..a1``, its states' columns of ``means`` (D, S) and rows of ``alpha`` ((1 + C) S,) in
    order: the ergodic states' first, each chain form's (:data:`behaviors.mop.threshold.CHAINS`)
    at the same places in each further S) with its sample seen by each template as
    :meth:`Refusal._threshold_evidence` maps it (``zs`` (K, 3 D): the sample, then each
    template's first and last state) and each template's log-density terms ``ljs`` (K,: the
    Gaussian's constant and the map's log Jacobian), as :func:`update_templates` left them
    (``m``: the member's row of ``mc``; ``ll``: scratch of 1 + C times the largest member's
    states, each chain form's log-densities in its own part; ``tops_k`` ((1 + 2 C) K,): each
    template's likeliest state, then each chain's (scratch), then each chain's summed weight,
    kept for the next step); returns the sample's log-likelihood. Each chain form's distances
    are taken in the same pass over the template's states as the ergodic ones (its sample
    mirrored or moved instead of its states: the states are read once). A chain that held no
    weight takes it where it begins only: no pass over it but its distances; a chain's prior
    is summed move by move in its template's ergodic log-densities' place once they are read,
    so that its passes vectorise too. Its sum is taken template by template (:func:`_summed`,
    the same to about 1e-16) and its exponentials by
    :func:`~behaviors.mop.compiled.exp_neg32`, so every loop over the states vectorises
    (DESIGN's 8 x 100 templates: 80 000 states per tick). The weights are kept as summed:
    member ``i``'s are ``alpha`` divided by ``totals[i]``, the division done as they are read
    at the next step (as a product by ``STAY / totals[i]``; about the same numbers as
    normalising them at once, one pass over the states fewer).

    Most states weigh nothing (in DESIGN's case about a quarter are within e^-40 of the
    likeliest), and so do whole templates (43 % of them): a template whose likeliest state
    lies further than that below the member's likeliest gets zero weights without an
    exponential (hot 348 -> 306 us for 8 members, cold 546 -> 509 us p10, same numbers).
    Skipping also the distances of chunks of 16 states whose bounding box lay that far below
    the likeliest state found so far computed a third of the states, but with the caches cold
    it was slower: 8 members 537 -> 612 us p10 (hot 379 -> 330), the skipped stretches
    breaking the streams the processor fetches ahead.

    In single precision (:data:`behaviors.mop.threshold.PRECISION`: ``means``, ``alpha``,
    ``ll`` float32, their arithmetic too, by :func:`~behaviors.mop.compiled.exp_neg32`; the
    sum and the result in double): eight states to a vector instead of four and half the
    memory. 8 members on DESIGN's real state, interleaved in one process: 197 -> 125 us median
    hot, 207 -> 135 cold (dividing by the total, as before, instead of multiplying by its
    inverse: 197 -> 190 alone); DESIGN's tick 1272, 1232, 1254 -> 1103, 1070, 1144 us median
    thread time (update_templates 617, 593, 599 -> 484, 494, 511; alternating runs, load 4-8).
    Its log-likelihood moves by about 3e-7 relative; every figure of ``bench/follow_quality.py
    --sections=sized,holds,sequences,unrelated,after`` stayed the same. A coarser model, every
    second state of each template (half the states, in both twins), refused less there:
    unrelated valid share 0.0394 -> 0.0403 (20 templates 0.0467 -> 0.0483, a diagonal 0.051
    -> 0.059), valid after the gestures 0.0790 -> 0.0795; not taken."""
    d = means.shape[0]
    factor = _F32(m[19])
    base = ti[a0, 2]
    part = ll.shape[0] // (_FORMS + 1)   # each chain form's log-densities from c * part
    kk = tops_k.shape[0] // (2 * _FORMS + 1)   # chains' likeliest from kk, their sums after
    zc = np.empty((_FORMS + 1, d), dtype=np.float32)   # the sample as each form sees it
    n = 0
    top = _NEG_INF32
    for k in range(a0, a1):
        first, length = ti[k, 2] + ti[k, 0], ti[k, 1]
        lj = _F32(ljs[k])
        lo = first - base
        for c in range(d):
            zc[0, c] = _F32(zs[k, c])
            for f in range(_FORMS):
                o = zs[k, 2 * d + c] if _BACKWARD[f] else zs[k, d + c]
                sign = (_SX[f] if c == 0 else _SY[f]) if c < 2 else 1.0
                zc[f + 1, c] = _F32(sign * (zs[k, c] - zs[k, d + c]) + o)
        for f in range(_FORMS + 1):
            out = ll[f * part + lo:f * part + lo + length]
            if f > 0 and not fresh and not tops_k[(_FORMS + f) * kk + k] > 0.0:
                # a chain holding no weight can take some only where it begins: its other
                # states are left out (threshold_model_step)
                b = length - 1 if _BACKWARD[f - 1] else 0
                s2 = _ZERO32
                for c in range(d):
                    e = zc[f, c] - means[c, first + b]
                    s2 += e * e
                out[b] = s2 * factor + lj
                tops_k[f * kk + k] = out[b]
                top = max(top, out[b])
                continue
            if d == 2:   # a puck's case, in one pass (the same operations)
                m0, m1 = means[0, first:first + length], means[1, first:first + length]
                z0, z1 = zc[f, 0], zc[f, 1]
                for j in range(length):
                    e0 = z0 - m0[j]
                    e1 = z1 - m1[j]
                    out[j] = (e0 * e0 + e1 * e1) * factor + lj
            else:
                out[:] = _ZERO32
                for c in range(1, d):   # column by column (``means`` is (D, S)): vectorised
                    zf, mc_ = zc[f, c], means[c, first:first + length]
                    for j in range(length):
                        e = zf - mc_[j]
                        out[j] += e * e
                z0, m0 = zc[f, 0], means[0, first:first + length]
                for j in range(length):
                    e0 = z0 - m0[j]
                    out[j] = (e0 * e0 + out[j]) * factor + lj
            tf = _largest(ll, f * part + lo, f * part + lo + length)
            tops_k[f * kk + k] = tf
            top = max(top, tf)
        n += length
    # views from 0 (indices the compiler knows are not negative: the loops vectorise)
    s_all = alpha.shape[0] // (_FORMS + 1)
    a, v = alpha[base:base + n], ll[:n]
    entries = n + _FORMS * (a1 - a0)   # where the jumps land: every ergodic state, chains' start
    sums = (_FORMS + 1) * kk   # each chain's summed weight from here (form by form)
    total_was = totals[i]
    if fresh:
        _entry_weights(a, alpha, s_all, base, n, ti, a0, a1, entries)
        total_was = 1.0
    chained = 0.0   # the chains' share: their sums at the last step (or their first states')
    if fresh:
        chained = _FORMS * (a1 - a0) / entries
    else:
        for f in range(_FORMS):
            for k in range(a0, a1):
                chained += tops_k[sums + f * kk + k]
        chained /= total_was
    keep = _F32(THRESHOLD_STAY / total_was)   # (a product, not a quotient)
    kc = _F32(CHAIN_KEEP / total_was)
    rest = _F32(((1.0 - THRESHOLD_STAY) * (1.0 - chained) + (1.0 - CHAIN_KEEP) * chained)
                / entries)
    least = max(_TINY32, rest * _LEAST32)   # a chain's state weighing less weighs nothing
    cut = top + _FLOOR32
    total = 0.0
    for k in range(a0, a1):
        lo = ti[k, 2] + ti[k, 0] - base
        hi = lo + ti[k, 1]
        length = hi - lo
        ak, vk = a[lo:hi], v[lo:hi]
        if tops_k[k] < cut:   # the whole template under e^-40 of the likeliest state
            ak[:] = _ZERO32
        else:
            for j in range(length):   # no weight under e^-40 (threshold_model_step)
                e = vk[j] - top
                w = (keep * ak[j] + rest) * exp_neg32(max(e, _FLOOR32))
                ak[j] = w if e >= _FLOOR32 else _ZERO32
            total += _summed(ak)
        for f in range(_FORMS):
            mk = alpha[(f + 1) * s_all + base + lo:(f + 1) * s_all + base + hi]
            mvk = ll[(f + 1) * part + lo:(f + 1) * part + hi]
            at = sums + f * kk + k   # its summed weight
            held = fresh or tops_k[at] > 0.0   # the chain held weight
            if tops_k[(f + 1) * kk + k] < cut:   # ... likewise under e^-40 of the likeliest
                if held:
                    mk[:] = _ZERO32
                tops_k[at] = 0.0
                continue
            begin = length - 1 if _BACKWARD[f] else 0   # where it begins: the jumps land there
            if not held:   # weight enters an empty chain where it begins only (the rest stay 0)
                e = mvk[begin] - top
                w = rest * exp_neg32(max(e, _FLOOR32))
                mk[begin] = w if e >= _FLOOR32 and w >= least else _ZERO32
                total += mk[begin]
                tops_k[at] = mk[begin]
                continue
            # its prior, in the ergodic log-densities' place (read): one pass per move
            for p in range(length):
                vk[p] = _W0 * mk[p]
            if _BACKWARD[f]:   # from the states after it in its template
                for p in range(length - 1):
                    vk[p] += _W1 * mk[p + 1]
                for p in range(length - 2):
                    vk[p] += _W2 * mk[p + 2]
                for p in range(length - 3):
                    vk[p] += _W3 * mk[p + 3]
            else:
                for p in range(1, length):
                    vk[p] += _W1 * mk[p - 1]
                for p in range(2, length):
                    vk[p] += _W2 * mk[p - 2]
                for p in range(3, length):
                    vk[p] += _W3 * mk[p - 3]
            for p in range(length):
                e = mvk[p] - top
                w = kc * vk[p] * exp_neg32(max(e, _FLOOR32))
                mk[p] = w if e >= _FLOOR32 and w >= least else _ZERO32   # (threshold.CHAIN_LEAST)
            e = mvk[begin] - top
            w = (kc * vk[begin] + rest) * exp_neg32(max(e, _FLOOR32))
            mk[begin] = w if e >= _FLOOR32 and w >= least else _ZERO32
            held_now = _summed(mk)
            total += held_now
            tops_k[at] = held_now
    if total <= 0.0:   # the likeliest states only chain states no weight reached: afresh
        _entry_weights(a, alpha, s_all, base, n, ti, a0, a1, entries)
        for f in range(_FORMS):
            tops_k[sums + f * kk + a0:sums + f * kk + a1] = 1.0 / entries
        totals[i] = 1.0
        return float(top + _FLOOR32)
    totals[i] = total
    return float(top) + math.log(total)
