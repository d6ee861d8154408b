"""A follower group's per-template rules after a forward step, compiled: one pass over every
template of every member.

:meth:`ActionFollower._finish <behaviors.mop.follower.ActionFollower._finish>` and the shape
rules it applies (:mod:`behaviors.mop.validity`, :mod:`behaviors.mop.shape_lead`) update a dozen
arrays over the templates after each step: followed state, size estimate, evidence, refusal with
hysteresis, engagement, probabilities, path misfit and coverage, shape sums. Written as numpy
array operations over the group's templates (measured in :mod:`behaviors.mop.group`) that is
about 150 numpy calls per tick, most of DESIGN's 8 performers x 100 templates tick after the
forward step; here it is one loop per template, in the same order of operations as the
follower's own array code (the group stays equal to its followers stepped alone), followed per
member by its likeliest template, best (with the switch margin), top three
(:mod:`behaviors.mop.group_steps`), shape lead and threshold model
(:mod:`behaviors.mop.threshold_kernel`).
"""

from __future__ import annotations

import math

import numba
import numpy as np

import behaviors.mop.compiled
from behaviors.mop import (blocked, commitment, coverage, coverage_kernel, fresh_refusal,
                           group_layout, group_steps, holding, invariance, member_spotting,
                           member_validity, members, misfit_size, path_kernel, reversal, rivals,
                           shape_lead, size_probe, size_sums, spotting, tempo, threshold,
                           threshold_kernel, validity)
from behaviors.mop.compiled import CONTRACT
from behaviors.mop.coverage_kernel import cover
from behaviors.mop.fresh_refusal import FRESH_WEIGHT, refused_after
from behaviors.mop.group_layout import AHEAD, LAG0, MC_ROWS
from behaviors.mop.group_steps import displacements, first_max, prefetch_ahead, top_three
from behaviors.mop.holding import SNAP_RADII, hold_size, resting_with
from behaviors.mop.threshold_kernel import threshold_evidence
from behaviors.mop.reversal import (REVERSAL_LARGER_AHEAD, reversal_size, reversal_step,
                                    sizes_again)
from behaviors.mop.member_validity import slow_of
from behaviors.mop.member_spotting import shares
from behaviors.mop.members import committed
from behaviors.mop.path_kernel import nearest_on_path
from behaviors.mop.commitment import add_lagged
from behaviors.mop.rivals import least_rival
from behaviors.mop.size_probe import probe_allowed, take_probe
from behaviors.mop.size_sums import estimate_sums
from behaviors.mop.shape_lead import DRIFT_FROM, DRIFT_HELD_AT_REST, KEPT_COMMIT
from behaviors.mop.validity import PAUSE_CARRY, PAUSE_SAMPLES
from behaviors.kernel_cache import compiled

# the files whose compiled functions or constants the kernels take in (holding's through its own)
_CALLS_INTO = (behaviors.mop.compiled, blocked, commitment, coverage, coverage_kernel,
               fresh_refusal, group_layout, group_steps, holding, invariance, member_spotting,
               member_validity, members, misfit_size, path_kernel, reversal, rivals, shape_lead,
               size_probe, size_sums, spotting, tempo, threshold, threshold_kernel, validity)

_F1, _F2, _F3 = numba.float64[::1], numba.float64[:, ::1], numba.float64[:, :, ::1]
_I1, _B1 = numba.intp[::1], numba.boolean[::1]
_I2, _BB2 = numba.intp[:, ::1], numba.boolean[:, ::1]
_S1, _S2 = numba.float32[::1], numba.float32[:, ::1]

# Compiled without numba's reference counts (``_nrt=False``; its scratch ``rows`` passed in):
# every row or slice view taken per template (``tc[k]``, ``states[gs]``, the units given to
# add_lagged) took a locked increment and decrement, about a fifth of DESIGN's group tick
# (perf samples). Thread time p10, interleaved processes, load 15-26: update_templates 953, 971
# -> 793, 822 us, the tick 1587, 1620 -> 1450, 1520 us; the same outputs to the bit.
@compiled(numba.void(_F2, _I2, _F2, _F2, _F2, _BB2, _F2, numba.int64[::1], _F1,
                     numba.int64[::1], _F1, _F3, _F3, _I2, numba.intp, numba.intp, numba.float64,
                     numba.float64, _F2, _B1, _I2, _F2, _BB2, _B1, _S2, _S1, _S1, _F2, _F1,
                     _F1, _I1, _F1, _F2, _F1, _F2, _I1, _F3, _F2),
           *_CALLS_INTO, fastmath=CONTRACT, _nrt=False)
def update_templates(states, ti, tc, mc, floats, flags, misfit, entries, mean, fw_entries, step_ll,
                     vectors, buf, ints, before, after, rival_p, min_lead, k_out, new_out,
                     top3_out, m_floats, m_flags, present, thr_means, alpha, scratch,
                     thr_z, thr_lj, thr_tops, reversal_at, reversal_tol, probe,
                     probe_floor2, rows, shared, tempo_x, tempo_g) -> None:
    """After one forward step (``mean``, ``fw_entries``, ``step_ll`` per template), each
    template's followed state and per-template rules, member by member, then each member's
    probabilities, best, top three and shape lead.

    ``states``: see :data:`~behaviors.mop.group_layout.STATE_COLUMNS`; ``ti`` (K, 3): each
    template's first state and length in its member's bank and where that bank begins in
    ``states``; ``tc``, ``mc``: see group_layout's ``TEMPLATE_SCALARS``, ``MEMBER_SCALARS``; the
    members' arrays are rows of ``vectors``, ``ints``, ``m_floats``, ``m_flags``
    (:data:`~behaviors.mop.members.MEMBER_INTS` and the rest): ``x``, ``anchor`` (M, D): each
    member's sample and anchor; ``buf``/``nbuf``: its recent samples; ``bounds``/``counts``: its
    first template and template count; ``k_out``: the rows progress, mean_ll, p below (fresh each
    tick). In place: ``floats`` (group_layout.FLOATS), ``flags`` (group_layout.FLAGS), ``misfit``
    (K, 3) sums, ``entries`` and ``best`` (M,: each member's own template index, switched when
    another leads by the member's margin in nats or it is refused); ``floats`` (K, len(FLOATS))
    and ``flags``: a column each, the members' arrays: a row each (not tuples of arrays: numba
    types a tuple's arrays one by one at every call, 6.5 -> 4.7 us; nor an argument each: see
    :func:`members.conclude`). Out per template: progress, recent mean log-likelihood, probability,
    whether its performance began anew; per member: top three by probability (-1 where fewer), the
    largest RMS displacement from the anchor (template units and size), any engaged, all refused,
    whether ``best`` leads every rival (not refused, probability at least ``rival_p``, or broader
    and alike: :func:`~behaviors.mop.rivals.broad_rivals`) in shape by ``min_lead``, whether the
    performer rests (``rest_out``: the holds' rule here, the stall rule in
    :func:`behaviors.mop.members.conclude`), whether ``best`` was committed to by shape
    (``committed_out``: :meth:`ShapeLead._committed`; ``shape_n``: each member's samples in its
    shape sums). ``before``/``after``: the path's reach in states. ``reversal_at`` (S,),
    ``reversal_tol`` (K,): each state's reversal landmark (its bank's state, -1 where none) and
    each template's tolerance there
    (:meth:`~behaviors.mop.invariance.PerformanceFrame._reversal_sizes`); ``probe`` (K, 4),
    ``probe_floor2`` (K,): :mod:`~behaviors.mop.size_probe`'s sums and floor. ``thr_means``:
    the states' means (D, S) in float32, the threshold model's. ``shared``,
    ``tempo_x``, ``tempo_g``: as :func:`members.conclude`'s (a barred best's release,
    :mod:`~behaviors.mop.blocked`)."""
    # the per-template state: columns of ``floats`` and ``flags`` (a template's state together,
    # group_layout.FLOATS)
    ev, rec, rw, num = floats[:, 0], floats[:, 1], floats[:, 2], floats[:, 3]
    den, size, misfit_w, shape = floats[:, 4], floats[:, 5], floats[:, 6], floats[:, 7]
    gone, least, judged, drift = floats[:, 8], floats[:, 9], floats[:, 10], floats[:, 11]
    drift_run, reached, attempt_from = floats[:, 12], floats[:, 13], floats[:, 14]
    rev_undo, rev_turn, rev_way, rev_age = floats[:, 15], vectors[10], vectors[11], ints[23]
    rev_at, seat, lags = floats[:, 16], floats[:, 17], floats[:, LAG0:].T
    x, anchor, thr_x = vectors[0], vectors[1], vectors[2]
    bounds, counts, best, acquired, nbuf = ints[0], ints[1], ints[3], ints[6], ints[7]
    sh_off, barred, freed = ints[2], ints[21], ints[22]
    bar_top, bar_sum, bar_kept = m_floats[13], m_floats[14], m_floats[15]
    drive_from, drive_peak, drive_moved = m_floats[5], m_floats[6], m_flags[8]
    progress_out, mean_ll_out, p_out = k_out[0], k_out[1], k_out[2]
    moving_out, thr_ev, kept_out, thr_total, shape_n = (m_floats[0], m_floats[1], m_floats[2],
                                                        m_floats[3], m_floats[4])
    any_engaged, all_refused, leads_out = m_flags[0], m_flags[1], m_flags[2]
    thr_has_x, rest_out, committed_out = m_flags[3], m_flags[4], m_flags[5]
    refused, engaged, misshaped = flags[:, 0], flags[:, 1], flags[:, 2]
    covered, at_hold_end, fresh, seated = flags[:, 3], flags[:, 4], flags[:, 6], flags[:, 7]
    d = x.shape[1]
    rel0, src, arc = d, 2 * d, 2 * d + 1              # columns of states
    hend, hahead, hbegin = 2 * d + 2, 2 * d + 3, 2 * d + 4
    sc0, ce0, uf0, co0 = 5, 5 + d, 5 + 2 * d, 5 + 3 * d  # columns of tc
    ahead = tc.shape[1] - 1
    ra0, un0 = MC_ROWS, MC_ROWS + d                 # columns of mc
    # the path's segment means read from ``states``' rows (its first columns), which the pass
    # fetches around the followed state anyway, not from a copy of them as (D, S) rows: the
    # same numbers, two to four cache lines a template fewer and their prefetches gone. In the
    # tick of DESIGN's group (alternating tick by tick with the copy's form in one process, both
    # compiled alike, 600 / 400 pairs, load 6): update_templates -89.7 us after the view's
    # frames, -119.7 back to back; the sides swapped +96.4, +83.2; the tick -118.4 / -151.5
    path = states.T
    u, z, v, away, dx, hq = rows[0], rows[1], rows[2], rows[3], rows[4], rows[5]
    hr, htol, hrad, dxu, tu, tr = rows[6], rows[7], rows[8], rows[9], rows[10], rows[11]
    for i in range(bounds.size):
        a0 = bounds[i]
        a1 = a0 + counts[i]
        m = mc[i]
        dims, decay, null_decay, log_constant, two_over = m[0], m[1], m[2], m[3], m[4]
        null2, accept2, onset_sigma, scaled, lo, hi = m[5], m[6], m[7], m[8] > 0.0, m[9], m[10]
        misfit_decay, shape2, shape_accept2, path_scale = m[11], m[12], m[13], m[14]
        spots, none, margin = m[15], m[16] > 0.0, m[17]
        far = displacements(buf, nbuf, x, anchor, m, un0, i, away, dx, dxu)
        moving = 0.0
        rejudge_at = m[21]
        # sizes whose ratio to the judged one lies within these are surely within rejudge_at
        # (no logarithm needed: 1e-9 is far above its rounding; beyond them, the logarithm)
        inside_lo = math.exp(-rejudge_at) * (1.0 + 1e-9)
        inside_hi = math.exp(rejudge_at) * (1.0 - 1e-9)
        for c in range(d):
            hrad[c] = m[ra0 + c]
        rest = resting_with(buf, nbuf, i, x, hrad, int(m[22]))   # holding (ActionFollower._finish)
        rest_out[i] = rest
        # a pause of an action that carried its performer forward (validity.unweighed;
        # m[30]: validity.UNWEIGHED_AT_REST, m[29]: UNJUDGED_AT_REST below)
        unjudged = rest and m[29] > 0.0
        paused = (m[30] > 0.0 and acquired[i] >= 0 and drive_moved[i]
                  and drive_peak[i] - drive_from[i] >= m[26]   # (validity.CARRY_FIRST)
                  and (rest or (drive_peak[i] - drive_from[i] >= PAUSE_CARRY
                                and resting_with(buf, nbuf, i, x, hrad, PAUSE_SAMPLES))))
        # the input reverses here (PerformanceFrame._reversal_sizes), went on past the last
        # reversal's turn (its sizes undone), the same turn read again
        turned, undone, again = False, False, False
        if scaled:
            for c in range(d):
                tu[c] = m[un0 + c]
            undone, turned, again = reversal_step(buf, nbuf, i, x, anchor[i], tu, m[23], dxu,
                                                  tr, rev_turn, rev_way, rev_age)
        for k in range(a0, a1):
            if k + AHEAD < mean.size:   # the states the template a few ahead will read
                prefetch_ahead(states, ti, mean, k + AHEAD)
            t = tc[k]
            start, lk, off = ti[k, 0], ti[k, 1], ti[k, 2]
            # followed state and progress (ActionFollower._finish)
            g = start + min(mean[k], lk - 1.0)
            gi = min(int(g), start + lk - 2)
            frac = g - gi
            gs = gi + off
            row, nrow = states[gs], states[gs + 1]
            progress_out[k] = row[src] + frac * (nrow[src] - row[src])
            if rest and scaled and row[hahead] >= 0.0:   # ActionFollower._hold_sizes
                hrow = states[int(row[hahead]) + off]
                for c in range(d):
                    hq[c] = hrow[rel0 + c]
                    hr[c] = dxu[c]
                    # none in the padding past the member's columns (hold_size sums the tolerance)
                    htol[c] = SNAP_RADII * m[ra0 + c] / m[un0 + c] if c < dims else 0.0
                sh = hold_size(hq, hr, size[k], lo, htol)
                if sh > 0.0:
                    num[k] = sh * (den[k] + t[2]) - t[2]
                    least[k] = min(least[k], sh)
                    seat[k] = row[hahead] - start
            if undone:
                num[k] -= rev_undo[k]
            was = num[k]
            if turned and not again:   # the landmark the turn first met
                rev_at[k] = reversal_at[gs]
            # ... and a reversal's (_reversal_sizes), but not the strained action driving's
            # (Refusal._recent_dist2)
            if turned and reversal_at[gs] >= 0 and not (
                    k - a0 == acquired[i]
                    and (log_constant - rec[k] / rw[k]) * two_over > accept2):
                rrow = states[reversal_at[gs] + off]
                for c in range(d):
                    hq[c] = rrow[rel0 + c]
                sr = reversal_size(hq, tr, lo, hi, reversal_tol[k])
                if reversal_at[gs] - gi > REVERSAL_LARGER_AHEAD and sr >= size[k]:
                    sr = 0.0   # a landmark beyond it sizes smaller only
                if again and not sizes_again(float(reversal_at[gs]), rev_at[k], sr, size[k]):
                    sr = 0.0
                if sr > 0.0:
                    num[k] = sr * (den[k] + t[2]) - t[2]
            if turned:
                rev_undo[k] = num[k] - was
            if scaled:   # PerformanceFrame._estimate_size
                qr, qq = estimate_sums(row, nrow, frac, rel0, dxu, d)
                num[k] += qr
                den[k] += qq
                least[k] = max(least[k], far * t[4])
                size[k] = min(max(max((num[k] + t[2]) / (den[k] + t[2]), least[k]), lo), hi)
                allowed = probe_allowed(acquired[i] < 0, k - a0 == best[i], refused[k],
                                        rw[k] > 0.0 and (log_constant - rec[k] / rw[k])
                                        * two_over > accept2)
                if allowed or probe[k, 2] > 0.0:   # sums not yet clear (size_probe)
                    take_probe(states, rel0, start + off, start + lk - 1 + off, g + off, dxu,
                               probe[k], probe_floor2[k], lo, hi, num, den, size, least, t[2], k,
                               allowed)
            if row[hend] == row[hend]:   # a hold rested in shows where it ends (holding)
                at_hold_end[k] = at_hold_end[k] or rest
                if at_hold_end[k]:
                    progress_out[k] = max(progress_out[k], row[hend])
                else:   # ... and no further than where it begins before
                    progress_out[k] = min(progress_out[k], row[hbegin])
            else:
                at_hold_end[k] = False
            sk = size[k]
            raw = step_ll[k] - t[0]
            log_size = dims * math.log(sk)
            raw -= log_size
            thr_lj[k] = m[20] + (-t[0] - log_size)   # the threshold model's log-density terms
            ev[k] = ev[k] if paused else ev[k] * decay + raw
            if not unjudged or rw[k] <= 0.0:   # validity.unjudged
                rec[k] = rec[k] * null_decay + step_ll[k]
                rw[k] = rw[k] * null_decay + 1.0
            # judged afresh once the size moved (PerformanceFrame._rejudge)
            ratio = size[k] / judged[k]
            if scaled and not (inside_lo < ratio < inside_hi) and abs(math.log(ratio)) > rejudge_at:
                judged[k] = size[k]
                fresh[k] = k - a0 == acquired[i]
                rec[k] = log_constant
                rw[k] = 1.0
                for c in range(misfit.shape[1]):
                    misfit[k, c] = 0.0
                misfit_w[k] = 0.0
            new = fw_entries[k] > entries[k]
            entries[k] = fw_entries[k]
            # a refused template back at its start and matching it begins anew
            if refused[k] and mean[k] < t[1] and (log_constant - step_ll[k]) * two_over <= null2:
                new = True
            if new:
                rec[k] = log_constant
                rw[k] = 1.0
                refused[k] = False
                engaged[k] = False
                fresh[k] = False
            new_out[k] = new
            if new:
                gone[k] = 0.0
                attempt_from[k] = progress_out[k]   # (validity.stalls)
                seated[k] = False
            if spots:   # the highest progress since the gesture began (spotting's _gone)
                gone[k] = max(gone[k], progress_out[k])
            mll = rec[k] / rw[k]
            mean_ll_out[k] = mll
            dist2 = (log_constant - mll) * two_over
            refused[k] = refused_after(refused[k], fresh[k], dist2, rw[k], null2, accept2)
            fresh[k] = fresh[k] and rw[k] < FRESH_WEIGHT
            ssz = sk if scaled else 1.0
            if mean[k] >= t[1] and not refused[k] and not engaged[k]:
                acc = 0.0
                for c in range(d):
                    r = away[c] / t[sc0 + c] / sk
                    acc += r * r
                engaged[k] = math.sqrt(acc / dims) >= onset_sigma
            # path misfit and coverage (Refusal._judge_shape): the nearest point on the
            # segments from the states within the reach of the followed one
            if new:
                misfit[k, 0] = 0.0
                misfit[k, 1] = 0.0
                misfit[k, 2] = 0.0
                misfit_w[k] = 0.0
                misshaped[k] = False
                covered[k] = False
                reached[k] = 0.0
            for c in range(d):
                base = t[ce0 + c] if none else anchor[i, c]
                u[c] = (x[i, c] - base) / t[sc0 + c] + t[uf0 + c]
                z[c] = u[c] / ssz + t[co0 + c]
                # the sample as the template sees it (the threshold model's too)
                thr_z[k, c] = z[c]
            # ... and its first coordinate mirrored about the template's first state (the
            # threshold model's mirror chains: threshold.mirrored_column)
            thr_z[k, d] = 2.0 * (t[uf0] + t[co0]) - z[0]
            gf = int(math.floor(g))
            last = start + lk - 1
            nearest_on_path(path, start, last, off, g, z, v, before, after)
            uu = 0.0
            uv = 0.0
            vv = 0.0
            for c in range(d):
                vc = v[c] - t[co0 + c]
                uu += u[c] * u[c]
                uv += u[c] * vc
                vv += vc * vc
            if scaled:   # a size moved at once (misfit_size)
                misfit_size.reread(misfit, k, k + 1, size)
            if not unjudged or misfit_w[k] <= 0.0:
                misfit[k, 0] = misfit[k, 0] * misfit_decay + uu
                misfit[k, 1] = misfit[k, 1] * misfit_decay + uv
                misfit[k, 2] = misfit[k, 2] * misfit_decay + vv
                misfit_w[k] = misfit_w[k] * misfit_decay + 1.0
            m2 = ((misfit[k, 0] / (ssz * ssz) - 2.0 * misfit[k, 1] / ssz + misfit[k, 2])
                  / misfit_w[k])
            m2 *= 1.0 / path_scale
            misshaped[k] = (misshaped[k] or m2 > shape2) and not m2 < shape_accept2
            # covered (coverage_kernel.cover: coverage, not while it runs ahead of the input
            # nor, covered sooner, while off its path)
            cover(states, lags, t, m, k, g, gf, start, last, off, arc, ahead, engaged[k], away,
                  sc0, sk, d, dims, m2, covered, reached)
            # shape sums (ShapeLead._leads) and displacement (early feedback)
            acc = 0.0
            mv = 0.0
            for c in range(d):
                q = row[rel0 + c] + frac * (nrow[rel0 + c] - row[rel0 + c])
                e = (dx[c] - sk * q * m[un0 + c]) / m[ra0 + c]
                acc += e * e
                r = dx[c] / t[sc0 + c] / ssz
                mv += r * r
            shape[k] += acc * spots
            # ... and at each timing offset (commitment.add_lagged)
            if spots > 0.0:
                add_lagged(lags, k, dx, g, start, last, states, off, rel0, d, sk,
                           m[un0:un0 + d], m[ra0:ra0 + d])
            if spots > 0.0:   # ... and the run of samples it drifts further off (_drifts)
                rising = acc > drift[k] and acc > dims * DRIFT_FROM ** 2
                held = rest and DRIFT_HELD_AT_REST
                drift_run[k] = drift_run[k] + (0.0 if held else 1.0) if rising else 0.0
                drift[k] = acc
            mv = mv / dims
            if mv > moving:
                moving = mv
        moving_out[i] = math.sqrt(moving)   # (the root of the largest: the largest root)
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
        # the threshold model (Refusal._threshold_evidence): the share of the probability the
        # templates keep against it
        kept = 1.0
        if present[i] and math.isfinite(m[18]):
            if not paused:   # (nor stepped in such a pause: validity.unweighed)
                lead = step_ll[first] - tc[first, 0]
                lead -= dims * math.log(size[first])
                threshold_evidence(thr_means, ti, m, a0, a1, thr_z, thr_lj, alpha, scratch,
                                   thr_total, i, thr_tops, lead, decay, x, thr_x, thr_has_x,
                                   thr_ev, ra0, d)
            kept = tot / (tot + math.exp(min(thr_ev[i] - top, 700.0)))
        kept_out[i] = kept
        gb = a0 + best[i]
        # a best blocked BLOCKED_SAMPLES in a row is barred while it leads, until it began anew
        # or may drive (recognition, blocked)
        fb, bar = first, barred[i]
        if bar >= 0:
            kb = a0 + bar
            gk = min(mean[kb], ti[kb, 1] - 1.0)
            if kb != first or new_out[kb] or not (
                    (sh_off[i] >= 0 and shares(a0, a1, kb, int(ti[kb, 0] + gk) - ti[kb, 0],
                                               shared, sh_off[i], refused, misshaped,
                                               progress_out, gone))
                    or slow_of(i, kb, gk, x, tempo_x, tempo_g, ints[14], ints[15], tc, sc0,
                               size[kb], dims, onset_sigma, shape_n[i] + 1.0, anchor)):
                freed[i], bar = bar, -1
                barred[i] = -1
        if bar >= 0:
            fb = blocked.likeliest_other(ev, a0, a1, a0 + bar)
        if (best[i] < 0 or ev[fb] - ev[gb] > margin or refused[gb]
                or (bar >= 0 and gb == a0 + bar)):
            gb = fb
        # committed to by shape (ShapeLead._committed): best, however improbable
        shape_n[i] += spots
        c = -1   # (searched only where the threshold model allows it, as _committed)
        if spots > 0.0 and kept >= KEPT_COMMIT:
            c = committed(shape, lags, flags, a0, a1, shape_n[i] * dims, min_lead)
        committed_out[i] = c >= 0
        if committed_out[i]:
            gb = c
        best[i] = gb - a0
        # the probabilities the rivals are read at: among the templates but a barred best
        # (blocked; ``fb``: the likeliest of them), kept for members.conclude
        bk, others = -1, 1.0
        if bar >= 0 and a0 + bar != gb:
            bk, others = a0 + bar, blocked.others_total(ev, a0, a1, a0 + bar, fb)
        bar_top[i], bar_sum[i] = ev[fb], others
        kept_o = kept   # ... and the threshold model's share against the likeliest of them
        if bk >= 0 and math.isfinite(m[18]):
            kept_o = others / (others + math.exp(min(thr_ev[i] - ev[fb], 700.0)))
        bar_kept[i] = kept_o
        # the rivals' least shape sum (rivals.least_rival: probable, or broader and alike)
        rival = least_rival(a0, a1, gb, bk, fb, others, kept_o, rival_p, min_lead, dims, ev, p_out,
                            shape, size, gone, progress_out, refused, engaged, covered, misshaped,
                            tc)
        # ... and only while its shape since the gesture began fits (ShapeLead._leads;
        # m[25]: shape_lead.TAKE_FIT squared, group_layout.MEMBER_SCALARS)
        leads_out[i] = (not shape[gb] > shape_n[i] * dims * m[25]
                        and (rival == np.inf or rival - shape[gb] >= min_lead))
