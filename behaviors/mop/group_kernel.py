"""A follower group's per-template rules after a forward step, compiled: one pass over every
template of every member.

:meth:`ActionFollower._finish <behaviors.mop.follower.ActionFollower._finish>` and the shape
rules it applies (:mod:`behaviors.mop.validity`, :mod:`behaviors.mop.spotting`) update a dozen
arrays over the templates after each step: followed state, size estimate, evidence, refusal with
hysteresis, engagement, probabilities, path misfit and coverage, shape sums. Written as array
operations over the group's templates (``behaviors/mop/group.py`` before this module) that was
about 150 numpy calls per tick, most of DESIGN's 8 performers x 100 templates tick after the
forward step; here it is one loop per template, in the same order of operations as the
follower's own array code (the group stays equal to its followers stepped alone), followed per
member by its likeliest template, best (with the switch margin), top three and shape lead.
"""

from __future__ import annotations

import math

import numba
import numpy as np

_F1, _F2, _F3 = numba.float64[::1], numba.float64[:, ::1], numba.float64[:, :, ::1]
_I1, _B1 = numba.intp[::1], numba.boolean[::1]
_I2 = numba.intp[:, ::1]

#: Per-template float constants, in this order (see :meth:`FollowerGroup._kernel_arrays`).
CONSTANTS = ("_jacobian", "_dims", "_decay", "_null_decay", "_onset_state", "_log_constant",
             "_two_over", "_null2", "_accept2", "_onset_sigma", "_scaled", "_prior", "_lo", "_hi",
             "_misfit_decay", "_shape2", "_shape_accept2", "_path_scale", "_k_spots", "_arc_need")
#: Per-template float state updated in place, in this order.
FLOATS = ("_evidence", "_recent", "_recent_weight", "_num", "_den", "_size", "_misfit_w", "_shape")
#: Per-template flags updated in place, in this order.
FLAGS = ("_refused", "_engaged", "_misshaped", "_covered")
#: Per-template (K, D) constants, in this order.
ROWS = ("_scale", "_k_center", "_k_ufirst", "_k_c", "_k_radius")


@numba.njit(numba.void(_F1, numba.intp, numba.intp, _I1), cache=True, nogil=True)
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


@numba.njit(numba.intp(_F1, numba.intp, numba.intp), cache=True, nogil=True)
def first_max(values: np.ndarray, a0: int, a1: int) -> int:
    """The index of the first largest of ``values[a0:a1]`` (``a0 + np.argmax``)."""
    best = a0
    for k in range(a0 + 1, a1):
        if values[k] > values[best]:
            best = k
    return best


@numba.njit(numba.void(numba.types.UniTuple(_F1, len(CONSTANTS)), numba.types.UniTuple(_F2, len(ROWS)),
                       _B1, _I1, _I1, _I1, _F1, _F1, _F1, _F2, _F2, _F2,
                       numba.types.UniTuple(_F1, len(FLOATS)), numba.types.UniTuple(_B1, len(FLAGS)),
                       _F2, numba.int64[::1], _F1, numba.int64[::1], _F1,
                       _F2, _F2, _F2, _F3, _I1, _I1, _I1, _I1, _F1,
                       numba.intp, numba.intp, numba.float64, numba.float64,
                       _F1, _I1, _F1, _F1, _F1, _F1, _B1, _I2, _F1, _B1, _B1, _B1),
            cache=True, nogil=True)
def update_templates(consts, rows, k_none, starts, lengths, state_off, source, dsource, arc,
                     rel, drel, path, floats, flags, misfit, entries, mean, fw_entries, step_ll,
                     x, anchor, m_units, buf, nbuf, bounds, counts, best, margin,
                     before, after, rival_p, min_lead, g_out, gs_out, frac_out, progress_out,
                     mean_ll_out, p_out, new_out, top3_out, moving_out, any_engaged,
                     all_refused, leads_out) -> None:
    """After one forward step (``mean``, ``fw_entries``, ``step_ll`` per template), each
    template's followed state and per-template rules, member by member (``x``, ``anchor``,
    ``m_units`` (M, D): each member's sample, anchor and units; ``buf``/``nbuf``: its recent
    samples; ``bounds``/``counts``: its first template and template count), then each member's
    likeliest template, best, top three and shape lead.

    In place: ``floats`` (see :data:`FLOATS`), ``flags`` (:data:`FLAGS`), ``misfit`` (K, 3)
    sums, ``entries`` and ``best`` (M,: each member's own template index, switched when another
    leads by ``margin`` (M,) nats or it is refused). Out per template: followed state ``g``
    (bank index), its state ``gs`` (group index) and fraction, progress, recent mean
    log-likelihood, probability, whether its performance began anew; per member: top three by probability (-1 where fewer), the largest RMS
    displacement from the anchor (template units and size), any engaged, all refused, whether
    ``best`` leads every rival (not refused, probability at least ``rival_p``) in shape by
    ``min_lead``. ``before``/``after``: the path's reach in states."""
    (jacobian, dims, decay, null_decay, onset_state, log_constant, two_over, null2, accept2,
     onset_sigma, scaled, prior, lo, hi, misfit_decay, shape2, shape_accept2, path_scale,
     k_spots, arc_need) = consts
    scale, center, ufirst, c_off, radius = rows
    ev, rec, rw, num, den, size, misfit_w, shape = floats
    refused, engaged, misshaped, covered = flags
    d = x.shape[1]
    s = buf.shape[1]
    u = np.empty(d)
    z = np.empty(d)
    v = np.empty(d)
    away = np.empty(d)
    dx = np.empty(d)
    for i in range(bounds.size):
        a0 = bounds[i]
        a1 = a0 + counts[i]
        # the mean of the last 3 buffered samples and this one (the engagement's displacement)
        n = min(nbuf[i], 3)
        for c in range(d):
            tot = 0.0
            for r in range(s - n, s):
                tot += buf[i, r, c]
            away[c] = (tot + x[i, c]) / (n + 1) - anchor[i, c]
            dx[c] = x[i, c] - anchor[i, c]
        moving = 0.0
        for k in range(a0, a1):
            # followed state and progress (ActionFollower._finish)
            lk = lengths[k]
            g = starts[k] + min(mean[k], lk - 1.0)
            gi = min(int(g), starts[k] + lk - 2)
            frac = g - gi
            gs = gi + state_off[k]
            g_out[k] = g
            gs_out[k] = gs
            frac_out[k] = frac
            progress_out[k] = source[gs] + frac * dsource[gs]
            if scaled[k] > 0.0:   # PerformanceFrame._estimate_size
                qr = 0.0
                qq = 0.0
                for c in range(d):
                    q = rel[gs, c] + frac * drel[gs, c]
                    qr += q * (dx[c] / m_units[i, c])
                    qq += q * q
                num[k] += qr
                den[k] += qq
                size[k] = min(max((num[k] + prior[k]) / (den[k] + prior[k]), lo[k]), hi[k])
            sk = size[k]
            raw = step_ll[k] - jacobian[k]
            raw -= dims[k] * math.log(sk)
            ev[k] = ev[k] * decay[k] + raw
            rec[k] = rec[k] * null_decay[k] + step_ll[k]
            rw[k] = rw[k] * null_decay[k] + 1.0
            new = fw_entries[k] > entries[k]
            entries[k] = fw_entries[k]
            # a refused template back at its start and matching it begins anew
            if refused[k] and mean[k] < onset_state[k] and \
                    (log_constant[k] - step_ll[k]) * two_over[k] <= null2[k]:
                new = True
            if new:
                rec[k] = log_constant[k]
                rw[k] = 1.0
                refused[k] = False
                engaged[k] = False
            new_out[k] = new
            mll = rec[k] / rw[k]
            mean_ll_out[k] = mll
            dist2 = (log_constant[k] - mll) * two_over[k]
            refused[k] = (refused[k] or dist2 > null2[k]) and not dist2 < accept2[k]
            ssz = sk if scaled[k] > 0.0 else 1.0
            if mean[k] >= onset_state[k] and not refused[k] and not engaged[k]:
                acc = 0.0
                for c in range(d):
                    r = away[c] / scale[k, c] / sk
                    acc += r * r
                engaged[k] = math.sqrt(acc / dims[k]) >= onset_sigma[k]
            # path misfit and coverage (Validity._judge_shape)
            if new:
                misfit[k, 0] = 0.0
                misfit[k, 1] = 0.0
                misfit[k, 2] = 0.0
                misfit_w[k] = 0.0
                misshaped[k] = False
                covered[k] = False
            for c in range(d):
                base = center[k, c] if k_none[k] else anchor[i, c]
                u[c] = (x[i, c] - base) / scale[k, c] + ufirst[k, c]
                z[c] = u[c] / ssz + c_off[k, c]
            gf = int(math.floor(g))
            last = starts[k] + lk - 1
            best_d = np.inf
            for o in range(-before, after + 1):
                st = min(max(gf + o, starts[k]), last) + state_off[k]
                za = 0.0
                for c in range(d):
                    za += (z[c] - path[st, c]) * path[st, d + c]
                t = min(max(za * path[st, 2 * d], 0.0), 1.0)
                dd = 0.0
                for c in range(d):
                    e = (z[c] - path[st, c]) - t * path[st, d + c]
                    dd += e * e
                if dd < best_d:
                    best_d = dd
                    for c in range(d):
                        v[c] = path[st, c] + t * path[st, d + c]
            uu = 0.0
            uv = 0.0
            vv = 0.0
            for c in range(d):
                vc = v[c] - c_off[k, c]
                uu += u[c] * u[c]
                uv += u[c] * vc
                vv += vc * vc
            md = misfit_decay[k]
            misfit[k, 0] = misfit[k, 0] * md + uu
            misfit[k, 1] = misfit[k, 1] * md + uv
            misfit[k, 2] = misfit[k, 2] * md + vv
            misfit_w[k] = misfit_w[k] * md + 1.0
            m2 = (misfit[k, 0] / (ssz * ssz) - 2.0 * misfit[k, 1] / ssz + misfit[k, 2]) / misfit_w[k]
            m2 *= 1.0 / path_scale[k]
            misshaped[k] = (misshaped[k] or m2 > shape2[k]) and not m2 < shape_accept2[k]
            at = gf + state_off[k]
            nxt = min(gf + 1, last) + state_off[k]
            if engaged[k] and arc[at] + (g - gf) * (arc[nxt] - arc[at]) >= arc_need[k]:
                covered[k] = True
            # shape sums (GestureSpotting._leads) and displacement (early feedback)
            acc = 0.0
            mv = 0.0
            for c in range(d):
                q = rel[gs, c] + frac * drel[gs, c]
                e = (dx[c] - sk * q * m_units[i, c]) / radius[k, c]
                acc += e * e
                r = dx[c] / scale[k, c] / ssz
                mv += r * r
            shape[k] += acc * k_spots[k]
            mv = math.sqrt(mv / dims[k])
            if mv > moving:
                moving = mv
        moving_out[i] = moving
        # probabilities, likeliest template, best (with the switch margin), top three, any/all
        first = first_max(ev, a0, a1)
        top = ev[first]
        tot = 0.0
        eng = False
        ref = True
        for k in range(a0, a1):
            p_out[k] = math.exp(ev[k] - top)
            tot += p_out[k]
            eng = eng or engaged[k]
            ref = ref and refused[k]
        any_engaged[i] = eng
        all_refused[i] = ref
        for k in range(a0, a1):
            p_out[k] /= tot
        top_three(p_out, a0, a1, top3_out[i])
        gb = a0 + best[i]
        if ev[first] - ev[gb] > margin[i] or refused[gb]:
            gb = first
        best[i] = gb - a0
        rival = np.inf
        for k in range(a0, a1):
            if k != gb and not refused[k] and p_out[k] >= rival_p and shape[k] < rival:
                rival = shape[k]
        leads_out[i] = rival == np.inf or rival - shape[gb] >= min_lead
