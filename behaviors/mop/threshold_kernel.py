"""A follower group's threshold models (:mod:`behaviors.mop.threshold`), compiled: one
member's step over every state of its templates, as
:func:`behaviors.mop.group_kernel.update_templates` left the sample mapped by each template,
and its evidence stepped with it (:func:`threshold_evidence`).
"""

from __future__ import annotations

import math

import numba
import numpy as np
from llvmlite import ir
from numba.core import cgutils
from numba.extending import intrinsic

import behaviors.mop.compiled
from behaviors.mop import threshold
from behaviors.mop.compiled import CONTRACT, exp_neg32
from behaviors.mop.compiled import fma as _fma
from behaviors.mop.threshold import MIRROR_KEEP, MIRROR_MOVES, TINY
from behaviors.mop.threshold import STILL_RADII as THRESHOLD_STILL_RADII
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
_TINY32 = _F32(TINY)
_W0, _W1, _W2, _W3 = (_F32(w) for w in MIRROR_MOVES)


_U = numba.uintp   # an index known to be >= 0: no wrap-around of negative indices
_I32 = np.int32


@intrinsic
def _larger(typingctx, a, b):
    """The larger of the float32 ``a`` and ``b`` (``llvm.maxnum``), flagged free of NaNs and of
    signed zeros' order, so that a running maximum over a loop becomes vector maxima (the
    compiler's ``max`` is a compare and a select, which it keeps scalar). The threshold model's
    log-densities are finite or infinite, never NaN (the samples are checked finite), and the
    sign of a zero maximum changes nothing it is used for.

    Taken in the distance pass of :func:`threshold_step` (each template's likeliest state of
    both twins): the pass and its maxima vectorised in one loop, where the maxima had been a
    second, scalar pass over both twins' log-densities in eight interleaved parts (the
    compiler's ``max`` vectorised in no form: in the distance pass as eight locals, as
    ``llvm.maxnum`` without the flags, as a chain with ``nnan``/``nsz`` fast-math in a function
    of its own). 8 members stepped over 40 successive ticks of DESIGN's real state, interleaved
    in one process, three runs at load 12-15: 156, 183, 197 -> 141, 164, 172 us median hot, 180,
    212, 303 -> 173, 194, 280 with the caches cold; the same numbers to the bit (every output of
    the step, and every state of the group's followers over 1600 ticks)."""
    def codegen(context, builder, signature, args):
        fn = cgutils.get_or_insert_function(
            builder.module, ir.FunctionType(args[0].type, [args[0].type] * 2), "llvm.maxnum.f32")
        return builder.call(fn, args, fastmath=("nnan", "nsz"))
    return a(a, b), codegen


@compiled(numba.float64(_S1), *_CALLS_INTO, fastmath=CONTRACT | {"reassoc"})
def _summed(v: np.ndarray) -> float:
    """The sum of the float32 ``v`` in double precision, in any order (``reassoc``: the loop
    vectorises; the same to about 1e-16). Called for each template of :func:`threshold_step`
    with any weight, the others' being zeros: 8 members on DESIGN's real state, interleaved in
    one process, 119 -> 103 us median hot (another run: 129 -> 121 hot, 149 -> 144 cold)
    against one pass over every state in eight interleaved parts (half of it zeros); a
    reassociating maximum in place of the eight-part maxima then taken was slower (103 -> 138
    us)."""
    total = 0.0
    for j in range(v.size):
        total += v[j]
    return total


@compiled(None, *_CALLS_INTO, fastmath=CONTRACT, inline="always")
def _entry_weights(a, ma, ti, a0, a1, base, entries) -> None:
    """A member's threshold weights afresh (:func:`behaviors.mop.threshold._entry_weights`):
    ``a`` its ergodic states', ``ma`` its mirror chains' (templates ``a0..a1``)."""
    a[:] = _F32(1.0 / entries)
    ma[:] = _ZERO32
    for k in range(a0, a1):
        ma[ti[k, 2] + ti[k, 0] - base] = _F32(1.0 / entries)


@compiled(None, *_CALLS_INTO, fastmath=CONTRACT, inline="always")
def _held(w: np.ndarray, n: int) -> tuple[int, int]:
    """The first and one past the last of the states ``0..n`` whose weight ``w`` is above zero
    (``n``, 0 if none), in one pass that vectorises (index minima and maxima in 32 bits)."""
    first, last = _I32(n), _I32(-1)
    for j in range(n):
        held = w[j] > _ZERO32
        first = min(first, _I32(j) if held else _I32(n))
        last = max(last, _I32(j) if held else _I32(-1))
    return first, last + _I32(1)


@compiled(None, *_CALLS_INTO, fastmath=CONTRACT, inline="always")
def _whole(a: int, b: int, n: int) -> tuple[int, int]:
    """The states ``a..b`` widened within ``0..n`` to 8 m + 1 of them (m >= 1 if ``n`` allows):
    the compiler takes a loop's first state apart and the rest in vectors of eight, any left
    over one by one (a single-precision exponential each costs about a vector's)."""
    m = (max(b - a, 1) + 6) // 8 * 8 + 1
    end = min(a + m, n)
    return max(end - m, 0), end


# Without numba's reference counts (``_nrt=False``): its eight slices a template each took a
# locked increment and decrement (with update_templates', a fifth of DESIGN's group tick).
# The group's outputs moved by at most 2e-11 relative (no best, validity or likely changed).
@compiled(numba.float64(_S2, _I2, _F1, numba.intp, numba.intp, _F2, _F1, _S1, _S1,
                        numba.boolean, _F1, numba.intp, _F1), *_CALLS_INTO, fastmath=CONTRACT,
          _nrt=False)
def threshold_step(means, ti, m, a0, a1, zs, ljs, alpha, ll, fresh, totals, i, tops_k) -> float:
    """:func:`behaviors.mop.threshold.threshold_model_step` of one member (templates
    ``a0..a1``, its states' columns of ``means`` (D, S) and rows of ``alpha`` in order: the
    ergodic states' in its first half, the mirror chains' at the same places in its second)
    with its sample seen by each template as :meth:`ThresholdLead._threshold_evidence` maps it
    (``zs`` (K, D + 1), the last column its first coordinate mirrored) and each template's
    log-density terms ``ljs`` (K,: the Gaussian's constant and the map's log Jacobian), as
    :func:`update_templates` left them (``m``: the member's row of ``mc``; ``ll``: scratch of
    twice the largest member's states, the mirror chains' in its second half; ``tops_k``
    (3K,): each template's likeliest state, then each chain's (scratch), then each chain's
    summed weight, kept for the next step); returns the sample's log-likelihood. A chain that
    held no weight takes it at its first state only: no pass over it but its distances; one
    that held some, only where it held it and three states on (:func:`_held`); a chain's
    prior is summed move by move in its template's ergodic log-densities' place once they
    are read, so that its passes vectorise too. Its sum is taken template by template
    (:func:`_summed`, the same to about 1e-16) and its exponentials by
    :func:`~behaviors.mop.compiled.exp_neg32`, so every loop over the states vectorises
    (DESIGN's 8 x 100 templates: 80 000 states per tick). The weights are kept as summed:
    member ``i``'s are ``alpha`` divided by ``totals[i]``, the division done as they are read
    at the next step (as a product by ``STAY / totals[i]``; about the same numbers as
    normalising them at once, one pass over the states
    fewer).

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
    d = zs.shape[1] - 1
    factor = _F32(m[19])
    base = ti[a0, 2]
    half = ll.shape[0] // 2   # the mirror chains' log-densities from here
    kk = tops_k.shape[0] // 3   # ... and their likeliest from here (their sums from 2 kk)
    n = 0
    top = _NEG_INF32
    for k in range(a0, a1):
        first, length = ti[k, 2] + ti[k, 0], ti[k, 1]
        out = ll[first - base:first - base + length]
        mout = ll[half + first - base:half + first - base + length]
        lj = _F32(ljs[k])
        z0, zm = _F32(zs[k, 0]), _F32(zs[k, d])
        m0 = means[0, first:first + length]
        tk = tm = _NEG_INF32   # its likeliest state's log-density, and its mirror chain's
        if d == 2:   # a puck's case, in one pass (the same operations)
            z1 = _F32(zs[k, 1])
            m1 = means[1, first:first + length]
            for j in range(length):
                e1 = z1 - m1[j]
                s1 = e1 * e1
                e0 = z0 - m0[j]
                f0 = zm - m0[j]
                o = (e0 * e0 + s1) * factor + lj
                mo = (f0 * f0 + s1) * factor + lj
                out[j] = o
                mout[j] = mo
                tk = _larger(tk, o)
                tm = _larger(tm, mo)
        else:
            out[:] = _ZERO32
            for c in range(1, d):   # column by column (``means`` is (D, S)): the loops vectorise
                zc, mc_ = _F32(zs[k, c]), means[c, first:first + length]
                for j in range(length):
                    e = zc - mc_[j]
                    out[j] += e * e
            for j in range(length):
                e0 = z0 - m0[j]
                f0 = zm - m0[j]
                mo = (f0 * f0 + out[j]) * factor + lj
                o = (e0 * e0 + out[j]) * factor + lj
                mout[j] = mo
                out[j] = o
                tk = _larger(tk, o)
                tm = _larger(tm, mo)
        tops_k[k] = tk
        tops_k[kk + k] = tm
        top = max(top, max(tk, tm))
        n += length
    # views from 0 (indices the compiler knows are not negative: the loops vectorise)
    s_all = alpha.shape[0] // 2
    a, v = alpha[base:base + n], ll[:n]
    ma, mv = alpha[s_all + base:s_all + base + n], ll[half:half + n]
    entries = n + (a1 - a0)   # where the jumps land: every ergodic state, each chain's first
    total_was = totals[i]
    if fresh:
        _entry_weights(a, ma, ti, a0, a1, base, entries)
        total_was = 1.0
    chained = 0.0   # the chains' share: their sums at the last step (or their first states')
    for k in range(a0, a1):
        chained += 1.0 / entries if fresh else tops_k[2 * kk + k]
    chained /= total_was
    keep = _F32(THRESHOLD_STAY / total_was)   # (a product, not a quotient)
    kc = _F32(MIRROR_KEEP / total_was)
    rest = _F32(((1.0 - THRESHOLD_STAY) * (1.0 - chained) + (1.0 - MIRROR_KEEP) * chained)
                / entries)
    cut = top + _FLOOR32
    total = 0.0
    for k in range(a0, a1):
        lo = ti[k, 2] + ti[k, 0] - base
        hi = lo + ti[k, 1]
        ak, vk = a[lo:hi], v[lo:hi]
        if tops_k[k] < cut:   # the whole template under e^-40 of the likeliest state
            # (zeroed only where it held weight, its sum kept per template: 8 members on
            # DESIGN's real state, caches cold, 201.7 -> 200.0 and 186.5 -> 184.1 us median,
            # the same numbers: not taken)
            ak[:] = _ZERO32
        else:
            for j in range(hi - lo):   # no weight under e^-40 (threshold_model_step)
                e = vk[j] - top
                w = (keep * ak[j] + rest) * exp_neg32(max(e, _FLOOR32))
                ak[j] = w if e >= _FLOOR32 else _ZERO32
            total += _summed(ak)
        mk, mvk = ma[lo:hi], mv[lo:hi]
        held = fresh or tops_k[2 * kk + k] > 0.0   # its mirror chain held weight
        if tops_k[kk + k] < cut:   # ... likewise under e^-40 of the likeliest state
            if held:
                mk[:] = _ZERO32
            tops_k[2 * kk + k] = 0.0
            continue
        if not held:   # weight enters an empty chain at its first state only (the rest stay 0)
            e = mvk[0] - top
            w = rest * exp_neg32(max(e, _FLOOR32))
            mk[0] = w if e >= _FLOOR32 and w >= _TINY32 else _ZERO32
            total += mk[0]
            tops_k[2 * kk + k] = mk[0]
            continue
        # its prior, in the ergodic log-densities' place (read): vectorised once indexed
        # unsigned (``mk[p - 1]`` kept numba's wrap-around select of negative
        # indices: the passes ran state by state, a quarter of this kernel's perf samples;
        # DESIGN's tick, thread time after the view's frames, alternating processes at load
        # 19: median 1385, 1294 -> 1277, 1196 us, update_templates 737, 712 -> 649, 622 us;
        # bench/mop.py --design's CPU median 1.415 -> 1.249 ms, p99 2.30 -> 1.99 ms, medians of
        # five alternating runs at load 13-22; the same numbers to the bit).
        # The four moves in one pass, each added by one fused multiply-add as the pass per
        # move added it (so the same numbers to the bit: written as one sum, the compiler
        # fused its first two products the other way round): 8 members on DESIGN's real state,
        # interleaved in one process, 194.5, 182.6, 182.7 -> 184.6, 173.5, 175.7 us median
        # hot, 266.8, 348.9, 315.3 -> 256.7, 334.5, 295.7 cold (46 % of the chains hold weight)
        length = hi - lo
        for p in range(min(length, 3)):   # (the first state's prior is read below)
            acc = _W0 * mk[p]
            if p >= 1:
                acc = _fma(_W1, mk[p - 1], acc)
            if p >= 2:
                acc = _fma(_W2, mk[p - 2], acc)
            vk[p] = acc
        # Its prior and weights only where it held weight and three states on (about 13 of its
        # 100 states; outside, the prior is 0, so are the weights, and so they stay), widened
        # to 8 m + 1 states (:func:`_whole`): the same numbers to the bit (every output of the
        # step at 100 ticks of DESIGN's real state); 8 members on it, interleaved in one
        # process, load 6-7, three rounds each way: paired -27.5, -29.1, -28.1 us median hot,
        # -24.5, -27.4, -23.2 cold (of ~300 / ~500; swapped +32.8, +31.6, +23.7 / +20.0, +27.1,
        # +20.9). Refused: the same over the states within e^-40 of the likeliest with a prior
        # above zero (a pass to find them) in whole vectors of eight, +9 us (the first state
        # taken apart left seven to the scalar tail: why an earlier form over the support in
        # whole vectors gained nothing); that span in 8 m + 1 states, -16 hot, -4 cold; the
        # ergodic states' pass over their live span, +11 to +24 us (half their states live)
        f0, f1 = _held(mk, length)
        r0, r1 = _whole(f0, min(f1 + 3, length), length)
        for p in range(max(r0, 3), r1):
            u = _U(p)
            acc = _W0 * mk[u]
            acc = _fma(_W1, mk[u - _U(1)], acc)
            acc = _fma(_W2, mk[u - _U(2)], acc)
            vk[u] = _fma(_W3, mk[u - _U(3)], acc)
        sm, sw, sv = mk[r0:r1], vk[r0:r1], mvk[r0:r1]   # (views from 0: the loop vectorises)
        for p in range(r1 - r0):
            e = sv[p] - top
            w = kc * sw[p] * exp_neg32(max(e, _FLOOR32))
            sm[p] = w if e >= _FLOOR32 and w >= _TINY32 else _ZERO32   # (threshold.TINY)
        e = mvk[0] - top   # the chain's first state: the jumps land there too
        w = (kc * vk[0] + rest) * exp_neg32(max(e, _FLOOR32))
        mk[0] = w if e >= _FLOOR32 and w >= _TINY32 else _ZERO32
        held_now = _summed(mk)
        total += held_now
        tops_k[2 * kk + k] = held_now
    if total <= 0.0:   # the likeliest states only chain states no weight reached: afresh
        _entry_weights(a, ma, ti, a0, a1, base, entries)
        totals[i] = 1.0
        return float(top + _FLOOR32)
    totals[i] = total
    return float(top) + math.log(total)



@compiled(numba.void(_S2, _I2, _F1, numba.intp, numba.intp, _F2, _F1, _S1, _S1, _F1,
                     numba.intp, _F1, numba.float64, numba.float64, _F2, _F2,
                     numba.boolean[::1], _F1, numba.intp, numba.intp),
          *_CALLS_INTO, fastmath=CONTRACT, _nrt=False)
def threshold_evidence(means, ti, m, a0, a1, zs, ljs, alpha, ll, totals, i, tops_k, lead, decay,
                       x, seen, has_seen, ev, ra0, d) -> None:
    """Member ``i``'s threshold model stepped with its sample (:meth:`ThresholdLead.
    _threshold_evidence <behaviors.mop.threshold_lead.ThresholdLead._threshold_evidence>`): its
    evidence ``ev[i]`` forgotten at ``decay`` and added the step (:func:`threshold_step`, less
    the model's offset ``m[18]``), no more than ``lead`` (the template of most evidence's raw
    log-likelihood) at the first sample or one within
    :data:`~behaviors.mop.threshold.STILL_RADII` still radii (``m``'s columns from ``ra0``) of
    the last (``seen[i]``, ``has_seen[i]``: ``x[i]`` kept)."""
    step = threshold_step(means, ti, m, a0, a1, zs, ljs, alpha, ll, not has_seen[i], totals, i,
                          tops_k) - m[18]
    still = has_seen[i]
    for c in range(d):
        if abs(x[i, c] - seen[i, c]) > THRESHOLD_STILL_RADII * m[ra0 + c]:
            still = False
    if not has_seen[i] or still:
        step = min(step, lead)
    for c in range(d):
        seen[i, c] = x[i, c]
    has_seen[i] = True
    ev[i] = ev[i] * decay + step
