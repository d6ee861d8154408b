"""A follower group's arrays: its members' state shared as views of arrays over the whole group,
and their constants laid out as the compiled passes read them.

Mixin of :class:`~behaviors.mop.group.FollowerGroup`, built once when the group is made: every
member's per-template state becomes a view of one array over the group (a tick updates all of
them in a few array operations), each member's own constants and state are rows of arrays
(M, ...), and the constants :func:`~behaviors.mop.group_kernel.update_templates` and
:func:`~behaviors.mop.members.conclude` read are stacked in their column layout.
"""

from __future__ import annotations

import numpy as np

from behaviors.mop import (coverage, gesture_end, group_layout, members, shape_lead, spotting,
                           take_rule, tempo, threshold, validity)
from behaviors.mop.holding import holding_columns
from behaviors.mop.take_fit import outwards
from behaviors.mop.shape_lead import TAKE_SAMPLES
from behaviors.mop.handover import TEMPO_END_KEEP


class GroupArrays:
    """The arrays a follower group steps its members with, shared with the members."""

    def _share_state(self) -> None:
        """Every member's per-template state becomes a view of one array over the whole group,
        and its constants are stacked, so a tick updates all of them in a few array operations."""
        fs, sl = self.followers, self._slices
        per = lambda fn: np.concatenate([np.broadcast_to(fn(f), (len(f.names),)) for f in fs])
        for name in self._PER_TEMPLATE:
            whole = np.concatenate([getattr(f, name) for f in fs])
            setattr(self, name, whole)
            for f, s in zip(fs, sl):
                setattr(f, name, whole[s])
        state_off = np.cumsum([0] + [len(f.bank.source) for f in fs])[:-1]
        self._state_off = per(lambda f: state_off[fs.index(f)]).astype(np.intp)
        self._starts_local = np.concatenate([f.bank.starts for f in fs]).astype(np.intp)
        self._lengths = np.concatenate([f.bank.lengths for f in fs]).astype(np.intp)
        dmax = max(f.dim for f in fs)
        self._rel = np.concatenate([np.pad(f._rel, ((0, 0), (0, dmax - f.dim))) for f in fs])
        self._scale = np.concatenate([np.pad(f.bank.scale, ((0, 0), (0, dmax - f.dim)),
                                             constant_values=1.0) for f in fs])

    def _member_arrays(self) -> None:
        """Each member's own constants and state (anchor, recent samples, best, ends) as rows of
        arrays (M, ...), padded to the widest member's features with values that change nothing."""
        fs, m = self.followers, len(self.followers)
        dmax = self._rel.shape[1]
        pad = lambda a, v=0.0: np.pad(np.asarray(a, dtype=float), (0, dmax - len(a)),
                                      constant_values=v)
        col = lambda fn, dtype=float: np.array([fn(f) for f in fs], dtype=dtype)
        self._m_units = np.array([pad(f._units, 1.0) for f in fs])
        self._m_radius = np.array([pad(f._still_radius) for f in fs])
        self._m_keep = col(lambda f: f.still_samples, np.intp)
        self._m_tangent = [i for i, f in enumerate(fs) if f.tangent > 0]
        # each member's template names and their rows in the group's per-template arrays
        self._k_names = [n for f in fs for n in f.names]
        self._m_index = [{n: int(a) + j for j, n in enumerate(f.names)}
                         for f, a in zip(fs, self._bounds)]
        # per template: what a sample is measured from (anchor, or the center for "none")
        self._k_none = np.concatenate([np.full(len(f.names), f.invariance == "none") for f in fs])
        self._k_center = np.concatenate([np.pad(f.bank.center, ((0, 0), (0, dmax - f.dim)))
                                         for f in fs])
        self._k_first = np.concatenate([np.pad(f._first_z, ((0, 0), (0, dmax - f.dim)))
                                        if f.invariance != "none"
                                        else np.zeros((len(f.names), dmax)) for f in fs])
        self._holds = np.concatenate([f.bank.holds for f in fs])
        self._shape = np.zeros(len(self._owner))      # spotting's shape sums (per template)
        self._shape_n = np.zeros(m)   # ... and their samples (per member)
        for n in group_layout.SHAPE_LAGS:   # ... and at each timing offset (commitment's fit)
            setattr(self, n, np.zeros(len(self._owner)))
        self._drift = np.zeros(len(self._owner))      # ... the last one's, and its run (_drifts)
        self._drift_run = np.zeros(len(self._owner))
        self._gone = np.zeros(len(self._owner))       # spotting's highest progress (per template)
        self._once = np.zeros(len(self._owner), dtype=bool)   # barred since it began (blocked)
        # ... and where its current attempt began (validity.stalls)
        self._attempt_from = np.zeros(len(self._owner))
        # spotting's shared starts (sharing.shared_until, ``share_radius``): each member's
        # (K_i, K_i) flattened, from _sh_off[i]; -1 for members without
        shared = [np.zeros(0, np.intp) if f._shared is None else f._shared.ravel() for f in fs]
        self._shared = np.concatenate(shared).astype(np.intp)
        self._sh_off = np.where([f._shared is None for f in fs], -1,
                                np.cumsum([0] + [a.size for a in shared])[:-1]).astype(np.intp)
        self._drive_moved = np.zeros(m, dtype=bool)
        # begun by abandonment, and the input's way to its anchor (validity.unbegun)
        self._abandoned, self._came = np.zeros(m, dtype=bool), np.zeros((m, dmax))
        self._abandon_rested = np.zeros(m, dtype=bool)   # ... and rested since (still_unbegun)
        # the attempt began at an end read as a return; the pending end is one (spotting)
        self._begun_at_return, self._end_returned = np.zeros((2, m), dtype=bool)
        # the input's path since the anchor, its samples and last two steps, and whether the
        # attempt was begun under way, rested since (under_way.underway)
        self._walk, self._walk_n = np.zeros(m), np.zeros(m, dtype=np.intp)
        self._step_prev, self._step_last = np.zeros(m), np.zeros(m)
        self._underway, self._underway_rested = np.zeros(m, dtype=bool), np.zeros(m, dtype=bool)
        self._everyone = np.ones(m, dtype=bool)   # every member has a sample (never written)
        self._acquired = np.full(m, -1, dtype=np.intp)
        self._drive_k = np.full(m, -1, dtype=np.intp)
        self._turning_arrays()
        self._drive_from, self._drive_peak = np.zeros(m), np.zeros(m)
        self._drive_leapt = np.zeros(m)   # (validity.leapt)
        self._last_state = self._state_off + self._starts_local + self._lengths - 1
        self._x = np.zeros((m, dmax))
        self._one_dim = all(f.dim == dmax for f in fs)
        self._anchor = np.zeros((m, dmax))
        self._has_anchor = np.zeros(m, dtype=bool)
        self._buf = np.zeros((m, int(self._m_keep.max()), dmax))
        self._nbuf = np.zeros(m, dtype=np.intp)
        self._best = np.full(m, -1, dtype=np.intp)   # -1: none yet (ActionFollower._best)
        self._run = np.zeros(m, dtype=np.intp)
        self._run_k = np.full(m, -1, dtype=np.intp)   # whose samples _run counts (recognition)
        # samples in a row best was blocked, whose, the best barred and the last freed (blocked)
        self._blocked, self._blocked_k = np.zeros(m, dtype=np.intp), np.full(m, -1, dtype=np.intp)
        self._barred, self._freed = np.full(m, -1, dtype=np.intp), np.full(m, -1, dtype=np.intp)
        # the likeliest evidence but a barred best's and the others' sum of exp (blocked)
        self._bar_top, self._bar_sum, self._bar_kept = np.zeros(m), np.ones(m), np.ones(m)
        self._lost = np.zeros(m, dtype=np.intp)
        self._ended = np.full(m, -1, dtype=np.intp)
        self._end_x = np.zeros((m, dmax))
        self._end_last = np.zeros((m, dmax))   # the ended template's last point (_moved_on)
        # where the input came nearest it since, not yet gone away from it, and the next
        # gesture's anchor less that point (take_rule.TAKE_FROM_NEAREST; zero: none)
        self._end_near, self._end_nearing = np.zeros((m, dmax)), np.zeros(m, dtype=bool)
        self._take_shift = np.zeros((m, dmax))
        # the last reversal's turn, the way into it and the samples since (-1: none pending;
        # PerformanceFrame._reversal_sizes)
        self._rev_turn, self._rev_way = np.zeros((m, dmax)), np.zeros((m, dmax))
        self._rev_age = np.full(m, -1, dtype=np.intp)
        self._has_end = np.zeros(m, dtype=bool)
        # where a gesture never recognised was followed to its end (gesture_end.UNSEEN_END)
        self._unseen_x, self._unseen_last = np.zeros((m, dmax)), np.zeros((m, dmax))
        self._has_unseen = np.zeros(m, dtype=bool)
        self._after_end = np.zeros(m, dtype=np.intp)
        self._peak, self._peak_k = np.zeros(m), np.full(m, -1, dtype=np.intp)
        # the action's last TEMPO_END_KEEP (13) progress values, _end_history_n of them valid,
        # and whether the end was reached at its tempo (handover.tempo_ended)
        self._end_history = np.zeros((m, TEMPO_END_KEEP))
        self._end_history_n = np.zeros(m, dtype=np.intp)
        self._lagged = np.zeros(m, dtype=bool)
        self._extent = np.concatenate([f._extent for f in fs])
        self._thr_ev, self._thr_x = np.zeros(m), np.zeros((m, dmax))
        self._thr_has_x = np.zeros(m, dtype=bool)
        # the gesture's last samples from the anchor, oldest first (TakeRule._fits_take)
        self._taken, self._taken_n = np.zeros((m, TAKE_SAMPLES, dmax)), np.zeros(m, dtype=np.intp)
        self._stroke_bent = np.zeros(m, dtype=bool)   # (Turning._strays' latch)
        self._tempo_arrays()
        self._m_dim = col(lambda f: f.dim)

    #: Per-template state shared with the members (each follower's arrays are views of these).
    _PER_TEMPLATE = ("_evidence", "_recent", "_recent_weight", "_refused", "_engaged", "_entries",
                     "_num", "_den", "_size", "_misfit", "_misfit_w", "_misshaped", "_covered",
                     "_least", "_judged", "_at_hold_end", "_reached", "_probe", "_fresh",
                     "_rev_undo", "_rev_at", "_seat", "_seated")
    #: Per-template state the group keeps for its members' spotting, not shared with them.
    _GROUP_TEMPLATE = ("_shape", "_drift", "_drift_run", "_gone",
                       "_attempt_from", "_once") + group_layout.SHAPE_LAGS
    _PER_MEMBER = ("_anchor", "_has_anchor", "_buf", "_nbuf", "_best", "_run", "_run_k", "_lost",
                   "_ended", "_end_x", "_end_last", "_has_end", "_acquired", "_after_end",
                   "_peak", "_peak_k", "_thr_ev", "_thr_x", "_thr_has_x", "_drive_k",
                   "_drive_from", "_drive_peak", "_drive_moved", "_shape_n", "_turn_in",
                   "_turn_h", "_turn_ref", "_turn_has_ref", "_turn_has_h", "_abandoned", "_came",
                   "_abandon_rested", "_taken", "_taken_n", "_stroke_bent", "_end_history",
                   "_end_history_n",
                   "_lagged", "_blocked", "_blocked_k", "_barred", "_freed", "_unseen_x",
                   "_unseen_last", "_has_unseen", "_end_near", "_end_nearing", "_take_shift",
                   "_rev_turn", "_rev_way", "_rev_age", "_begun_at_return",
                   "_end_returned")

    def _kernel_arrays(self) -> None:
        """The constants :func:`~behaviors.mop.group_kernel.update_templates` reads, laid out
        as it reads them (see :data:`~behaviors.mop.group_layout.STATE_COLUMNS` and the rest),
        and the per-template state it updates (the members' own arrays, shared)."""
        fs, k, m = self.followers, len(self._owner), len(self.followers)
        dmax = self._rel.shape[1]
        padded = lambda a, f: np.pad(a, ((0, 0), (0, dmax - f.dim)))
        self._states = np.ascontiguousarray(np.concatenate(
            [np.hstack([padded(f.bank.means, f), padded(f._rel, f), f.bank.source[:, None],
                        f._arc[:, None], holding_columns(f)]) for f in fs]))
        self._ti = np.ascontiguousarray(np.stack([self._starts_local, self._lengths,
                                                  self._state_off], axis=1))
        z = lambda f, on: padded(f._first_z, f) if on else np.zeros((len(f.names), dmax))
        self._tc = np.ascontiguousarray(np.hstack([
            np.concatenate([f._jacobian for f in fs])[:, None],
            np.concatenate([f._onset_state for f in fs])[:, None],
            np.concatenate([f._prior for f in fs])[:, None],
            np.concatenate([f._arc_need for f in fs])[:, None],
            np.concatenate([f._reach_inv for f in fs])[:, None],
            self._scale,
            self._k_center,
            np.concatenate([z(f, f.invariance == "offset") for f in fs]),
            np.concatenate([z(f, f.invariance == "scale") for f in fs]),
            np.concatenate([f._read_ahead for f in fs])[:, None]]))
        scalars = {"dims": lambda f: f.dim, "decay": lambda f: f._decay,
                   "null_decay": lambda f: f._null_decay, "log_constant": lambda f: f._log_constant,
                   "two_over": lambda f: 2.0 / f._zdim, "null2": lambda f: f._null2,
                   "accept2": lambda f: f._accept2, "onset_sigma": lambda f: f.onset * f.sigma,
                   "scaled": lambda f: f.invariance == "scale", "lo": lambda f: f.scale_range[0],
                   "hi": lambda f: f.scale_range[1], "misfit_decay": lambda f: f._misfit_decay,
                   "shape2": lambda f: f._shape2, "shape_accept2": lambda f: f._shape_accept2,
                   "path_scale": lambda f: f.sigma ** 2 * f.dim,
                   "spots": lambda f: f.invariance != "none",
                   "none": lambda f: f.invariance == "none",
                   "margin": lambda f: f.switch_margin, "threshold": lambda f: f.threshold,
                   "thr_factor": lambda f: -0.5 / (f.sigma * f.sigma),
                   "thr_const": lambda f: f._threshold_const, "rejudge_at": lambda f: f._rejudge_at,
                   "keep": lambda f: f.still_samples, "reversal_move2": lambda f: f._reversal_move2,
                   "coverage": lambda f: f.coverage,
                   "take_fit2": lambda f: shape_lead.TAKE_FIT ** 2,
                   "carry_first": lambda f: validity.CARRY_FIRST,
                   "crawl_samples": lambda f: tempo.CRAWL_SAMPLES,
                   "crawl_hovers": lambda f: tempo.CRAWL_HOVERS,
                   "unjudged_at_rest": lambda f: validity.UNJUDGED_AT_REST,
                   "unweighed_at_rest": lambda f: validity.UNWEIGHED_AT_REST,
                   "rest_behind": lambda f: validity.REST_BEHIND,
                   "taken_performed": lambda f: validity.TAKEN_PERFORMED,
                   "early_fit2": lambda f: coverage.EARLY_FIT ** 2,
                   "tempo_end_from": lambda f: spotting.TEMPO_END_FROM,
                   "arrive_radius": lambda f: gesture_end.ARRIVE_RADIUS,
                   "rested_lifts": lambda f: validity.RESTED_LIFTS,
                   "late_fit2": lambda f: coverage.LATE_FIT ** 2,
                   "late_until": lambda f: coverage.LATE_UNTIL}
        cols = np.array([[float(scalars[n](f)) for n in group_layout.MEMBER_SCALARS] for f in fs])
        radius = np.array([np.pad(f._still_radius, (0, dmax - f.dim), constant_values=1.0)
                           for f in fs])
        sizes = np.tile(outwards(take_rule.TAKE_SIZES), (m, 1))
        self._mc = np.ascontiguousarray(np.hstack([cols, radius, self._m_units, sizes]))
        rules = {"spread2": lambda f: f.max_spread ** 2, "min_p": lambda f: f.min_probability,
                 "spots": lambda f: f.invariance != "none", "confirm": lambda f: f.confirm,
                 "log_constant": lambda f: f._log_constant, "zdim": lambda f: f._zdim,
                 "keep": lambda f: f.still_samples, "hint_onset": lambda f: f.hint_onset * f.sigma,
                 "end": lambda f: f.end, "null2": lambda f: f._null2,
                 "depart2": lambda f: (f.accept_distance * f.sigma) ** 2,
                 "lost_after": lambda f: f.lost_samples, "dims": lambda f: f.dim,
                 "memory": lambda f: f.memory}
        cols = np.array([[float(rules[n](f)) for n in members.MEMBER_RULES] for f in fs])
        self._mk = np.ascontiguousarray(np.hstack([cols, self._m_radius, self._m_units]))
        # the per-template state the compiled passes update, one column each of two arrays
        # (a template's state together: group_layout.FLOATS)
        self._floats = self._columns(group_layout.FLOATS, float)
        self._flags = self._columns(group_layout.FLAGS, bool)
        self._k_new = np.zeros(k, dtype=bool)
        self._m_top3 = np.zeros((m, 3), dtype=np.intp)
        self._m_moving = np.zeros(m)
        self._m_any_engaged, self._m_all_refused = np.zeros(m, dtype=bool), np.zeros(m, dtype=bool)
        self._m_leads, self._m_committed = np.zeros(m, dtype=bool), np.zeros(m, dtype=bool)
        self._m_kept = np.ones(m)
        self._m_out = np.empty((len(members.MEMBER_OUT), m))   # members.conclude's answers
        self._m_flags = np.empty((len(members.MEMBER_FLAGS), m), dtype=bool)
        self._m_likely, self._m_likely_v = np.empty((m, 3), dtype=np.intp), np.empty((m, 3, 2))
        self._m_restart = np.empty(m, dtype=np.intp)
        self._m_rest = np.zeros(m, dtype=bool)   # resting (tempo.resting): once per tick
        self._reversal_at = np.concatenate([f._reversal_at for f in fs]).astype(np.intp)
        self._reversal_tol = np.concatenate([f._reversal_tol for f in fs])
        self._probe_floor2 = np.concatenate([np.full(len(f.names), f._probe_floor2) for f in fs])
        self._k_rows = np.empty((12, dmax))   # update_templates' scratch: a sample's twelve views
        # the threshold models' state (Refusal._threshold_evidence): over every state of a member
        self._means = np.ascontiguousarray(self._states[:, :dmax].T)
        # ... in single precision (threshold.PRECISION)
        self._thr_means = self._means.astype(threshold.PRECISION)
        # ... the ergodic states' weights, then the mirror chains' (threshold_kernel)
        self._thr_alpha = np.zeros(2 * len(self._states), dtype=threshold.PRECISION)
        self._thr_scratch = np.zeros(2 * max(len(f.bank.means) for f in fs),
                                     dtype=threshold.PRECISION)
        # the sample as each template sees it, then its first coordinate mirrored
        self._thr_z, self._thr_lj = np.zeros((k, dmax + 1)), np.zeros(k)
        self._thr_total = np.ones(m)   # member i's weights are _thr_alpha's over _thr_total[i]
        # each template's and mirror chain's likeliest state (scratch), each chain's summed weight
        self._thr_tops = np.zeros(3 * k)
        # the members' own arrays, each a row of one array (members.MEMBER_VECTORS, ...)
        self._m_vectors = self._rows(members.MEMBER_VECTORS, float)
        self._m_ints = self._rows(members.MEMBER_INTS, np.intp)
        self._m_floats = self._rows(members.MEMBER_FLOATS, float)
        self._m_bools = self._rows(members.MEMBER_BOOLS, bool)

    def _rows(self, names: tuple[str, ...], dtype: type) -> np.ndarray:
        """The members' arrays ``names`` (M, ...) as the rows of one array (len(names), M, ...):
        each name becomes a view of its row (the per-template state: :meth:`_columns`)."""
        rows = np.array([getattr(self, n) for n in names], dtype=dtype)
        for n, row in zip(names, rows):
            setattr(self, n, row)
        return rows

    def _columns(self, names: tuple[str, ...], dtype: type) -> np.ndarray:
        """The per-template arrays ``names`` (K,) as the columns of one array (K, len(names)):
        each name (and the members' share of a shared one) becomes a view of its column."""
        cols = np.ascontiguousarray(np.array([getattr(self, n) for n in names], dtype=dtype).T)
        for j, n in enumerate(names):
            setattr(self, n, cols[:, j])
            if n in self._PER_TEMPLATE:
                for f, sl in zip(self.followers, self._slices):
                    setattr(f, n, cols[sl, j])
        return cols
