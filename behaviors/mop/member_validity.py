"""A follower group's per-member validity rules before its conclusion, compiled.

What :meth:`~behaviors.mop.group_rules.GroupRules._turned` and
:func:`behaviors.mop.members.conclude` (before its own rules; :func:`still_unbegun` after them)
apply to every member: the gesture's last samples and whether a new action fits them
(:mod:`behaviors.mop.shape_lead`), the input's turning against its best template's
(:mod:`behaviors.mop.turning`), the tempo at which a new action is taken and the crawling run
(:func:`behaviors.mop.tempo.slow_take`, :func:`tempo.crawls`), and a way
back to an abandonment's anchor (:func:`behaviors.mop.validity.unbegun`). Arrays as in
:mod:`behaviors.mop.members`; each function states the follower method it equals.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from behaviors.mop import (group_layout, halts, handover, overrun, path_kernel, shape_lead,
                          speed_profile, take_fit, take_rule)
from behaviors.mop import validity
from behaviors.mop import tempo as tempo_rules   # (its function tempo is this module's)
from behaviors.mop.handover import TEMPO_END_BACK, TEMPO_END_OVER, TEMPO_END_STILL
from behaviors.mop.group_layout import MC_ROWS
from behaviors.mop.take_rule import TAKE_FROM_NEAREST, TAKE_RESIZE
from behaviors.mop.take_fit import size_of_refused, take_fits_at
from behaviors.mop.validity import CARRY_FIRST
from behaviors.mop.tempo import LEAST_TEMPO, TEMPO_SAMPLES
from behaviors.kernel_cache import compiled

# the files whose compiled functions or constants the kernels take in (path_kernel's through
# overrun's)
_CALLS_INTO = (group_layout, halts, handover, overrun, path_kernel, shape_lead, speed_profile,
               take_fit, take_rule, tempo_rules, validity)

_F1, _F2, _F3 = numba.float64[::1], numba.float64[:, ::1], numba.float64[:, :, ::1]
_I1, _I2, _B1 = numba.intp[::1], numba.intp[:, ::1], numba.boolean[::1]
_FA1 = numba.float64[:]   # a column of the per-template state (group_layout.FLOATS)


@compiled(numba.void(_F2, _F2, _B1, _B1, _F2, _B1, _F1, _B1, _F1, _I1, _I1, _I2, _F1, _F1, _F1,
                   _F1, numba.intp, numba.float64, _B1, _F1, numba.float64, _B1, _F1, _F1,
                   numba.float64, _B1, _B1, numba.float64, numba.float64, numba.float64,
                   _F2, _FA1, _F3, _I1, _B1, numba.float64, numba.float64),
          *_CALLS_INTO)
def turned(x, anchor, present, turning, ref, has_ref, heading, has_heading, turn, best, bounds, ti,
           mean, turns, step, limit, reach, first_steps, ok, before, unturned, hidden, waits,
           source, straight_to, straight, rest, rest_bent, rest_unturned,
           rest_turned, path, size, taken, taken_n, bent, stroke_straight, strays) -> None:
    """:meth:`Turning._turned` for every present member whose input ``turning`` is measured
    (2-D spatial): its turning since its gesture began (``turn``, from the last step's end
    ``ref`` and direction ``heading``, :func:`~behaviors.mop.turning.turn_step`; ``step``:
    its step length), and whether it is within ``limit`` (M,) radians of its best template's at the
    states within ``reach`` of the followed one (:func:`~behaviors.mop.turning.turn_fits`;
    ``turns`` (S,): each state's turning, laid out as ``ti``), into ``ok``; and whether its
    best is not shown just before a straight stroke's bend (``before`` (S,), ``unturned``:
    :func:`bends.unturned <behaviors.mop.bends.unturned>`), into ``hidden``; and whether its
    size's growth spares no overrun where its template waits (``waits`` (S,),
    :func:`bends.waits <behaviors.mop.bends.waits>`; :func:`bends.unspared
    <behaviors.mop.bends.unspared>`: ``source`` (S,), each state's progress; ``straight_to``:
    its limit, -inf for never), into
    ``straight``; and, into ``ok`` as well, whether a new best is not taken while the member
    rests (``rest``) on a straight stroke where its template has turned (:func:`bends.bent_rest
    <behaviors.mop.bends.bent_rest>`; ``rest_bent``: its limit, 0 for never; ``rest_unturned``,
    ``rest_turned``: its second); and, into ``hidden`` as well, whether the member draws a
    straight stroke its best's path so far strays from (:func:`bends.strays
    <behaviors.mop.bends.strays>`: ``path`` (S, 2), each state from its template's first, raw
    units; ``size`` (K,); ``taken``, ``taken_n``: the gesture's last samples, this one not yet
    among them; ``bent``: the member's input left its chord since its attempt began, set here;
    ``stroke_straight``, ``strays``: its limits, ``strays`` 0 for never). The same
    operations in the same order as the follower's own."""
    pi, two_pi = math.pi, 2.0 * math.pi
    for i in range(x.shape[0]):
        hidden[i] = False
        straight[i] = False
        if not (turning[i] and present[i]):
            continue
        if not has_ref[i]:
            ref[i, 0], ref[i, 1] = anchor[i, 0], anchor[i, 1]
            has_ref[i] = True
        else:
            d0, d1 = x[i, 0] - ref[i, 0], x[i, 1] - ref[i, 1]
            if math.hypot(d0, d1) > (step[i] if has_heading[i] else first_steps * step[i]):
                h = math.atan2(d1, d0)
                if has_heading[i]:
                    turn[i] += (h - heading[i] + pi) % two_pi - pi
                heading[i], has_heading[i] = h, True
                ref[i, 0], ref[i, 1] = x[i, 0], x[i, 1]
        k = bounds[i] + best[i]
        lo, n, off = ti[k, 0], ti[k, 1], ti[k, 2]
        c = int(lo + min(mean[k], n - 1.0))
        least = np.inf
        for j in range(max(lo, c - reach), min(lo + n - 1, c + reach) + 1):
            least = min(least, abs((turns[off + j] - turn[i] + pi) % two_pi - pi))
        ok[i] = least <= limit[i]
        if rest_bent > 0 and rest[i]:
            off_c = abs((turns[off + c] - turn[i] + pi) % two_pi - pi)
            ok[i] = ok[i] and not (abs(turn[i]) < unturned and off_c >= rest_bent
                                   or abs(turn[i]) < rest_unturned and off_c >= rest_turned)
        hidden[i] = before[off + c] > 0.0 and abs(turn[i]) < unturned
        d0, d1 = x[i, 0] - anchor[i, 0], x[i, 1] - anchor[i, 1]
        chord = math.hypot(d0, d1)
        if strays > 0.0 and not bent[i] and chord > 0.0:
            u0, u1 = d0 / chord, d1 / chord
            for r in range(max(0, taken_n[i] - (taken.shape[1] - 1)), taken_n[i]):
                if abs(taken[i, r, 0] * u1 - taken[i, r, 1] * u0) > stroke_straight:
                    bent[i] = True
                    break
            if not bent[i]:
                far = 0.0
                for j in range(lo, c + 1):
                    far = max(far, abs(path[off + j, 0] * u1 - path[off + j, 1] * u0))
                hidden[i] = hidden[i] or far * size[k] > strays
        g = lo + min(mean[k], n - 1.0)
        j = int(g)
        at = source[off + j] + (g - j) * (source[off + min(j + 1, lo + n - 1)] - source[off + j])
        straight[i] = waits[off + c] > 0.0 and abs(turn[i]) < unturned and at < straight_to


@compiled(numba.void(_B1, _B1, _F2, _F2, _F3, _I1, _I1, _I1, _I1, _B1, _F2, _I2, _F1, _F2, _F2,
                     _F2, numba.float64, _F2), *_CALLS_INTO)
def takes(present, has_anchor, x, anchor, taken, taken_n, bounds, best, acquired, leads, states,
          ti, mean, tc, mc, floats, limit, shift) -> None:
    """:meth:`TakeRule._remember_take` for every present member with an ``anchor``: its sample
    ``x - anchor`` appended to its last samples ``taken[i]`` (TAKE_SAMPLES, D; ``taken_n`` of
    them, oldest first, the oldest out when full); then the last of :meth:`ShapeLead._leads`'
    conditions, :meth:`TakeRule._fits_take`, for each whose new ``best`` leads (not
    ``acquired``): whether those samples fit its path within ``limit`` (``leads``, in place;
    "scale" invariance only; ``states``, ``ti``, ``tc``, ``mc`` laid out as
    :func:`behaviors.mop.group_kernel.update_templates` reads them, ``mean`` the forward's,
    ``floats`` the per-template state of :data:`~behaviors.mop.group_layout.FLOATS`, a
    column each); a take
    refused sizes its template where :func:`~behaviors.mop.take_fit.size_of_refused` finds
    a size (:data:`~behaviors.mop.take_rule.TAKE_RESIZE`). ``shift`` (M, D): each member's
    anchor less where the input came nearest the ended template's last point, the samples read
    from there too (:data:`~behaviors.mop.take_rule.TAKE_FROM_NEAREST`; zero: not).

    Compiled here rather than done by the group's Python around its compiled passes (fancy
    indexing over the members and a call through the follower, its Python and a copy of the
    samples, for each member whose new best led). With :func:`tempo`, :func:`unbegun` and
    :func:`still_unbegun` called from :func:`behaviors.mop.members.conclude` instead of one
    dispatch each from Python: see the figures in
    :meth:`behaviors.mop.group.FollowerGroup._conclude`. Strict arithmetic, as the
    follower's; called from the strict :func:`~behaviors.mop.members.conclude`, the per-template
    pass (compiled with ``contract``) is left as it was."""
    d = x.shape[1]
    num, den = floats[:, 3], floats[:, 4]   # (group_layout.FLOATS)
    size, least = floats[:, 5], floats[:, 9]
    arc = states[:, 2 * d + 1]   # (group_layout.STATE_COLUMNS)
    for i in range(x.shape[0]):
        if not present[i]:
            continue
        n = taken_n[i]
        if has_anchor[i]:
            if n == taken.shape[1]:
                for r in range(n - 1):
                    for c in range(d):
                        taken[i, r, c] = taken[i, r + 1, c]
                n -= 1
            for c in range(d):
                taken[i, n, c] = x[i, c] - anchor[i, c]
            n += 1
            taken_n[i] = n
        m = mc[i]   # group_layout.MEMBER_SCALARS: dims, scaled, lo, hi, misfit_decay, path_scale
        if not (leads[i] and acquired[i] != best[i] and m[8] > 0.0 and n > 0):
            continue
        sizes = m[MC_ROWS + 2 * d:]   # take_rule.TAKE_SIZES from the estimate outwards
        gb = bounds[i] + best[i]
        start, length = ti[gb, 0], ti[gb, 1]
        g = start + min(mean[gb], length - 1.0)
        leads[i] = take_fits_at(taken[i, :n, :int(m[0])], states, ti[gb, 2], start, length, g,
                                tc[gb, 5:], tc[gb, 5 + 3 * d:], size[gb], m[9], m[10], m[11],
                                m[14], sizes, limit)
        moved = False
        for c in range(d):
            moved = moved or shift[i, c] != 0.0
        if not leads[i] and TAKE_FROM_NEAREST > 0.0 and moved:
            dm = int(m[0])
            near = np.empty((n, dm))
            for r in range(n):
                for c in range(dm):
                    near[r, c] = taken[i, r, c] + shift[i, c]
            leads[i] = take_fits_at(near, states, ti[gb, 2], start, length, g, tc[gb, 5:],
                                    tc[gb, 5 + 3 * d:], size[gb], m[9], m[10], m[11], m[14],
                                    sizes, TAKE_FROM_NEAREST)
        if leads[i] or TAKE_RESIZE <= 0.0:
            continue
        s = size_of_refused(taken[i, :n, :int(m[0])], states, arc, ti[gb, 2], start, length, g,
                            tc[gb, 5:], tc[gb, 5 + 3 * d:], size[gb], max(m[9], least[gb]),
                            m[11], m[14], sizes, TAKE_RESIZE)
        if s > 0.0:   # as TakeRule._fits_take: in place on the estimate's sums
            num[gb] = s * (den[gb] + tc[gb, 2]) - tc[gb, 2]
            size[gb] = s


@compiled(numba.boolean[::1](_F2, _I2, _F1, _F2, _F2, _F2, _F2, _B1, _B1, _I1, _I1, _I1, _I1,
                             _F3, _F2, _F2, _FA1, _I1, _B1, _F1, _I1, _F1, _F1,
                             numba.float64[:, :]), *_CALLS_INTO)
def overruns(states, ti, mean, tc, mc, x, anchor, present, spots, bounds, best, at, seen,
             tempo_x, tempo_g, tempo_s, size, overran_k, straight, progress, drive_k,
             drive_from, drive_peak, units) -> np.ndarray:
    """:meth:`Validity._overruns` of every present member that spots, for its best template
    (``size``: each template's), against the samples, followed states and sizes its tempo ring
    keeps (``tempo_x``, ``tempo_g``, ``tempo_s``; ``at``: the slot written next, ``seen``:
    samples so far; as :func:`tempo` reads them, before it writes this one); ``states``,
    ``ti``, ``tc``, ``mc``: as :func:`behaviors.mop.members.conclude` takes them;
    ``overran_k``: the template each overran at its last sample (-1: none), updated;
    ``straight``: whether its size's growth spares it (:func:`turned`); ``progress`` (K,),
    ``drive_k``, ``drive_from``, ``drive_peak``, ``units`` (M, D): as
    :func:`behaviors.mop.members.conclude` reads them (for :func:`behaviors.mop.halts.halts`,
    before this sample's peak). Out: (M,) flags."""
    out = np.zeros(bounds.size, dtype=np.bool_)
    w = TEMPO_SAMPLES
    back = max(overrun.PACE_SAMPLES, overrun.RISE_SAMPLES)
    d = x.shape[1]
    sc0, uf0, co0 = 5, 5 + 2 * d, 5 + 3 * d   # columns of tc (group_layout.TEMPLATE_ROWS)
    for i in range(bounds.size):
        m = mc[i]
        if not present[i]:
            continue
        held = overran_k[i] == best[i]
        overran_k[i] = -1
        if not (spots[i] and m[8] > 0.0) or seen[i] < back:   # "scale" only
            continue
        gb = bounds[i] + best[i]
        start, length, off = ti[gb, 0], ti[gb, 1], ti[gb, 2]
        sp = (at[i] - overrun.PACE_SAMPLES) % w
        sr = (at[i] - overrun.RISE_SAMPLES) % w
        out[i] = overrun.overruns(
            states[:, :d], states[:, 2 * d + 1], start, length, off, tc[gb, sc0:sc0 + d],
            tc[gb, uf0:uf0 + d], tc[gb, co0:co0 + d], anchor[i], x[i], tempo_x[sr, i],
            tempo_x[sp, i], min(mean[gb], length - 1.0), tempo_g[sr, gb], tempo_g[sp, gb],
            size[gb], tempo_s[sp, gb], m[14], m[0], held, not straight[i])
        if out[i]:
            overran_k[i] = best[i]
        sigma = math.sqrt(m[14] / m[0])
        # ... or its performer halts, not yet carried forward, where its template goes on (the
        # follower's Recognition._conclude: halts.halts, the ring before this sample)
        if not out[i] and seen[i] >= halts.BACK and drive_k[i] == best[i] and max(
                drive_peak[i], progress[gb]) - drive_from[i] < CARRY_FIRST:
            out[i] = halts.halts(
                states[:, :d], start, length, off, tc[gb, sc0:sc0 + d], units[i], x[i],
                tempo_x[(at[i] - halts.RECENT) % w, i], tempo_x[(at[i] - halts.BACK) % w, i],
                min(mean[gb], length - 1.0), progress[gb], size[gb], sigma)
        # ... or it waits where its template slows and the input keeps its speed, at this
        # sample and the one before (speed_profile.outpaces; not counted as an overrun)
        if out[i] or seen[i] < speed_profile.BACK + 1:
            continue
        # (over the member's own columns: speed_profile's RMS per column counts them all, and
        # the padding past them would dilute a narrower member's speed)
        dm = int(m[0])
        ms, sc, uf = states[:, :dm], tc[gb, sc0:sc0 + dm], tc[gb, uf0:uf0 + dm]
        co, an = tc[gb, co0:co0 + dm], anchor[i, :dm]
        x_recent = tempo_x[(at[i] - speed_profile.RECENT) % w, i, :dm]
        x_back = tempo_x[(at[i] - speed_profile.BACK) % w, i, :dm]
        waits = True
        for ago in range(2):
            xa = x[i, :dm] if ago == 0 else tempo_x[(at[i] - 1) % w, i, :dm]
            ga = mean[gb] if ago == 0 else tempo_g[(at[i] - 1) % w, gb]
            sa = size[gb] if ago == 0 else tempo_s[(at[i] - 1) % w, gb]
            if not speed_profile.outpaces(
                    ms, start, length, off, sc, uf, co, an, xa,
                    tempo_x[(at[i] - speed_profile.RECENT - ago) % w, i, :dm],
                    tempo_x[(at[i] - speed_profile.BACK - ago) % w, i, :dm], min(ga, length - 1.0),
                    tempo_g[(at[i] - speed_profile.STALL_SAMPLES - ago) % w, gb], sa, sigma):
                waits = False
                break
        # ... or, at its start, the input quickens where its template slows
        # (speed_profile.quickens, this sample)
        waits = waits or speed_profile.quickens(
            ms, start, length, off, sc, uf, co, an, x[i, :dm], x_recent, x_back,
            min(mean[gb], length - 1.0), progress[gb], size[gb], tempo_s[(at[i] - 1) % w, gb],
            sigma)
        # ... or the input goes on off the way it turns (speed_profile.turns_on, this sample)
        out[i] = waits or speed_profile.turns_on(
            ms, start, length, off, sc, uf, co, an, x[i, :dm], x_recent, x_back,
            min(mean[gb], length - 1.0), size[gb], tempo_s[(at[i] - 1) % w, gb], sigma)
    return out


@compiled(numba.boolean(numba.intp, numba.intp, numba.float64, _F2, _F3, _F2, _I1, _I1, _F2,
                        numba.intp, numba.float64, numba.float64, numba.float64, numba.float64,
                        _F2), *_CALLS_INTO)
def slow_of(i: int, k: int, state: float, x: np.ndarray, past_x: np.ndarray,
            past_g: np.ndarray, at: np.ndarray, seen: np.ndarray, scale: np.ndarray, c0: int,
            size: float, dims: float, onset: float, samples: float,
            anchor: np.ndarray) -> bool:
    """:meth:`Validity._slow_take` of member ``i``'s template ``k`` (group index; ``state``:
    its followed state, ``mean`` clipped to the template) against the oldest sample the ring
    keeps (before :func:`tempo` keeps this one), or its first state at the ``anchor`` where
    that one precedes the attempt of ``samples`` samples with this one
    (:func:`tempo.before_attempt`); ``scale[k, c0:]``: its spread, at ``size``."""
    w = TEMPO_SAMPLES
    if seen[i] < w or LEAST_TEMPO <= 0:
        return False
    a = at[i]
    fresh = tempo_rules.before_attempt(samples)
    tot = 0.0
    for c in range(x.shape[1]):
        r = (x[i, c] - (anchor[i, c] if fresh else past_x[a, i, c])) / (scale[k, c0 + c] * size)
        tot += r * r
    return tempo_rules.slow_take(state - (0.0 if fresh else past_g[a, k]),
                                 math.sqrt(tot / dims), onset,
                                 tempo_rules.span(samples) if fresh else float(w))


@compiled(numba.void(_F1, _I1, _B1, _B1, _I1, _I1, _I1, _I1, _I1, _F2, _F3, _F2, _F2, _F2, _FA1,
                     _F1, numba.float64, _B1, _I2, _I1, _F1, _F2, _F2), *_CALLS_INTO)
def tempo(mean: np.ndarray, lengths: np.ndarray, present: np.ndarray, spots: np.ndarray,
          at: np.ndarray, seen: np.ndarray, bounds: np.ndarray, counts: np.ndarray,
          best: np.ndarray, x: np.ndarray, past_x: np.ndarray, past_g: np.ndarray,
          past_s: np.ndarray, scale: np.ndarray, size: np.ndarray, dims: np.ndarray, onset: float,
          leads: np.ndarray, crawl: np.ndarray, drive_k: np.ndarray, samples: np.ndarray,
          anchor: np.ndarray, mc: np.ndarray) -> None:
    """:meth:`Validity._slow_take` for every present member that spots (``spots``): once it has
    :data:`TEMPO_SAMPLES` samples (``seen``), its best template taken too slowly
    (:func:`tempo.slow_take`: followed state, ``mean`` clipped to the template, against the
    oldest kept in ``past_g``; the input against ``past_x[at]`` in the template's spread
    ``scale`` at its ``size``, RMS over ``dims`` columns; its first state and the ``anchor``
    where that sample precedes the attempt of ``samples`` samples with this one,
    :func:`tempo.before_attempt`) does not lead (``leads``), and
    ``crawl[i]`` (samples in a row best crawled, best) counts on (:func:`tempo.crawls`;
    kept while the input hovers as :func:`tempo.crawl_run` says, ``drive_k``: the action
    that last drove; ``mc``: the member scalars, :data:`~behaviors.mop.tempo.CRAWL_SAMPLES`
    and ``CRAWL_HOVERS`` among them, :data:`~behaviors.mop.group_layout.MEMBER_SCALARS`);
    then this sample, the followed states and sizes (``past_s``) are kept in the ring's slot
    ``at``, which moves on."""
    w = TEMPO_SAMPLES
    for i in range(bounds.size):
        if not (present[i] and spots[i]):
            continue
        a = at[i]
        slow = False
        hovers = False
        if seen[i] >= w and LEAST_TEMPO > 0:
            gb = bounds[i] + best[i]
            fresh = tempo_rules.before_attempt(samples[i])
            tot = 0.0
            for c in range(x.shape[1]):
                r = (x[i, c] - (anchor[i, c] if fresh else past_x[a, i, c])) / (scale[gb, c]
                                                                                 * size[gb])
                tot += r * r
            moved = math.sqrt(tot / dims[i])
            advance = min(mean[gb], lengths[gb] - 1.0) - (0.0 if fresh else past_g[a, gb])
            if tempo_rules.slow_take(advance, moved, onset,
                                     tempo_rules.span(samples[i]) if fresh else float(w)):
                leads[i] = False
                slow = True
            hovers = moved < onset and abs(advance) < LEAST_TEMPO * w and drive_k[i] != best[i]
        same = crawl[i, 1] == best[i]
        if slow:
            crawl[i, 0] = crawl[i, 0] + 1 if same else 1
        elif not (same and hovers and mc[i, 28] > 0.0 and 0 < mc[i, 27] <= crawl[i, 0]):
            crawl[i, 0] = 0   # tempo.crawl_run
        crawl[i, 1] = best[i]
        for c in range(x.shape[1]):
            past_x[a, i, c] = x[i, c]
        for k in range(bounds[i], bounds[i] + counts[i]):
            past_g[a, k] = min(mean[k], lengths[k] - 1.0)
            past_s[a, k] = size[k]
        at[i] = (a + 1) % w
        seen[i] += 1


@compiled(numba.void(_B1, _B1, _F2, _F2, _F2, _B1), *_CALLS_INTO)
def unbegun(abandoned: np.ndarray, present: np.ndarray, x: np.ndarray, anchor: np.ndarray,
            came: np.ndarray, leads: np.ndarray) -> None:
    """:func:`behaviors.mop.validity.unbegun` for every present member whose attempt was begun
    by abandonment (``abandoned``): no new action leads (``leads`` cleared) while its way from
    the ``anchor`` (``x - anchor``, (M, D)) goes back against ``came``. As a loop over the
    members calling the function (three numpy products each) it took 33 us median of DESIGN's
    8 x 100 templates tick back to back, 53 us after the view's two frames; compiled, one call:
    5 us (the products summed in column order: numpy's may round the last bit otherwise, which
    decides only a cosine of exactly -REVERSED)."""
    for i in range(x.shape[0]):
        if not (abandoned[i] and present[i]):
            continue
        dot = 0.0
        ww = 0.0
        cc = 0.0
        for c in range(x.shape[1]):
            w = x[i, c] - anchor[i, c]
            dot += w * came[i, c]
            ww += w * w
            cc += came[i, c] * came[i, c]
        if dot < -validity.REVERSED * math.sqrt(ww * cc):
            leads[i] = False


@compiled(numba.void(_B1, _B1, _B1, _B1, _F2), *_CALLS_INTO)
def still_unbegun(abandoned: np.ndarray, rested: np.ndarray, rests: np.ndarray,
                  present: np.ndarray, mc: np.ndarray) -> None:
    """:func:`behaviors.mop.validity.still_unbegun` for every ``present`` member, in place: still
    ``abandoned`` and ``rested`` since, after a sample where it ``rests`` (``mc``: the member
    scalars, :data:`~behaviors.mop.validity.RESTED_LIFTS` at column 36). As numpy operations
    on the present members (three masked reads, six operations, two masked writes) it took
    ~26 us of DESIGN's 8 x 100 templates tick after the per-template pass (4.6 us with its
    code in the caches; about 3 of the 8 performers are abandoned on a tick, so skipping it
    when none is would rarely help); compiled, one call: ~5 us. The whole tick after the
    view's two frames, the two interleaved in blocks of 25 in one process (four runs of 1000
    or 1500 ticks each, load 1.5-2.3): median 1568 -> 1505, 1461 -> 1431, 1643 -> 1580,
    1377 -> 1375 us."""
    for i in range(abandoned.size):
        if not present[i]:
            continue
        r = rests[i]
        lifted = (r and mc[i, 36] == 0.0) or (rested[i] and not r)
        still = abandoned[i] and not lifted
        abandoned[i] = still
        rested[i] = still and r


@compiled(numba.boolean(_F2, _I1, numba.intp, numba.float64, numba.float64), *_CALLS_INTO)
def tempo_ended(history: np.ndarray, count: np.ndarray, i: int, progress: float,
                end: float) -> bool:
    """Member ``i``'s action's ``progress`` appended to its last ones ``history[i]`` (oldest
    first, ``count[i]`` valid, the newest last), then :func:`behaviors.mop.handover.tempo_ended`
    over them."""
    s = history.shape[1]
    for r in range(s - 1):
        history[i, r] = history[i, r + 1]
    history[i, s - 1] = progress
    count[i] = min(count[i] + 1, s)
    if count[i] < s:
        return False
    return handover.tempo_reached(history[i, s - 1 - TEMPO_END_BACK],
                                  history[i, s - 1 - TEMPO_END_BACK - TEMPO_END_OVER], end)


@compiled(numba.boolean(_F3, _I1, numba.intp, _F1), *_CALLS_INTO)
def slowed(buf: np.ndarray, count: np.ndarray, i: int, radius: np.ndarray) -> bool:
    """:func:`behaviors.mop.handover.slowed` over member ``i``'s buffered samples: the last moved at
    most ``TEMPO_END_STILL radius`` (D,) in every column from the one before."""
    s = buf.shape[1]
    if count[i] < 2:
        return False
    for c in range(buf.shape[2]):
        if not abs(buf[i, s - 1, c] - buf[i, s - 2, c]) <= TEMPO_END_STILL * radius[c]:
            return False
    return True
