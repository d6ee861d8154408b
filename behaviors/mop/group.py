"""Several followers stepped as one (one per performer), in one vectorised forward pass."""

from __future__ import annotations

from typing import Sequence

import numpy as np

from behaviors.mop import members
from behaviors.mop.follower import ActionFollower, FollowState, SampleError
from behaviors.mop.group_rules import GroupRules
from behaviors.mop.state import ByName
from behaviors.mop.forward import WindowedForward
from behaviors.mop.hmm import TemplateBank, TemplateError


class FollowerGroup(GroupRules):
    """Several followers (one per performer or character, each with its own templates and
    input) stepped together in one vectorised forward pass: one tick of many characters costs
    about as much as one follower over all their templates. The followers must share their
    parameters; their feature counts may differ. Each keeps its own state (``step`` of the
    group and of a member must not be mixed).
    """

    def __init__(self, followers: Sequence[ActionFollower]) -> None:
        self.followers = list(followers)
        if not self.followers:
            raise TemplateError("a follower group needs at least one follower")
        first = self.followers[0]
        for i, f in enumerate(self.followers[1:], 1):
            if not first.same_parameters(f):
                raise TemplateError(f"follower {i} of the group has other parameters than follower 0; "
                                    "a group's followers must share sigma, window, transitions and limits")
        width = max(f._zdim for f in self.followers)
        means, starts, lengths, dims, names, owner = [], [], [], [], [], []
        offset = 0
        for i, f in enumerate(self.followers):
            b = f._fbank
            padded = np.zeros((b.means.shape[0], width))
            padded[:, :b.dim] = b.means
            means.append(padded)
            starts.append(b.starts + offset)
            offset += b.means.shape[0]
            lengths.append(b.lengths)
            dims += [f._zdim] * len(b.names)
            names += [f"{i}:{n}" for n in b.names]
            owner += [i] * len(b.names)
        bank = TemplateBank(tuple(names), np.concatenate(means), np.concatenate(starts),
                            np.concatenate(lengths), np.zeros(width), np.ones(width))
        p = first._params
        self.forward = WindowedForward(bank, sigma=p["sigma"], half_window=p["window"],
                                       transitions=first.forward.transitions, floor=p["floor"],
                                       dims=np.array(dims))
        self._owner = np.array(owner, dtype=np.intp)
        bounds = np.concatenate([[0], np.cumsum([len(f.names) for f in self.followers])])
        self._slices = [slice(int(a), int(b)) for a, b in zip(bounds[:-1], bounds[1:])]
        self._z = np.zeros((len(owner), width))
        self._bounds = bounds[:-1].astype(np.intp)
        self._counts = np.diff(bounds).astype(np.intp)
        self._share_state()
        self._member_arrays()
        self.reset()

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
        self._source = np.concatenate([f.bank.source for f in fs])
        self._dsource = np.append(np.diff(self._source), 0.0)   # state to next (within a template)
        dmax = max(f.dim for f in fs)
        self._rel = np.concatenate([np.pad(f._rel, ((0, 0), (0, dmax - f.dim))) for f in fs])
        self._drel = np.concatenate([np.diff(self._rel, axis=0), np.zeros((1, dmax))])
        self._r = np.zeros((len(self._owner), dmax))
        self._away = np.zeros((len(self._owner), dmax))
        self._scale = np.concatenate([np.pad(f.bank.scale, ((0, 0), (0, dmax - f.dim)), constant_values=1.0)
                                      for f in fs])
        self._onset_sigma = per(lambda f: f.onset * f.sigma)
        self._scaled = per(lambda f: float(f.invariance == "scale"))
        self._any_scale = bool(np.any(self._scaled))
        self._prior = np.concatenate([f._prior for f in fs])
        self._lo = per(lambda f: f.scale_range[0])
        self._hi = per(lambda f: f.scale_range[1])
        self._jacobian = np.concatenate([f._jacobian for f in fs])
        self._dims = per(lambda f: float(f.dim))
        self._decay = per(lambda f: f._decay)
        self._null_decay = per(lambda f: f._null_decay)
        self._onset_state = np.concatenate([f._onset_state for f in fs])
        self._log_constant = per(lambda f: f._log_constant)
        self._two_over = per(lambda f: 2.0 / f._zdim)
        self._null2 = per(lambda f: f._null2)
        self._accept2 = per(lambda f: f._accept2)

    def _member_arrays(self) -> None:
        """Each member's own constants and state (anchor, recent samples, best, ends) as rows of
        arrays (M, ...), padded to the widest member's features with values that change nothing."""
        fs, m = self.followers, len(self.followers)
        dmax = self._r.shape[1]
        pad = lambda a, v=0.0: np.pad(np.asarray(a, dtype=float), (0, dmax - len(a)), constant_values=v)
        col = lambda fn, dtype=float: np.array([fn(f) for f in fs], dtype=dtype)
        self._m_dim = col(lambda f: f.dim)
        self._m_zdim = col(lambda f: f._zdim)
        self._m_units = np.array([pad(f._units, 1.0) for f in fs])
        self._m_radius = np.array([pad(f._still_radius) for f in fs])
        self._m_lc = col(lambda f: f._log_constant)
        self._m_null2 = col(lambda f: f._null2)
        self._m_margin = col(lambda f: f.switch_margin)
        self._m_min_p = col(lambda f: f.min_probability)
        self._m_spread2 = col(lambda f: f.max_spread ** 2)
        self._m_confirm = col(lambda f: f.confirm, np.intp)
        self._m_end = col(lambda f: f.end)
        self._m_keep = col(lambda f: f.still_samples, np.intp)
        self._m_lost_after = col(lambda f: f.lost_samples, np.intp)
        self._m_depart2 = col(lambda f: (f.accept_distance * f.sigma) ** 2)
        self._m_onset = col(lambda f: f.onset * f.sigma)
        self._m_spots = col(lambda f: f.invariance != "none", bool)
        self._m_tangent = [i for i, f in enumerate(fs) if f.tangent > 0]
        self._m_names = [f.names for f in fs]
        # per template: what a sample is measured from (anchor, or the center for "none")
        self._k_none = np.concatenate([np.full(len(f.names), f.invariance == "none") for f in fs])
        self._k_center = np.concatenate([np.pad(f.bank.center, ((0, 0), (0, dmax - f.dim))) for f in fs])
        self._k_first = np.concatenate([np.pad(f._first_z, ((0, 0), (0, dmax - f.dim))) if f.invariance != "none"
                                        else np.zeros((len(f.names), dmax)) for f in fs])
        self._holds = np.concatenate([f.bank.holds for f in fs])
        # the path-shape rules (validity): states in raw template units, arcs, limits
        padded = lambda a, f: np.pad(a, ((0, 0), (0, dmax - f.dim)))
        self._path = np.ascontiguousarray(np.concatenate(
            [np.hstack([padded(f.bank.means, f), padded(f._seg, f), f._seg_inv[:, None]]) for f in fs]))
        self._k_radius = np.concatenate([np.tile(pad(f._still_radius, 1.0), (len(f.names), 1)) for f in fs])
        self._arc = np.concatenate([f._arc for f in fs])
        self._arc_need = np.concatenate([f._arc_need for f in fs])
        per = lambda fn: np.concatenate([np.full(len(f.names), fn(f), dtype=float) for f in fs])
        self._misfit_decay = per(lambda f: f._misfit_decay)
        self._shape2 = per(lambda f: f._shape2)
        self._shape_accept2 = per(lambda f: f._shape_accept2)
        self._path_scale = per(lambda f: f.sigma ** 2 * f.dim)
        self._k_c = np.concatenate([np.pad(f._first_z, ((0, 0), (0, dmax - f.dim))) if f.invariance == "scale"
                                    else np.zeros((len(f.names), dmax)) for f in fs])
        self._k_ufirst = np.concatenate([np.pad(f._first_z, ((0, 0), (0, dmax - f.dim)))
                                         if f.invariance == "offset" else np.zeros((len(f.names), dmax))
                                         for f in fs])
        self._k_spots = per(lambda f: float(f.invariance != "none"))
        self._shape = np.zeros(len(self._owner))      # spotting's shape sums (per template)
        self._acquired = np.full(m, -1, dtype=np.intp)
        self._last_state = self._state_off + self._starts_local + self._lengths - 1
        self._index = np.arange(len(self._owner))
        self._spans = [(s.start, s.stop) for s in self._slices]
        self._x = np.zeros((m, dmax))
        self._anchor = np.zeros((m, dmax))
        self._has_anchor = np.zeros(m, dtype=bool)
        self._buf = np.zeros((m, int(self._m_keep.max()), dmax))
        self._nbuf = np.zeros(m, dtype=np.intp)
        self._best = np.zeros(m, dtype=np.intp)
        self._run = np.zeros(m, dtype=np.intp)
        self._lost = np.zeros(m, dtype=np.intp)
        self._ended = np.full(m, -1, dtype=np.intp)
        self._end_x = np.zeros((m, dmax))
        self._has_end = np.zeros(m, dtype=bool)

    _PER_TEMPLATE = ("_evidence", "_recent", "_recent_weight", "_refused", "_engaged", "_entries",
                     "_num", "_den", "_size", "_misfit", "_misfit_w", "_misshaped", "_covered")
    _PER_MEMBER = ("_anchor", "_has_anchor", "_buf", "_nbuf", "_best", "_run", "_lost", "_ended",
                   "_end_x", "_has_end", "_acquired")

    def _clear_members(self, rows: np.ndarray) -> None:
        """Members ``rows`` (bool or indices) forget their performance (ActionFollower.reset)."""
        self._has_anchor[rows] = False
        self._nbuf[rows] = 0
        for a in (self._best, self._run, self._lost):
            a[rows] = 0
        self._ended[rows] = -1
        self._has_end[rows] = False
        self._acquired[rows] = -1
        self._shape[np.isin(self._owner, np.arange(len(self.followers))[rows])] = 0.0

    def reset(self) -> None:
        """Forget every performance."""
        self.forward.reset()
        for f in self.followers:
            f.reset()
        self._clear_members(slice(None))

    def reset_member(self, i: int) -> None:
        """Forget the performance followed by member ``i`` only (its next performance starts
        afresh: every template at its first state, no evidence); the others go on."""
        sl = self._slices[i]
        self.forward.reset_templates(np.arange(sl.start, sl.stop), fresh=True)
        f = self.followers[i]
        entries = self.forward.entries[sl].copy()
        f.reset()
        f._entries[:] = entries
        self._clear_members([i])

    def step(self, samples: Sequence[np.ndarray]) -> list[FollowState]:
        """One sample per follower, in order; returns each follower's state."""
        if len(samples) != len(self.followers):
            raise SampleError(f"{len(samples)} samples for a group of {len(self.followers)} followers")
        X = self._x
        lost = []
        for i, (f, x) in enumerate(zip(self.followers, samples)):
            x = f._sample(x)
            if x is None:
                lost.append(i)
            else:
                X[i, :f.dim] = x
        present = np.ones(len(self.followers), dtype=bool)
        present[lost] = False
        fresh = present & ~self._has_anchor
        self._anchor[fresh] = X[fresh]
        self._has_anchor |= present
        self._inputs(present)
        fw = self.forward
        saved = None
        if lost:
            saved = fw.snapshot(np.flatnonzero(np.isin(self._owner, lost)))
            kept = [(n, getattr(self, n)[self._owner_of(lost)].copy()) for n in self._PER_TEMPLATE + ("_shape",)] + \
                   [(n, getattr(self, n)[lost].copy()) for n in self._PER_MEMBER]
        step_ll = fw.step(self._z)
        if saved is not None:
            fw.restore(saved)
        out = self._finish(step_ll, present)
        if lost:
            for n, a in kept:
                getattr(self, n)[lost if n in self._PER_MEMBER else self._owner_of(lost)] = a
            for i in lost:
                out[i] = self.followers[i]._held()
        return out

    def _owner_of(self, members: list[int]) -> np.ndarray:
        return np.isin(self._owner, members)

    def _inputs(self, present: np.ndarray) -> None:
        """:meth:`PerformanceFrame._inputs` of every member into the forward's input (K, width);
        ``present`` (M,): the members with a sample."""
        r = self._mapped()
        self._z[:, :r.shape[1]] = r
        for i in self._m_tangent:   # direction of motion: the member's own lag
            if not present[i]:
                continue
            f, sl = self.followers[i], self._slices[i]
            f._anchor = self._anchor[i, :f.dim].copy()
            self._z[sl, :f._zdim] = f._inputs(self._x[i, :f.dim].copy())

    def _mapped(self) -> np.ndarray:
        """Every member's sample in each of its templates' standardised units (K, D): from the
        anchor (the center for "none"), divided by the estimated size for "scale"."""
        own = self._owner
        r = self._x.take(own, axis=0)
        r -= np.where(self._k_none[:, None], self._k_center, self._anchor.take(own, axis=0))
        if self._any_scale:
            r /= np.where(self._scaled > 0, self._size, 1.0)[:, None]
        r /= self._scale
        r += self._k_first
        return r

    def _finish(self, step_ll: np.ndarray, present: np.ndarray) -> list[FollowState]:
        """:meth:`ActionFollower._finish` for every member at once: the per-template arrays in
        one pass over the group, then each member's best, validity, state and spotting."""
        fw, X = self.forward, self._x
        mean = fw.mean
        g = self._starts_local + np.minimum(mean, self._lengths - 1.0)
        gi = np.minimum(g.astype(np.intp), self._starts_local + self._lengths - 2)
        frac = g - gi
        gs = gi + self._state_off
        progress = self._source.take(gs)
        progress += frac * self._dsource.take(gs)
        own = self._owner
        if self._any_scale:
            q = self._rel.take(gs, axis=0)
            q += frac[:, None] * self._drel.take(gs, axis=0)
            r = ((X - self._anchor) / self._m_units).take(own, axis=0)
            self._num += np.einsum("kd,kd->k", q, r) * self._scaled
            self._den += np.einsum("kd,kd->k", q, q) * self._scaled
            np.clip((self._num + self._prior) / (self._den + self._prior), self._lo, self._hi,
                    out=self._size)
        raw_ll = step_ll - self._jacobian
        raw_ll -= self._dims * np.log(self._size)
        ev, rec, rw = self._evidence, self._recent, self._recent_weight
        ev *= self._decay
        ev += raw_ll
        rec *= self._null_decay
        rec += step_ll
        rw *= self._null_decay
        rw += 1.0
        entries = self._entries
        new = fw.entries > entries
        entries[:] = fw.entries
        refused, engaged = self._refused, self._engaged
        back = refused & (mean < self._onset_state)
        if np.count_nonzero(back):
            back &= (self._log_constant - step_ll) * self._two_over <= self._null2
            new |= back
        if np.count_nonzero(new):
            rec[new] = self._log_constant[new]
            rw[new] = 1.0
            refused[new] = False
            engaged[new] = False
        mean_ll = rec / rw
        dist2 = (self._log_constant - mean_ll) * self._two_over
        refused |= dist2 > self._null2
        refused &= ~(dist2 < self._accept2)
        starting = (mean >= self._onset_state) & ~refused & ~engaged
        if np.count_nonzero(starting):
            # ActionFollower._displacement of the last samples' mean, for all members at once
            away = members.recent_mean(self._buf, self._nbuf, 3, X) - self._anchor
            r = away.take(own, axis=0) / self._scale
            r /= self._size[:, None]
            far = np.sqrt(np.einsum("kd,kd->k", r, r) / self._dims) >= self._onset_sigma
            engaged |= starting & far
        bounds, counts = self._bounds, self._counts
        top = np.maximum.reduceat(ev, bounds)
        p = np.exp(ev - np.repeat(top, counts))
        lead = members.segment_argmax(ev, top, bounds, counts, self._index)
        total = np.add.reduceat(p, bounds)
        p /= np.repeat(total, counts)
        # each member's threshold model competes as one more, never driving, explanation: the
        # share of the probability its templates keep against it
        rival = np.exp(np.minimum(self._threshold_evidence(raw_ll[lead], present) - top, 700.0))
        self._kept = total / (total + rival)
        return self._conclude(lead, p,
                              progress, g, gs, frac, mean_ll, new, step_ll, present)

    def _threshold_evidence(self, lead_ll: np.ndarray, present: np.ndarray) -> np.ndarray:
        """Each member's threshold-model evidence (M,) (-inf where it has none): the member's
        own :meth:`Validity._threshold_evidence`, one member after another."""
        out = np.full(len(self.followers), -np.inf)
        for i, f in enumerate(self.followers):
            if present[i] and np.isfinite(f.threshold):
                out[i] = f._threshold_evidence(self._x[i, :f.dim].copy(), self._anchor[i, :f.dim],
                                               float(lead_ll[i]))
        return out

    def _conclude(self, top: np.ndarray, p: np.ndarray, progress: np.ndarray, g: np.ndarray,
                  gs: np.ndarray, frac: np.ndarray, mean_ll: np.ndarray, new: np.ndarray,
                  step_ll: np.ndarray, present: np.ndarray) -> list[FollowState]:
        """:meth:`ActionFollower._conclude` for every member at once; ``top`` (M,): each
        member's template of most evidence (group index)."""
        ev, refused, engaged, bounds = self._evidence, self._refused, self._engaged, self._bounds
        X, fw = self._x, self.forward
        gb = bounds + self._best
        switch = (ev[top] - ev[gb] > self._m_margin) | refused[gb]
        gb = np.where(switch, top, gb)
        self._best = bi = gb - bounds
        self._judge_shape(g, new)
        any_engaged = np.logical_or.reduceat(engaged, bounds)
        slope = self._dsource[gs[gb]]
        m0, m1, m2 = fw._mom[:, gb]
        var = np.maximum(m2 / m0 - (m1 / m0) ** 2, 0.0)
        variance = var * slope * slope
        spread2 = var / (self._lengths[gb] - 1.0) ** 2
        size = self._size[gb][:, None]
        last = self._rel[self._last_state[gb]] * self._m_units * size + self._anchor
        ok = (engaged[gb] & ~refused[gb] & self._covered[gb] & ~self._misshaped[gb]
              & (spread2 <= self._m_spread2) & (p[gb] * self._kept >= self._m_min_p)
              & ~(self._has_end & members.moved_on(X, self._end_x, last, self._m_radius)))
        # a new action drives only once its shape clearly leads (spotting)
        ok &= ~self._m_spots | (self._acquired == bi) | self._lead(gs, frac, gb,
                                                                   p * np.repeat(self._kept, self._counts))
        self._run = run = np.where(ok, self._run + 1, 0)
        valid = run >= self._m_confirm
        self._acquired = np.where(valid, bi, -1)
        loglik = mean_ll[gb]
        distance = np.sqrt(np.maximum(0.0, -2.0 * (loglik - self._m_lc) / self._m_zdim))
        members.push(self._buf, self._nbuf, X, present, self._m_keep)
        still = members.still(self._buf, self._nbuf, self._m_keep, self._m_radius)
        r = (X - self._anchor).take(self._owner, axis=0) / self._scale
        if self._any_scale:
            r /= np.where(self._scaled > 0, self._size, 1.0)[:, None]
        moving = np.maximum.reduceat(np.sqrt((r * r).sum(axis=1) / self._dims), bounds) >= self._m_onset
        show = any_engaged | (~still & moving)
        order = members.top_three(p, bounds, self._counts, self._index) if show.any() else None
        prog_b = progress[gb]
        holding = self._holds[self._state_off[gb] + np.rint(g[gb]).astype(np.intp)] | (prog_b >= 0.9)
        top3 = order.tolist() if order is not None else None
        sizes = self._size.copy()   # the states' maps are views of this tick's arrays
        out: list[FollowState] = []
        for i, (b, var_b, val, ll, dist, restarted, hold, sh, eng, end, here, pb) in enumerate(zip(
                bi.tolist(), variance.tolist(), valid.tolist(), loglik.tolist(), distance.tolist(),
                new[gb].tolist(), holding.tolist(), show.tolist(), any_engaged.tolist(),
                self._ended.tolist(), present.tolist(), prog_b.tolist())):
            if not here:
                out.append(None)  # type: ignore[arg-type]
                continue
            a, z = self._spans[i]
            names, index, prog = self._m_names[i], self.followers[i]._index, progress[a:z]
            likely: tuple[tuple[str, float, float], ...] = ()
            if sh:
                likely = tuple((names[j - a], float(p[j]), float(progress[j])) for j in top3[i]
                               if j >= 0 and not refused[j])
            shown, best, best_progress = prog, names[b], pb
            if end >= 0 and not eng:
                best, best_progress = names[end], 1.0
                shown = prog.copy()
                shown[end] = 1.0
            state = self.followers[i]._state = FollowState(
                best=best, progress=best_progress, variance=var_b, probabilities=ByName(index, p[a:z]),
                progress_by=ByName(index, shown), valid=val, loglik=ll, distance=dist,
                restarted=restarted, loglik_by=ByName(index, mean_ll[a:z]), likely=likely,
                scale_by=ByName(index, sizes[a:z]), holding=hold)
            out.append(state)
        self._ended = np.where(any_engaged & present, -1, self._ended)
        self._spot(valid, ok, any_engaged, still, gb, prog_b, step_ll[gb], present)
        return out
