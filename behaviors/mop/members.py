"""A follower group's per-member rules (one row per member), compiled.

:class:`~behaviors.mop.group.FollowerGroup` steps many followers at once; the rules a single
:class:`~behaviors.mop.follower.ActionFollower` applies to itself once its templates are updated
(validity, stillness, early feedback, gesture spotting) are written here once more over arrays
of members: per-template arrays ``(K,)`` of the whole group cut into members by ``bounds`` (each
member's first template), per-member arrays ``(M,)`` or ``(M, D)`` (``D`` the widest member's
features, narrower members padded with values that change nothing). Each function states the
follower method it equals; ``tests/mop/test_group.py`` checks them and the group against
followers stepped alone; the rules applied before the conclusion (turning, tempo, a way back to
an abandonment's anchor) are in :mod:`behaviors.mop.member_validity`, the spotting choices
asked at the end in :mod:`behaviors.mop.member_spotting`. Compiled: as array operations over
the members (about 90 numpy calls on arrays of 8) they cost more than the per-template pass.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from behaviors.mop import (blocked, gesture_end, group_layout, halts, handover, member_buffer,
                           member_spotting, member_validity, overrun, path_kernel, shape_lead,
                           speed_profile, spotting, take_fit, take_rule, tempo, validity)
from behaviors.mop.blocked import BLOCKED_SAMPLES, BLOCKED_SIZE
from behaviors.mop.gesture_end import (END_GRACE, REANCHOR_RADII, RETURN_BACK, RETURN_RADIUS,
                                       UNSEEN_END)
# (members.push and the rest of the buffer's stay importable from here)
from behaviors.mop.member_buffer import arrived, nearest, push, recent_mean, still  # noqa: F401
from behaviors.mop.member_spotting import (GOES_ON, departed, finished_short, lead_gain,
                                           moved_on, shares, spot)
from behaviors.mop.shape_lead import COMMIT_FIT, CONFIRM_GAIN, DRIFT_SAMPLES, SHAPE_SPREAD
from behaviors.mop.tempo import LEAST_TEMPO
from behaviors.mop.validity import BACK_FIRST, FORWARD_FIRST, LEAP_STATES
from behaviors.kernel_cache import compiled

# the files whose constants or compiled functions the kernels take in (group_layout's, halts',
# overrun's, path_kernel's, speed_profile's, take_fit's and take_rule's through member_validity's)
_CALLS_INTO = (blocked, gesture_end, group_layout, halts, handover, member_buffer,
               member_spotting, member_validity, overrun, path_kernel, shape_lead, speed_profile,
               spotting, take_fit, take_rule, tempo, validity)

_F1, _F2, _F3 = numba.float64[::1], numba.float64[:, ::1], numba.float64[:, :, ::1]
_I1, _I2, _B1 = numba.intp[::1], numba.intp[:, ::1], numba.boolean[::1]
_BB2 = numba.boolean[:, ::1]
_FA1 = numba.float64[:]   # a column of the per-template state (group_layout.FLOATS)

#: Per-member scalars (columns of ``mk`` (M, 14 + 2D), then the rows ``radius`` and ``units``).
MEMBER_RULES = ("spread2", "min_p", "spots", "confirm", "log_constant", "zdim", "keep",
                "hint_onset", "end", "null2", "depart2", "lost_after", "dims", "memory")
_RAD = len(MEMBER_RULES)
#: The members' own arrays of a follower group (its attributes of these names), each a row of
#: one array: per member (R, M, D), (R, M) integers, floats and flags, as the compiled passes
#: (:func:`conclude`, :func:`~behaviors.mop.group_kernel.update_templates`) take them.
MEMBER_VECTORS = ("_x", "_anchor", "_thr_x", "_end_x", "_end_last", "_came", "_unseen_x",
                  "_unseen_last", "_end_near", "_take_shift", "_rev_turn", "_rev_way")
MEMBER_INTS = ("_bounds", "_counts", "_sh_off", "_best", "_run", "_run_k", "_acquired", "_nbuf",
               "_lost", "_after_end", "_drive_k", "_peak_k", "_m_restart", "_taken_n",
               "_tempo_at", "_tempo_n", "_end_history_n", "_overran_k", "_walk_n", "_blocked",
               "_blocked_k", "_barred", "_freed", "_rev_age")
MEMBER_FLOATS = ("_m_moving", "_thr_ev", "_m_kept", "_thr_total", "_shape_n", "_drive_from",
                 "_drive_peak", "_peak", "_m_dim", "_walk", "_step_prev", "_step_last",
                 "_drive_leapt", "_bar_top", "_bar_sum", "_bar_kept")
MEMBER_BOOLS = ("_m_any_engaged", "_m_all_refused", "_m_leads", "_thr_has_x", "_m_rest",
                "_m_committed", "_has_end", "_turn_ok", "_drive_moved", "_has_anchor",
                "_tempo_on", "_abandoned", "_abandon_rested", "_lagged", "_underway",
                "_underway_rested", "_has_unseen", "_straight", "_end_nearing", "_begun_at_return",
                "_end_returned", "_bend_hidden")
#: What :func:`conclude` answers per member: the rows of its ``out`` (M,) and ``out_flags``.
MEMBER_OUT = ("variance", "loglik", "distance", "progress")
MEMBER_FLAGS = ("valid", "show", "holding", "restarted")


@compiled(numba.intp(_FA1, numba.float64[:, :], numba.boolean[:, ::1], numba.intp, numba.intp,
                     numba.float64, numba.float64), *_CALLS_INTO)
def committed(shape: np.ndarray, lags: np.ndarray, flags: np.ndarray, a0: int, a1: int,
              samples: float, lead: float) -> int:
    """:meth:`ShapeLead._committed` among templates ``a0..a1`` (group indices; ``flags``:
    the group's flag columns, refused, engaged, misshaped, covered first), but for the threshold
    model's share: the one committed to by shape, or -1. ``lags``: the shape sums at each timing
    offset (a row each, :data:`~behaviors.mop.group_layout.SHAPE_LAGS`), whose least is the
    fit :data:`~behaviors.mop.shape_lead.COMMIT_FIT` reads. ``samples``: the shape sums' samples
    times the features; ``lead``: :data:`~behaviors.mop.shape_lead.LEAD` in shape units."""
    refused, engaged, misshaped, covered = flags[:, 0], flags[:, 1], flags[:, 2], flags[:, 3]
    c = -1
    for k in range(a0, a1):
        if (not refused[k] and engaged[k] and covered[k] and not misshaped[k]
                and (c < 0 or shape[k] < shape[c])):
            c = k
    if c < 0 or COMMIT_FIT <= 0.0:
        return -1
    fit = lags[0, c]
    for j in range(1, lags.shape[0]):
        fit = min(fit, lags[j, c])
    if fit > samples * COMMIT_FIT ** 2:
        return -1
    for k in range(a0, a1):
        if k != c and not refused[k] and shape[k] - shape[c] < lead:
            return -1
    return c


@compiled(numba.void(_F2, _I2, _F1, _F2, _F2, _BB2, _F2, _F1, _B1, _F2, _F2, _F3, _B1, _F2,
                   numba.boolean[:, ::1], _I2, _F3, _F1, _F2, _BB2, _I1, _I2, _B1, _I2, _I2, _F3,
                   _I1, _F3, _F2, _F2, numba.float64, _F2, _F2, _F3, numba.float64, _F2),
          *_CALLS_INTO)
def conclude(states, ti, mean, mom, floats, flags, k_out, step_ll, holds, scale, mk, vectors,
             present, m_floats, m_flags, ints, buf, extent, out, out_flags, shared, crawl, new,
             top3, likely_k, likely_v, lengths, tempo_x, tempo_g, tempo_s, onset, tc, mc, taken,
             take_limit, end_history) -> None:
    """:meth:`ActionFollower._conclude` and :meth:`GestureSpotting._spot`'s choice for every
    member, after the per-template pass (:func:`behaviors.mop.group_kernel.update_templates`,
    whose outputs ``p``, ``progress``, ``mean_ll``, ``moving``, ``any_engaged``, ``all_refused``,
    ``leads``, ``turn_ok`` (the input turned as ``best`` does) and ``kept`` (the share of the
    probability the templates keep against the threshold model) it reads; ``best`` already
    switched there). The members' own arrays are rows of ``vectors``, ``ints``, ``m_floats``
    and ``m_flags`` (:data:`MEMBER_VECTORS` and the rest), ``size``, ``highest`` and
    ``drift_run`` columns of ``floats`` and ``progress``, ``mean_ll``, ``p`` of ``k_out``, as in
    :func:`~behaviors.mop.group_kernel.update_templates` (an argument each, their unboxing
    cost more: a no-op of each signature with the group's arguments, dispatched in the tick
    after two view frames, median 12.7-14.5 -> 6.8-7.8 us for this pass's 56 -> 26 arguments,
    15.1-19.1 -> 14.2-14.3 us for update_templates' 49 -> 33). ``states``, ``ti``: as there;
    ``mean``, ``mom``: the forward's; ``flags``: the group's flag columns (refused,
    engaged, misshaped, covered first); ``mk``: see
    :data:`MEMBER_RULES`; ``present``: the members with a sample this tick; ``rest``: whether
    each rests (:func:`~behaviors.mop.tempo.resting` over the samples the push keeps,
    measured once by the per-template pass; a member without a sample is put back after the
    tick); ``crawl``: each member's crawling run and its best, as
    :func:`~behaviors.mop.member_validity.tempo` left them;
    ``committed``: ``best`` committed to by shape (drives however improbable); ``drift_run``
    (K,): the samples in a row each template drifted further off (:meth:`ShapeLead._drifts`).

    In place: ``run`` (samples in a row ``best`` was ok) and whose they are (``run_k``),
    ``acquired`` (and the last action that drove, where it began and its
    highest progress since: ``drive_k``, ``drive_from``, ``drive_peak``), the recent samples
    ``buf``/``nbuf``, the gesture's end ``has_end``/``end_x`` (and the ended template's last
    point there, ``end_last``: :meth:`GestureSpotting._moved_on`), ``lost`` (refused samples in a
    row), ``after_end`` (samples since the end was reached) and ``peak``/``peak_k`` (the highest
    progress of the action driving, and which; ``extent`` (K,): each template's farthest state
    from its first, in units). Out per member: the rows of ``out`` (:data:`MEMBER_OUT`:
    ``best``'s variance in progress units squared, recent mean log-likelihood, its distance,
    progress) and of ``out_flags`` (:data:`MEMBER_FLAGS`: valid, the likeliest actions shown,
    holding, ``best`` began anew: ``new`` (K,) of the forward step), how a new attempt starts
    (``restart``: :data:`GOES_ON`...) and, where shown, the likeliest actions (the early
    feedback of :meth:`ActionFollower._conclude`): ``top3``'s templates (group indices) not
    refused into ``likely_k`` (M, 3; -1 after the last), their probability and progress into
    ``likely_v`` (M, 3, 2). Rows, not seven arrays and the top three read from Python: the
    tick's Python part read them with ~80 numpy calls (scalar indexing of ``p``, ``progress``
    and ``refused``, row views)."""
    size = floats[:, 5]
    # first the gesture's last samples and whether they fit a new best's path, the tempo of a
    # new action and a way back to an abandonment's anchor, last the abandonment's end
    # (member_validity: takes, tempo, unbegun, still_unbegun; ``tc``, ``mc``, ``taken``,
    # ``take_limit``: the take's; ``lengths`` (K,), ``tempo_x``, ``tempo_g``, ``onset``: the
    # tempo's). See member_validity.takes for what this saves
    member_validity.takes(present, m_flags[9], vectors[0], vectors[1], taken, ints[13], ints[0],
                          ints[3], ints[6], m_flags[2], states, ti, mean, tc, mc, floats,
                          take_limit, vectors[9])
    overran = member_validity.overruns(states, ti, mean, tc, mc, vectors[0], vectors[1], present,
                                       m_flags[10], ints[0], ints[3], ints[14], ints[15],
                                       tempo_x, tempo_g, tempo_s, size, ints[17], m_flags[17],
                                       k_out[0], ints[10], m_floats[5], m_floats[6],
                                       mk[:, _RAD + vectors.shape[2]:_RAD + 2 * vectors.shape[2]])
    member_validity.tempo(mean, lengths, present, m_flags[10], ints[14], ints[15], ints[0],
                          ints[1], ints[3], vectors[0], tempo_x, tempo_g, tempo_s, scale, size,
                          m_floats[8], onset, m_flags[2], crawl, ints[10], m_floats[4],
                          vectors[1], mc)
    member_validity.unbegun(m_flags[11], present, vectors[0], vectors[1], vectors[5], m_flags[2])
    # ... nor in an attempt begun under way (under_way.underway)
    for i in range(present.size):
        if present[i] and m_flags[14, i]:
            m_flags[2, i] = False
    refused, engaged, misshaped, covered = flags[:, 0], flags[:, 1], flags[:, 2], flags[:, 3]
    seated = flags[:, 7]
    highest, drift_run = floats[:, 8], floats[:, 12]   # (group_layout.FLOATS)
    attempt_from = floats[:, 14]
    progress, mean_ll, p = k_out[0], k_out[1], k_out[2]
    x, anchor, end_x, end_last = vectors[0], vectors[1], vectors[3], vectors[4]
    end_near, nearing = vectors[8], m_flags[18]   # (take_rule.TAKE_FROM_NEAREST)
    bounds, sh_off, best, run, run_k = ints[0], ints[2], ints[3], ints[4], ints[5]
    acquired, nbuf, lost, after_end = ints[6], ints[7], ints[8], ints[9]
    drive_k, peak_k, restart = ints[10], ints[11], ints[12]
    end_history_n, lagged = ints[16], m_flags[13]
    counts, blocked_n, blocked_k, barred, freed = ints[1], ints[19], ints[20], ints[21], ints[22]
    once = flags[:, 5]   # (group_layout.FLAGS)
    moving, kept, drive_from, drive_peak, peak = (m_floats[0], m_floats[2], m_floats[5],
                                                  m_floats[6], m_floats[7])
    drive_leapt = m_floats[12]
    any_engaged, all_refused, leads, rest, committed = (m_flags[0], m_flags[1], m_flags[2],
                                                        m_flags[4], m_flags[5])
    has_end, turn_ok, drive_moved = m_flags[6], m_flags[7], m_flags[8]
    has_unseen, unseen_x, unseen_last = m_flags[16], vectors[6], vectors[7]
    variance, loglik, distance, prog = out[0], out[1], out[2], out[3]
    valid, show, holding, restarted = out_flags[0], out_flags[1], out_flags[2], out_flags[3]
    d = x.shape[1]
    src = 2 * d
    spread = np.empty(d)
    for i in range(bounds.size):
        m = mk[i]
        radius, units = m[_RAD:_RAD + d], m[_RAD + d:_RAD + 2 * d]
        spots = m[2] > 0.0
        bi = best[i]
        gb = bounds[i] + bi
        a1 = bounds[i + 1] if i + 1 < bounds.size else ti.shape[0]
        start, length, off = ti[gb, 0], ti[gb, 1], ti[gb, 2]
        g = start + min(mean[gb], length - 1.0)
        gs = min(int(g), start + length - 2) + off
        slope = states[gs + 1, src] - states[gs, src]
        m0, m1, m2 = mom[0, gb], mom[1, gb], mom[2, gb]
        mu = m1 / m0
        var = max(m2 / m0 - mu * mu, 0.0)
        variance[i] = var * slope * slope
        spread2 = var / ((length - 1.0) * (length - 1.0))
        sk = size[gb]
        moved = False
        if has_end[i]:
            moved = moved_on(x[i], end_x[i], end_last[i], radius)
        if present[i]:
            push(buf, nbuf, x, i, int(m[6]))
        st = still(buf, nbuf, i, int(m[6]), radius)
        rests = rest[i]   # tempo.resting, the holds' flag (group_kernel.update_templates)
        # the probability the validity reads: a barred best's share left out (blocked)
        pv = p[gb] * kept[i]
        if barred[i] >= 0 and barred[i] != bi:   # (update_templates: among the others)
            pv = math.exp(floats[gb, 0] - m_floats[13, i]) / m_floats[14, i] * m_floats[15, i]
        ok = (engaged[gb] and not refused[gb] and covered[gb] and not misshaped[gb]
              and spread2 <= m[0] and (pv >= m[1] or committed[i]) and not moved)
        # a new action drives only once its shape clearly leads, the input turned as it does
        # and its start is no longer shared with another the input still fits (spotting)
        # ... and no action drives once it crawled CRAWL_SAMPLES samples in a row (crawls;
        # mc[i, 27]: tempo.CRAWL_SAMPLES, group_layout.MEMBER_SCALARS)
        # ... nor once the input drifted further off it DRIFT_SAMPLES in a row (_drifts)
        for k in range(bounds[i], a1):   # (barred since it began: blocked)
            if new[k]:
                once[k] = False
        sh = spots and sh_off[i] >= 0 and shares(bounds[i], a1, gb, int(g) - start, shared,
                                                 sh_off[i], refused, misshaped, progress, highest)
        ok = ok and not (spots and once[gb]) and not (
            spots and 0 < mc[i, 27] <= crawl[i, 0]) and not (
            spots and 0 < DRIFT_SAMPLES <= drift_run[gb]) and (
            not spots or acquired[i] == bi or (leads[i] and turn_ok[i] and not sh))
        if spots:   # (blocked: taken at a crawl at a small size, not driving)
            blk = acquired[i] != bi and engaged[gb] and sk < BLOCKED_SIZE and crawl[i, 0] > 0
            blocked_n[i] = (blocked_n[i] + 1 if blocked_k[i] == bi else 1) if blk else 0
            blocked_k[i] = bi
            if counts[i] > 1 and (0 < BLOCKED_SAMPLES <= blocked_n[i]
                                  or (blk and bi == freed[i])) and blocked.lead_of_size(
                    floats[:, 0], bounds[i], a1, gb, sk, m[12], m[13]):
                barred[i] = bi
                once[gb] = True
        if spots and drive_k[i] == bi:   # not back before forward (validity.backs_first)
            last = progress[gb]   # (its followed state's last step)
            if end_history_n[i] > 0 and peak_k[i] == bi:
                last = end_history[i, end_history.shape[1] - 1]
            step = (progress[gb] - last) * (length - 1.0)
            # a leap taken while it did not drive carries no one (validity.leapt)
            if acquired[i] != bi and step > LEAP_STATES:
                drive_leapt[i] += step / (length - 1.0)
            drive_peak[i] = max(drive_peak[i], progress[gb])
            ok = ok and not (drive_peak[i] - drive_from[i] < FORWARD_FIRST
                             and progress[gb] < drive_from[i] - BACK_FIRST)
            # ... nor once its performer finished it short of its end (handover.finished)
            ok = ok and not finished_short(drive_peak[i], progress[gb], crawl[i, 0] > 0)
            # ... nor, moved without carrying the performer forward, holds them at rest (stalls)
            # (spared once performed TAKEN_PERFORMED since its attempt began, resting too;
            # mc[i, 26]: validity.CARRY_FIRST, mc[i, 32]: TAKEN_PERFORMED)
            ok = ok and not (rests and drive_moved[i]
                             and drive_peak[i] - (drive_from[i] + drive_leapt[i]) < mc[i, 26]
                             and not (drive_from[i] - attempt_from[gb] >= mc[i, 32]
                                      and abs(step) < LEAST_TEMPO) and not seated[gb])
            # ... nor holds them resting behind where it began (validity.rests_behind;
            # mc[i, 31]: validity.REST_BEHIND)
            ok = ok and not (rests and 0 <= mc[i, 31] < drive_from[i] - progress[gb])
        # a new best confirms on samples of its own (recognition: the run does not carry over)
        run[i] = run[i] + 1 if ok and run_k[i] == bi else (1 if ok else 0)
        run_k[i] = bi
        # an action that reached its end drives at most END_GRACE samples more (gesture_end.drives)
        after_end[i] = after_end[i] + 1 if has_end[i] else 0
        # ... but a new action whose shape lead grew by CONFIRM_GAIN on its first sample is
        # its own confirmation (shape_lead; floats' columns 7 and 11: _shape, _drift)
        rn = float(run[i])
        if spots and rn == 1.0 and acquired[i] != bi and lead_gain(
                floats[:, 7], floats[:, 11], refused, bounds[i], a1, gb,
                m_floats[4, i]) >= CONFIRM_GAIN * 2.0 * SHAPE_SPREAD ** 2:
            rn = m[3]
        val = rn >= m[3] and after_end[i] <= END_GRACE
        # shown valid only while the input does not overrun its path (member_validity.overruns);
        # the rules go on as if it were
        valid[i] = val and not (spots and overran[i])
        if val and drive_k[i] != bi:
            drive_k[i] = bi
            drive_from[i] = progress[gb]
            drive_peak[i] = progress[gb]
            drive_leapt[i] = 0.0
            drive_moved[i] = False
        if val and not rests:
            drive_moved[i] = True
        acquired[i] = bi if val else -1
        ll = mean_ll[gb]
        loglik[i] = ll
        distance[i] = math.sqrt(max(0.0, -2.0 * (ll - m[4]) / m[5]))
        # early feedback only while the input moves (the follower's hint_onset)
        show[i] = not st and (any_engaged[i] or moving[i] >= m[7])
        pb = progress[gb]
        prog[i] = pb
        holding[i] = holds[off + int(np.rint(g))] or pb >= 0.9
        restarted[i] = new[gb]
        shown = 0
        if show[i]:   # the top three not refused, likeliest first
            for t in range(3):
                j = top3[i, t]
                if j >= 0 and not refused[j]:
                    likely_k[i, shown] = j
                    likely_v[i, shown, 0] = p[j]
                    likely_v[i, shown, 1] = progress[j]
                    shown += 1
        for t in range(shown, 3):
            likely_k[i, t] = -1
        restart[i] = GOES_ON
        if spots and present[i]:
            peak[i] = max(peak[i], pb) if bi == peak_k[i] else pb
            if bi != peak_k[i]:
                end_history_n[i] = 0
            peak_k[i] = bi
            reached = member_validity.tempo_ended(end_history, end_history_n, i, pb, m[8])
            ended = val and not has_end[i] and pb >= m[8]
            # finished short of its end (handover.finished): ended where the input came nearest
            # its last point
            done = (not has_end[i] and not ended and drive_k[i] == bi
                    and finished_short(drive_peak[i], pb, crawl[i, 0] > 0))
            # lagging on an eased end the performer went through (handover.tempo_ended; mc[i, 34]:
            # handover.TEMPO_END_FROM, group_layout.MEMBER_SCALARS)
            lag = (not has_end[i] and not ended and not done and val and pb >= mc[i, 34]
                   and member_validity.slowed(buf, nbuf, i, radius) and reached)
            was_end = has_end[i]
            ended = ended or done or lag
            if not has_end[i] and not ended and peak[i] - pb >= RETURN_BACK:
                # GestureSpotting._returned: back at the last point while followed backwards
                acc = 0.0
                for c in range(d):
                    r = x[i, c] / units[c] - (states[start + length - 1 + off, d + c] * sk
                                              + anchor[i, c] / units[c])
                    acc += r * r
                ended = math.sqrt(acc) <= RETURN_RADIUS * sk * extent[gb]
                m_flags[20, i] = ended   # (read as a return: gesture_end.REANCHOR_RADII)
            if ended:
                end_x[i] = x[i]
                for c in range(d):
                    end_last[i, c] = (states[start + length - 1 + off, d + c] * units[c] * sk
                                      + anchor[i, c])
                if done:
                    nearest(buf, nbuf, i, end_last[i], end_x[i])
                end_near[i] = end_x[i]
                nearing[i] = True
                has_end[i] = True
                # the performer had already stopped there: the grace counts from where they
                # stopped (GestureSpotting._arrived; mc[i, 35]: gesture_end.ARRIVE_RADIUS)
                after_end[i] = arrived(buf, nbuf, i, radius, mc[i, 35])
                lagged[i] = lag
            elif was_end:
                near, held, nearest2 = 0.0, 0.0, 0.0   # summed apart, as spotting's sums
                for c in range(d):
                    near += (x[i, c] - end_last[i, c]) ** 2
                    held += (end_x[i, c] - end_last[i, c]) ** 2
                    nearest2 += (end_near[i, c] - end_last[i, c]) ** 2
                if lagged[i] and near < held:
                    # ended at its tempo: the end is where the input comes nearest its last point
                    end_x[i] = x[i]
                # where the input came nearest that point until it first went away from it
                if nearing[i] and near < nearest2:
                    end_near[i] = x[i]
                else:
                    nearing[i] = False
            step_d2 = (m[4] - step_ll[gb]) * (2.0 / m[5])
            # the input's step here and its path since the anchor (under_way.underway)
            m_floats[10, i] = m_floats[11, i]
            m_floats[11, i] = member_buffer.step_length(buf, nbuf, i, radius, int(m[12]))
            m_floats[9, i] += m_floats[11, i]
            ints[18, i] += 1
            lost[i] = lost[i] + 1 if all_refused[i] else 0
            for c in range(d):
                spread[c] = scale[gb, c] * sk
            gone = departed(x[i], end_x[i], spread, m[12], m[10])
            if (UNSEEN_END and not has_end[i] and not has_unseen[i] and drive_k[i] < 0
                    and not val and not refused[gb] and pb >= m[8] and end_history_n[i] > 1
                    and mc[i, 34] <= end_history[i, end_history.shape[1] - 2] < m[8]):
                # GestureSpotting._spot: never recognised, followed to its end: pending there
                has_unseen[i] = True
                for c in range(d):
                    unseen_x[i, c] = x[i, c]
                    unseen_last[i, c] = (states[start + length - 1 + off, d + c] * units[c] * sk
                                         + anchor[i, c])
            unseen = (has_unseen[i] and drive_k[i] < 0
                      and moved_on(x[i], unseen_x[i], unseen_last[i], radius))
            off_rest = (REANCHOR_RADII > 0.0 and m_flags[19, i] and rests and drive_k[i] < 0
                        and member_buffer.rests_off(buf, nbuf, i, int(m[6]), anchor[i], radius,
                                                    REANCHOR_RADII))
            restart[i] = spot(has_end[i], st, step_d2, m[9], ok, gone, val, pb, lost[i], int(m[11]),
                              any_engaged[i], unseen, off_rest)
    member_validity.still_unbegun(m_flags[11], m_flags[12], rest, present, mc)
    member_validity.still_unbegun(m_flags[14], m_flags[15], rest, present, mc)
    # not shown just before a straight stroke's bend while the input went on straight
    # (bends.unturned: the rules went on as if it were); here rather than as two numpy calls
    # after this pass (see glitch.path_distances for what these fusions saved)
    for i in range(present.size):   # (m_flags[21]: _bend_hidden)
        out_flags[0, i] = out_flags[0, i] and not m_flags[21, i]
