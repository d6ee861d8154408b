"""One step of :class:`~behaviors.mop.forward.WindowedForward` for every template, compiled.

Each template's step is a short loop over its window's states (at most ``2p + 1``): emissions,
transitions, normalisation, moments, re-entry and the window's move, fused in one pass with no
temporary arrays. Written as numpy operations over all templates at once (one ``(window,
templates)`` array per quantity, about 100 numpy calls per step), the step took 1.3 ms for
DESIGN's 8 performers x 100 templates on a quiet machine, most of it passes over memory and
call overhead; compiled, see ``bench/mop.py``. Same algorithm as
:func:`~behaviors.mop.forward.forward_reference` (the plain one, one template at a time), with
the same shortcuts as before (and exponentials by :func:`~behaviors.mop.compiled.exp_neg`): where a
main window lies on the first states, its first-states window holds only this step's restart mass
and is not computed (its floor of 1e-100 per state, below 1e-90 of the main window's own floor, is
left out), and log-weights below the window's best by more than 200 count as ``e^-200``.
"""

from __future__ import annotations

import math

import numba
import numpy as np

import behaviors.mop.compiled
from behaviors.mop import emissions
from behaviors.mop.compiled import CONTRACT, exp_neg, fma, prefetch
from behaviors.mop.emissions import distances, stretched_distances
from behaviors.kernel_cache import compiled

# the files whose compiled functions the kernels take in
_CALLS_INTO = (behaviors.mop.compiled, emissions)

START_FLOOR = 1e-100  # keeps the first-states windows' products far from subnormal numbers
CLAMP = -200.0        # log-weights below the window's best by more than this count as e^-200
AHEAD = 2             # templates ahead whose window states are fetched while one is stepped
# Indices that are never negative but that the compiler cannot prove so (``x[t - 1]``,
# ``stay[first + r]``) are cast to unsigned: numba then leaves out the wrap-around of negative
# indices, whose select made the compiler gather and scatter the loops' values one by one
# (vgatherqpd / vscatterqpd: slow on this machine) instead of loading and storing them as runs
# (step_windows alone on real states of DESIGN's group: 387 -> 319 us median, 356 -> 291 at
# best, interleaved, load 16; the same results to the bit).
_U = numba.uintp
_U1, _U2, _U3 = _U(1), _U(2), _U(3)
# The helpers below (and the emissions', :mod:`behaviors.mop.emissions`) are inlined into
# :func:`step_windows` (``inline="always"``: the same operations; as calls, step_windows alone
# on real states of DESIGN's group took 378 -> 361 and 397 -> 378 us at best, 410 -> 384 and
# 467 -> 464 us median, two interleaved runs at load 8).


@compiled(None, *_CALLS_INTO, fastmath=CONTRACT, inline="always")
def _transit(x: np.ndarray, y: np.ndarray, n: int, back: float, fwd: np.ndarray, at_start: bool,
             at_end: bool) -> None:
    """y = the transitions applied to window x (first ``n`` states): what moves before the
    first state stays there when ``at_start``, what moves past the last onto it when ``at_end``,
    else it leaves the window. Gathered per target state (a scatter's read-modify-writes made
    each state wait for the last: 3x slower)."""
    nf = fwd.size
    if nf <= 4:   # self, next and up to two skips: unrolled (absent ones weigh 0)
        f0 = fwd[0]
        f1 = fwd[1] if nf > 1 else 0.0
        f2 = fwd[2] if nf > 2 else 0.0
        f3 = fwd[3] if nf > 3 else 0.0
        for t in range(min(n, 3)):
            acc = f0 * x[t]
            if t >= 1:
                acc += f1 * x[t - 1]
            if t >= 2:
                acc += f2 * x[t - 2]
            y[t] = acc
        for t in range(min(n - 1, 3)):
            y[t] += back * x[t + 1]
        # the move back added in the same pass, each product by one fused multiply-add in the
        # order the compiler contracted the sum and the pass after it (f0 x[u] + f1 x[u - 1]
        # fused as fma(f0, x[u], f1 x[u - 1])): the same numbers to the bit. step_windows
        # alone on 100 real states of DESIGN's group, interleaved in one process, load 9-10,
        # medians of 8 rounds' paired differences: -5.3 us hot, -7.4 us cold (of ~400; the
        # harness' A/A: +9.5, -6.0); with the normalisation in the emissions' pass (below)
        # -27.9 hot, -16.4 cold
        for t in range(3, n - 1):
            u = _U(t)
            y[u] = fma(back, x[u + _U1], fma(f3, x[u - _U3], fma(f2, x[u - _U2],
                                                                fma(f0, x[u], f1 * x[u - _U1]))))
        if n > 3:
            u = _U(n - 1)
            y[u] = fma(f3, x[u - _U3], fma(f2, x[u - _U2], fma(f0, x[u], f1 * x[u - _U1])))
    else:
        for t in range(n):
            acc = 0.0
            for o in range(min(nf, t + 1)):
                acc += fwd[o] * x[t - o]
            if t + 1 < n:
                acc += back * x[t + 1]
            y[t] = acc
    if at_start:
        y[0] += back * x[0]
    if at_end:
        tail = 0.0
        for k in range(1, min(nf, n + 1)):
            w = 0.0
            for o in range(k, nf):
                w += fwd[o]
            tail += w * x[n - k]
        y[n - 1] += tail


_F1, _F2, _I1, _B1 = numba.float64[::1], numba.float64[:, ::1], numba.int64[::1], numba.boolean[::1]


@compiled(None, *_CALLS_INTO, fastmath=CONTRACT, inline="always")
def _dwell(x: np.ndarray, kept: np.ndarray, stay: np.ndarray, first: int, n: int) -> None:
    """kept = the part of window x (first ``n`` states, from bank state ``first``) that moves by
    the transitions: each state's share ``stay`` stays where it is (added after the move)."""
    for r in range(n):
        kept[r] = x[r] * (1.0 - stay[_U(first + r)])


@compiled(numba.float64(_F1, numba.intp), *_CALLS_INTO, fastmath=CONTRACT | {"reassoc"})
def _sum(x: np.ndarray, n: int) -> float:
    """The sum of ``x[:n]``, in any order (``reassoc``: the loop vectorises). With
    :func:`_moments`, for the window's sums that ran as one chain of additions each (every one
    waiting for the last): step_windows alone on real states of DESIGN's group, interleaved in
    one process, 237 -> 226 us median hot, 254 -> 244 with the caches cold; the sums differ in
    their last bits (``bench/follow_quality.py``: 9 of 182 figures moved, by 1e-15 relative)."""
    total = 0.0
    for r in range(n):
        total += x[r]
    return total


@compiled(numba.types.UniTuple(numba.float64, 3)(_F1, numba.intp), *_CALLS_INTO,
          fastmath=CONTRACT | {"reassoc"})
def _moments(x: np.ndarray, n: int) -> tuple[float, float, float]:
    """The moments ``sum x_r``, ``sum r x_r``, ``sum r^2 x_r`` over ``x[:n]``, in any order."""
    m0 = m1 = m2 = 0.0
    for r in range(n):
        m0 += x[r]
        m1 += r * x[r]
        m2 += r * r * x[r]
    return m0, m1, m2


# loaded from its cache (or compiled) when a follower or group is built, not at its first step;
# without numba's reference counts (``_nrt=False``; its working windows passed in as
# ``scratch``): each template's row views (``z[j]``, ``a[j]``, ``b[j]``) took a locked increment
# and decrement. DESIGN's group tick, thread time p10 in alternating processes at load 20-27:
# the forward step 306, 328, 340, 348 -> 246, 250, 257, 268 us; the same results to the bit.
@compiled(numba.void(_F2, _I1, _I1, _I1, _B1, _F2, _F2, _F2, _F1, _I1, _F1, _F2, _I1, _B1,
                     numba.int64, numba.float64, _F1, numba.float64, numba.float64, _F1, _F1,
                     _F1, _B1, _F2, _F2, _F1, _F1, _B1), *_CALLS_INTO, fastmath=CONTRACT,
          _nrt=False)
def step_windows(means: np.ndarray, starts: np.ndarray, wk: np.ndarray, max_lo: np.ndarray,
                 start_tail: np.ndarray, z: np.ndarray, a: np.ndarray, b: np.ndarray,
                 s: np.ndarray, lo: np.ndarray, mean: np.ndarray, mom: np.ndarray,
                 entries: np.ndarray, fresh: np.ndarray, half: int, back: float, fwd: np.ndarray,
                 eps: float, floor: float, const: np.ndarray, out: np.ndarray,
                 stay: np.ndarray, dwells: np.ndarray, scratch: np.ndarray,
                 tangent: np.ndarray, spans: np.ndarray, lift: np.ndarray,
                 stretched: np.ndarray) -> None:
    """Advance every template's windows by one step (see the module docstring).

    ``means`` (states, d) and ``z`` (K, d) prescaled by 1 / (sigma sqrt 2); ``a``, ``b`` (K, w):
    main and first-states windows, updated in place with ``s`` (normaliser), ``lo`` (window
    start), ``mean`` (progress in states), ``mom`` (3, K) (the moments of the main window before
    it moved) and ``entries``; ``fresh`` (K,): templates taking a first step (no transitions, no
    restart), cleared; ``out`` (K,): the step's log-likelihood. ``floor`` 0: the log domain, every
    first-states window computed. ``stay`` (states,): each state's share that stays before the
    transitions move the rest (a template's holds), used for the templates ``dwells`` (K,).
    ``scratch`` (7, w rounded up to 8): the working windows (overwritten). ``tangent``
    (states, d), ``spans``, ``lift`` (states,): each state's stretch along its path (direction,
    half-length prescaled, log normaliser; :mod:`behaviors.mop.stretch`), 0 for a point, read
    only for the templates ``stretched`` (K,)."""
    k, w = a.shape
    logs = floor <= 0.0
    start_floor = START_FLOOR if floor > 0.0 else 0.0
    # the weighed windows and their distances have room for whole vectors of eight: their
    # exponentials run over the window rounded up to eight states, the states past it unused
    # (weight 0, distance infinite): DESIGN's windows of 31 states left 7 exponentials a window
    # to a scalar loop that cost more than the 24 in vectors (with the stay shares fetched
    # early, below: step_windows alone on real states, interleaved, load 16: 384 -> 348 us
    # median, 304 -> 246 at best; the same results to the bit)
    w8 = (w + 7) // 8 * 8
    q, qs, lb, lbs = scratch[0], scratch[1], scratch[2], scratch[3]
    shifted, kept, kept_s = scratch[4], scratch[5], scratch[6]
    for r in range(w8):   # (as fresh arrays: zeros, and no state's distance yet)
        q[r] = qs[r] = 0.0
        lb[r] = lbs[r] = np.inf
    per_line = max(1, 8 // means.shape[1])   # state rows per 64-byte cache line
    for j in range(k):
        if j + AHEAD < k:   # the states the template a few ahead will read (both windows)
            h = j + AHEAD
            for r in range(0, wk[h], per_line):
                prefetch(means, starts[h] + lo[h] + r)
                if lo[h] > 0:
                    prefetch(means, starts[h] + r)
            if dwells[h]:   # ... and the shares of them that stay
                for r in range(0, wk[h], 8):
                    prefetch(stay, starts[h] + lo[h] + r)
                    if lo[h] > 0:
                        prefetch(stay, starts[h] + r)
        n = wk[j]
        lo0 = lo[j]
        first = fresh[j]
        fresh[j] = False   # (its next step is not a first one)
        ej = 0.0 if first else eps
        at_start = lo0 == 0
        full = logs or not at_start      # the first-states window computed in full
        n8 = (n + 7) // 8 * 8
        zj = z[j]
        if stretched[j]:
            m = stretched_distances(means, starts[j] + lo0, zj, n, lb, tangent, spans, lift)
            if full:
                m = min(m, stretched_distances(means, starts[j], zj, n, lbs, tangent, spans,
                                                lift))
        else:
            m = distances(means, starts[j] + lo0, zj, n, lb)
            if full:
                m = min(m, distances(means, starts[j], zj, n, lbs))
        for r in range(n, n8):   # (a longer window's states may lie there)
            lb[r] = lbs[r] = np.inf
        aj, bj = a[j], b[j]
        fl = floor / n
        cq, fq = 1.0, 0.0   # the main window's normalisation: q (c) + floor
        if first:
            for r in range(n):
                q[r] = aj[r] + fl
                if full:
                    qs[r] = bj[r] + start_floor
        else:
            # The transitions move the windows while the performer rests too: in a pause the
            # followed state settles 0.01-0.02 ahead of the still input. Measured and not kept
            # (bench/follow_quality.py; bench/follow_seeds.py --sections=sized,unrelated,
            # sequences), the state of the action driving, once it carried its performer forward
            # (validity.carried), held while they rest (tempo.resting) where it lies ahead of the
            # state nearest the input (its windows as they were; not within the first or last
            # 10% of it, nor within 9 states of a hold inside it): pauses valid 0.969 -> 0.977,
            # held through 0.957 -> 0.971 (held-out 0.950, 0.915 as before), progress drift
            # median 0.0097 -> 0.0078, held-out 0.0112 -> 0.0101 (p90 0.084 -> 0.048, 0.065 ->
            # 0.048), holds identical; held-out sized valid after 30% 101-106 mean 0.9084 ->
            # 0.9103 (104 0.910 -> 0.920), but 102 0.9036 -> 0.9022 (a 1.2x punch ankle re-sized
            # at its held state, 1.0 -> 0.87) and 101 lower by a sample, the progress RMSE median
            # up on four seeds (slow stretches read as rests). Held only 1 state ahead: 103 lower
            # too. Every template of a resting performer held from its state nearest the input on
            # (the emission then draws the state back): 102 0.8973, tuned hold backward 0.0013 ->
            # 0.0047; without the carried test, a wander's wrong take held through its last rest
            # (validity.stalls spares a resting state): unrelated worst 0.098 -> 0.111.
            # Held only once the performer really stopped (the rest read within 0.25 of its
            # radii, 3 reads in a row), so slow stretches are not: pauses valid 0.969 -> 0.970,
            # drift p90 0.084 -> 0.082 (held-out 0.065 -> 0.059), sized 101-106 as before but 104
            # up, yet 108's progress RMSE median 0.0198 -> 0.0202 (an unpaused 0.7x dance ankle:
            # its own foot stops held); 6 reads: held-out drift median 0.011238 -> 0.011244;
            # within 0.5, 7 reads: pauses 0.971, but 102 0.9036 -> 0.9022 (a real stop), 101 down.
            dw = dwells[j]
            xa, xb = aj, bj
            if dw:   # the held share of each hold state stays; the rest moves
                _dwell(aj, kept, stay, starts[j] + lo0, n)
                _dwell(bj, kept_s, stay, starts[j], n)
                xa, xb = kept, kept_s
            _transit(xa, q, n, back, fwd, at_start, lo0 == max_lo[j])
            if dw:
                for r in range(n):
                    q[r] += aj[r] - kept[r]
            tot = _sum(q, n)
            if full:
                _transit(xb, qs, n, back, fwd, True, start_tail[j])
                if dw:
                    for r in range(n):
                        qs[r] += bj[r] - kept_s[r]
                tot += _sum(qs, n)
            c = (1.0 - ej) / tot
            if logs:
                for r in range(n):
                    q[r] = q[r] * c + fl
            else:   # (the main window's in its emissions' pass, below: one pass fewer, the
                # same numbers to the bit; step_windows alone as for _transit's: -4.5 us hot,
                # -9.8 cold)
                cq, fq = c, fl
            if full:
                for r in range(n):
                    qs[r] = qs[r] * c + start_floor
                qs[0] += ej
        # observation probabilities; e0: the first state's (for the restart mass)
        e0 = 0.0
        if not logs:
            for r in range(n8):
                q[r] = (q[r] * cq + fq) * exp_neg(max(m - lb[r], CLAMP))
            if full:
                for r in range(n8):
                    qs[r] *= exp_neg(max(m - lbs[r], CLAMP))
            e0 = exp_neg(max(m - lb[0], CLAMP))
        else:
            top = -np.inf
            for r in range(n):
                q[r] = (math.log(q[r]) if q[r] > 0.0 else -np.inf) - lb[r]
                qs[r] = (math.log(qs[r]) if qs[r] > 0.0 else -np.inf) - lbs[r]
                top = max(top, q[r], qs[r])
            m = -top
            for r in range(n):
                q[r] = math.exp(max(q[r] + m, -600.0))
                qs[r] = math.exp(max(qs[r] + m, -600.0))
        m0, m1, m2 = _moments(q, n)
        restart = e0 * ej if (at_start and not logs) else 0.0
        total = m0 + restart
        start_mass = restart
        if full:
            start_mass = _sum(qs, n)
            total += start_mass
        s[j] = total
        out[j] = math.log(total) - m + const[j]
        # re-entry: a new performance holds more probability than the one followed so far
        switched = start_mass > m0
        if switched:
            for r in range(n):
                if full:
                    q[r] = qs[r]
                else:
                    q[r] = exp_neg(max(m - lb[r], CLAMP)) * START_FLOOR
            if not full:
                q[0] += e0 * ej
            for r in range(w):
                bj[r] = 0.0
            entries[j] += 1
            lo0 = 0
            m0, m1, m2 = _moments(q, n)
            restart = 0.0
            full = False
        elif full:
            for r in range(n):
                bj[r] = qs[r]
        mom[0, j], mom[1, j], mom[2, j] = m0, m1, m2
        mu = lo0 + m1 / m0
        mean[j] = mu
        new_lo = min(max(int(mu + 0.5) - half, 0), max_lo[j])
        shift = new_lo - lo0
        if shift != 0:
            for r in range(n):
                src = r + shift
                shifted[r] = q[src] if 0 <= src < n else 0.0
            for r in range(n):
                q[r] = shifted[r]
            if not logs and lo[j] == 0 and not switched:
                # a main window leaving the first states: its first-states window is this step's
                for r in range(n):
                    bj[r] = exp_neg(max(m - lb[r], CLAMP)) * START_FLOOR
                bj[0] += e0 * ej
                restart = 0.0
        lo[j] = new_lo
        for r in range(n):
            aj[r] = q[r]
        if new_lo == 0:
            # where the two windows coincide they are one
            aj[0] += restart
            if full:
                for r in range(n):
                    aj[r] += bj[r]
                    bj[r] = 0.0


@compiled(numba.void(numba.float64[:], numba.boolean[:], _F1, _F2, _F1, _I1, _F2, _I1,
                     numba.int64), *_CALLS_INTO, _nrt=False)
def seat_windows(states: np.ndarray, seated: np.ndarray, mean: np.ndarray, a: np.ndarray,
                 s: np.ndarray, lo: np.ndarray, mom: np.ndarray, max_lo: np.ndarray,
                 half: int) -> None:
    """:meth:`~behaviors.mop.forward.WindowedForward.seat`: each template whose ``states``
    (K,: a state from its first, -1 none) lies ahead of its ``mean`` has its main window's
    whole probability ``s`` on that state (window ``a``, start ``lo``, moments ``mom``), marked
    in ``seated``; ``states`` then cleared to -1 (left as it is where none is 0 or more).
    Compiled, with step_windows clearing ``fresh``: against the Python forms (a maximum over
    the group's strided column, the templates ahead, a numpy clear of ``fresh``) DESIGN's tick
    after the view's frames -50.0 and -10.4 us, back to back -18.2 and -42.0 (one group, the
    forms swapped tick by tick, 800 pairs, load 5-6; the same swap A/A +13.5, +8.0)."""
    k = states.size
    top = -np.inf
    for j in range(k):
        top = max(top, states[j])
    if top < 0.0:
        return
    for j in range(k):
        if states[j] > mean[j]:
            h = int(states[j])
            low = min(max(h - half, 0), max_lo[j])
            for r in range(a.shape[1]):
                a[j, r] = 0.0
            a[j, h - low] = s[j]
            lo[j] = low
            mean[j] = h
            mom[0, j], mom[1, j], mom[2, j] = 1.0, float(h), float(h * h)
            seated[j] = True
        states[j] = -1.0
