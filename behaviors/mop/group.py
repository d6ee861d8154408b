"""Several followers stepped as one (one per performer), in one vectorised forward pass."""

from __future__ import annotations

from typing import Sequence

import numpy as np

from behaviors.mop.follower import ActionFollower, FollowState, SampleError
from behaviors.mop.forward import WindowedForward
from behaviors.mop.hmm import TemplateBank, TemplateError


class FollowerGroup:
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
        self.reset()

    def _share_state(self) -> None:
        """Every member's per-template state becomes a view of one array over the whole group,
        and its constants are stacked, so a tick updates all of them in a few array operations."""
        fs, sl = self.followers, self._slices
        per = lambda fn: np.concatenate([np.broadcast_to(fn(f), (len(f.names),)) for f in fs])
        for name in ("_evidence", "_recent", "_recent_weight", "_refused", "_engaged", "_entries",
                     "_num", "_den", "_size"):
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

    def reset(self) -> None:
        """Forget every performance."""
        self.forward.reset()
        for f in self.followers:
            f.reset()

    def reset_member(self, i: int) -> None:
        """Forget the performance followed by member ``i`` only (its next performance starts
        afresh: every template at its first state, no evidence); the others go on."""
        sl = self._slices[i]
        self.forward.reset_templates(np.arange(sl.start, sl.stop))
        f = self.followers[i]
        entries = self.forward.entries[sl].copy()
        f.reset()
        f._entries[:] = entries

    def step(self, samples: Sequence[np.ndarray]) -> list[FollowState]:
        """One sample per follower, in order; returns each follower's state."""
        if len(samples) != len(self.followers):
            raise SampleError(f"{len(samples)} samples for a group of {len(self.followers)} followers")
        lost = []
        samples_ok: dict[int, np.ndarray] = {}
        for i, (f, x) in enumerate(zip(self.followers, samples)):
            x = f._sample(x)
            if x is None:
                lost.append(i)
            else:
                sl = self._slices[i]
                self._z[sl, :f._zdim] = f._inputs(x)
                samples_ok[i] = x
        fw = self.forward
        saved = None
        if lost:
            saved = fw.snapshot(np.flatnonzero(np.isin(self._owner, lost)))
        step_ll = fw.step(self._z)
        if saved is not None:
            fw.restore(saved)
        return self._finish(step_ll, samples_ok, lost)

    def _finish(self, step_ll: np.ndarray, samples: dict[int, np.ndarray],
                lost: list[int]) -> list[FollowState]:
        """:meth:`ActionFollower._finish` for every member at once: the per-template arrays in
        one pass over the group, then each member's best, state and spotting."""
        fw, sls = self.forward, self._slices
        kept = None
        names = ("_evidence", "_recent", "_recent_weight", "_refused", "_engaged", "_entries",
                 "_num", "_den", "_size")
        if lost:
            kept = [(i, [getattr(self, n)[sls[i]].copy() for n in names]) for i in lost]
        mean = fw.mean
        g = self._starts_local + np.minimum(mean, self._lengths - 1.0)
        gi = np.minimum(g.astype(np.intp), self._starts_local + self._lengths - 2)
        frac = g - gi
        gs = gi + self._state_off
        progress = self._source.take(gs)
        progress += frac * self._dsource.take(gs)
        if self._any_scale:
            q = self._rel.take(gs, axis=0)
            q += frac[:, None] * self._drel.take(gs, axis=0)
            r = self._r
            for i, x in samples.items():
                f = self.followers[i]
                r[sls[i], :f.dim] = (x - f._anchor) / f._units
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
        past = (mean >= self._onset_state) & ~refused
        starting = past & ~engaged
        if np.count_nonzero(starting):
            # ActionFollower._displacement of the last samples' mean, for all members at once
            who = [i for i in np.flatnonzero(np.logical_or.reduceat(starting, self._bounds)).tolist()
                   if i in samples]
            away = self._away
            for i in who:
                f = self.followers[i]
                away[sls[i], :f.dim] = np.mean(f._recent_x[-3:] + [samples[i]], axis=0) - f._anchor
            r = away / self._scale
            r /= self._size[:, None]
            far = np.sqrt(np.einsum("kd,kd->k", r, r) / self._dims) >= self._onset_sigma
            for i in who:
                past[sls[i]] &= far[sls[i]]
        engaged |= past
        top = np.maximum.reduceat(ev, self._bounds)
        p = np.exp(ev - np.repeat(top, self._counts))
        p /= np.repeat(np.add.reduceat(p, self._bounds), self._counts)
        lists = (progress.tolist(), p.tolist(), mean_ll.tolist(), self._size.tolist())
        if kept:
            for i, saved in kept:
                for n, a in zip(names, saved):
                    getattr(self, n)[sls[i]] = a
        out = []
        for i, (f, sl) in enumerate(zip(self.followers, sls)):
            if i not in samples:
                out.append(f._held())
                continue
            a, b = sl.start, sl.stop
            out.append(f._conclude(int(np.argmax(ev[sl])), p[sl], progress[sl], g[sl], gi[sl],
                                   mean_ll[sl], new[sl], step_ll[sl], fw, a, samples[i],
                                   tuple(v[a:b] for v in lists)))
        return out
