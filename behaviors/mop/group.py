"""Several followers stepped as one (one per performer), in one vectorised forward pass.

A tick: the samples taken, the forward step, the per-template pass
(:func:`behaviors.mop.group_kernel.update_templates`), the per-member rules
(:func:`behaviors.mop.members.conclude`) and each member's state. The arrays it steps with (the
members' state shared as views, the constants as the compiled passes read them) are built in
:mod:`behaviors.mop.group_arrays`.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from behaviors.kernel_cache import load
from behaviors.mop import (group_kernel, group_steps, member_validity, members, shape_lead,
                          take_rule)
from behaviors.mop.follower import ActionFollower, FollowState, SampleError
from behaviors.mop.group_arrays import GroupArrays
from behaviors.mop.group_rules import GroupRules
from behaviors.mop.state import ByName
from behaviors.mop.forward import WindowedForward
from behaviors.mop.glitch import REACH_AHEAD, REACH_BACK, path_distances
from behaviors.mop.hmm import TemplateBank, TemplateError
from behaviors.mop.shape_lead import RIVAL_PROBABILITY, SHAPE_SPREAD
from behaviors.mop.group_layout import SHAPE_LAGS
from behaviors.mop.validity import PATH_REACH


class FollowerGroup(GroupArrays, GroupRules):
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
                raise TemplateError(f"follower {i} of the group has other parameters than "
                                    "follower 0; a group's followers must share sigma, window, "
                                    "transitions and limits")
        # the kernels a step calls, loaded now: not on the first step (behaviors.kernel_cache)
        load(group_steps.map_inputs, group_steps.take_samples, path_distances,
             group_kernel.update_templates, members.conclude, member_validity.turned)
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
        stay = np.concatenate([f.forward._stay for f in self.followers])
        # each member's states stretched as its own (behaviors.mop.stretch), padded as its means
        tangent = np.zeros((len(bank.means), width))
        row = 0
        for f in self.followers:
            t = f.forward._tangent
            tangent[row:row + len(t), :t.shape[1]] = t
            row += len(t)
        half = np.concatenate([f.forward._half / f.forward._prescale for f in self.followers])
        self.forward = WindowedForward(bank, sigma=p["sigma"], half_window=p["window"],
                                       transitions=first.forward.transitions, floor=p["floor"],
                                       dims=np.array(dims), stay=stay, stretch=(tangent, half))
        self._owner = np.array(owner, dtype=np.intp)
        bounds = np.concatenate([[0], np.cumsum([len(f.names) for f in self.followers])])
        self._slices = [slice(int(a), int(b)) for a, b in zip(bounds[:-1], bounds[1:])]
        self._z = np.zeros((len(owner), width))
        self._bounds = bounds[:-1].astype(np.intp)
        self._counts = np.diff(bounds).astype(np.intp)
        self._share_state()
        self._member_arrays()
        self._kernel_arrays()
        dmax = self._x.shape[1]   # glitches (ActionFollower._glitch): the members' limits
        self._jump = np.array([np.pad(f._jump, (0, dmax - f.dim), constant_values=np.inf)
                               for f in self.followers])
        self._jumped = np.zeros(len(self.followers), dtype=bool)
        self._off_dims = np.array([f.dim for f in self.followers], dtype=np.intp)
        self._off_limit2 = np.array([f._off_limit2 for f in self.followers])
        self._on_limit2 = np.array([f._on_limit2 for f in self.followers])
        self._near2 = np.zeros(len(self.followers))   # the samples' path distances (squared)
        self._off = np.zeros(len(self.followers), dtype=bool)   # each beyond OFF_PATH
        # the last sample followed beyond ON_PATH (ActionFollower._strayed)
        self._strayed = np.zeros(len(self.followers), dtype=bool)
        self.reset()

    def _clear_members(self, rows: np.ndarray) -> None:
        """Members ``rows`` (bool or indices) forget their performance (ActionFollower.reset)."""
        self._has_anchor[rows] = False
        self._jumped[rows] = False
        self._strayed[rows] = False
        self._nbuf[rows] = 0
        self._ended[rows] = -1
        self._forget_members(rows)
        self._tempo_n[rows] = 0
        self._overran_k[rows] = -1
        self._crawl[rows] = (0, -1)   # as ActionFollower.reset: no crawl, no best
        mine = self._owner_of(rows)
        self._shape[mine] = 0.0
        for n in SHAPE_LAGS:
            getattr(self, n)[mine] = 0.0
        self._drift[mine] = 0.0
        self._drift_run[mine] = 0.0
        self._gone[mine] = 0.0
        self._attempt_from[mine] = 0.0

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
            raise SampleError(f"{len(samples)} samples for a group of {len(self.followers)} "
                              "followers")
        X = self._x
        lost: list[int] = []
        stacked = None
        if self._one_dim:   # every member's samples alike: checked and copied at once
            try:   # (np.array then a cast when needed: asarray(dtype=float) of arrays costs 6x)
                stacked = np.array(samples)
                if stacked.dtype != np.float64:
                    stacked = stacked.astype(float)
            except (ValueError, TypeError):
                stacked = None
        fits = stacked is not None and stacked.shape == X.shape
        taken = 0   # (1: taken, each from the anchor it had, as _off_paths mapped them)
        if fits and not self._off_paths(stacked):
            taken = group_steps.take_samples(stacked, X, self._anchor, self._has_anchor,
                                             self._jump, self._jumped)
        if taken:
            present = self._everyone   # every sample finite, none a glitch, anchors taken
            np.greater(self._near2, self._on_limit2, out=self._strayed)
        else:   # a lost member (or a glitch) keeps its last sample
            if fits:
                present = np.isfinite(stacked.sum(axis=1))
                new = stacked
            else:
                new = X.copy()
                present = np.ones(len(self.followers), dtype=bool)
                for i, (f, x) in enumerate(zip(self.followers, samples)):
                    x = f._sample(x)
                    if x is None:
                        present[i] = False
                    else:
                        new[i, :f.dim] = x
                self._off_paths(new)
            present &= ~self._glitched(new, present)
            X[present] = new[present]
            lost = np.flatnonzero(~present).tolist()
            if not self._has_anchor.all():
                fresh = present & ~self._has_anchor
                self._anchor[fresh] = X[fresh]
                self._has_anchor |= present
        self._inputs(present, mapped=taken == 1)
        fw = self.forward
        saved = None
        if lost:
            saved = fw.snapshot(np.flatnonzero(self._owner_of(lost)))
            kept = [(n, getattr(self, n)[self._owner_of(lost)].copy())
                    for n in self._PER_TEMPLATE + self._GROUP_TEMPLATE]
            kept += [(n, getattr(self, n)[lost].copy()) for n in self._PER_MEMBER]
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

    def _glitched(self, new: np.ndarray, present: np.ndarray) -> np.ndarray:
        """:meth:`ActionFollower._glitch` of every member: which of the ``present`` members'
        samples ``new`` (M, D) are glitches to hold (counted in their followers' ``glitches``)."""
        rows = np.flatnonzero(present & self._has_anchor)
        far = (np.abs(new[rows] - self._x[rows]) > self._jump[rows]).any(axis=1)
        far |= self._off[rows] & ~self._strayed[rows]
        glitch = np.zeros(len(self.followers), dtype=bool)
        glitch[rows] = far & ~self._jumped[rows]
        self._jumped[present] = glitch[present]
        kept = present & ~glitch
        self._strayed[kept] = self._near2[kept] > self._on_limit2[kept]
        for i in np.flatnonzero(glitch).tolist():
            self.followers[i].glitches += 1
        return glitch

    def _off_paths(self, new: np.ndarray) -> bool:
        """:meth:`ActionFollower._path_distance2` of every member's sample ``new`` (M, D) into
        ``_near2``, beyond OFF_PATH into ``_off``; whether any is a glitch by it (not held the tick
        before, nor its last sample followed off every path: its samples then go one by one)."""
        group_steps.map_inputs(new, self._anchor, self._tc, self._mc, self._size, self._k_first,
                               self._bounds, self._counts, self._z)
        fw = self.forward
        return path_distances(self._z, fw.bank.means, fw.bank.starts, fw.bank.lengths, fw.mean,
                              self._evidence, self._refused, self._bounds, self._counts,
                              self._off_dims, self._best, self._near2, REACH_BACK, REACH_AHEAD,
                              self._off_limit2, self._off, self._jumped, self._strayed)

    def _owner_of(self, members: list[int] | np.ndarray | slice) -> np.ndarray:
        """Which templates (K,) belong to ``members`` (indices, a mask or a slice of the
        members; a mask over the templates: ``np.isin`` costs ~20x more)."""
        mine = np.zeros(len(self.followers), dtype=bool)
        mine[members] = True
        return mine[self._owner]

    def _inputs(self, present: np.ndarray, mapped: bool = False) -> None:
        """:meth:`PerformanceFrame._inputs` of every member into the forward's input (K, width);
        ``present`` (M,): the members with a sample; ``mapped``: :meth:`_off_paths` left them
        there already (the same samples, anchors and sizes)."""
        if not mapped:
            group_steps.map_inputs(self._x, self._anchor, self._tc, self._mc, self._size,
                                   self._k_first, self._bounds, self._counts, self._z)
        for i in self._m_tangent:   # direction of motion: the member's own lag
            if not present[i]:
                continue
            f, sl = self.followers[i], self._slices[i]
            f._anchor = self._anchor[i, :f.dim].copy()
            self._z[sl, :f._zdim] = f._inputs(self._x[i, :f.dim].copy())

    def _finish(self, step_ll: np.ndarray, present: np.ndarray) -> list[FollowState]:
        """:meth:`ActionFollower._finish` for every member at once: the per-template rules in
        one compiled pass over the group, then each member's validity, state and spotting."""
        fw, k = self.forward, len(self._owner)
        # fresh each tick: the states' maps are views of them
        self._k_out = k_out = np.empty((3, k))
        self._k_progress, self._k_mean_ll, self._k_p = k_out
        # shape_lead.LEAD read at each step, as the followers read it
        group_kernel.update_templates(
            self._states, self._ti, self._tc, self._mc, self._floats, self._flags, self._misfit,
            self._entries, fw.mean, fw.entries, step_ll, self._m_vectors, self._buf,
            self._m_ints, PATH_REACH[0], PATH_REACH[1], RIVAL_PROBABILITY,
            shape_lead.LEAD * 2.0 * SHAPE_SPREAD ** 2, k_out, self._k_new, self._m_top3,
            self._m_floats, self._m_bools, present, self._thr_means, self._thr_alpha,
            self._thr_scratch, self._thr_z, self._thr_lj, self._thr_tops, self._reversal_at,
            self._reversal_tol, self._probe, self._probe_floor2, self._k_rows, self._shared,
            self._tempo_x, self._tempo_g)
        states = self._conclude(step_ll, present)
        fw.seat(self._seat, self._seated)   # (views of their rows of the kernel's arrays)
        return states

    def _conclude(self, step_ll: np.ndarray, present: np.ndarray) -> list[FollowState]:
        """:meth:`ActionFollower._conclude` for every member at once, after the per-template
        pass (best already switched there): validity and spotting compiled
        (:func:`members.conclude`), then each member's state.

        The gesture's last samples and their fit to a new best (:meth:`TakeRule._fits_take`),
        the tempo, the way back and the abandonment's end are applied by :func:`members.conclude`
        (:mod:`~behaviors.mop.member_validity`), not from here. Measured against doing them
        here (the samples kept by fancy indexing over the members, the fit tried through each
        follower from Python, a call with its copies and checks for each member whose new best
        led, and the three others dispatched one by one, their 29 arguments unboxed again):
        DESIGN's tick after the view's two frames, interleaved in one process (blocks of 25,
        1500 ticks each, four runs at load 3-7, outputs equal on every field of every tick):
        median thread time 896 -> 839, 871 -> 813, 979 -> 897, 1177 -> 1041 us."""
        fw, m = self.forward, len(self.followers)
        p, mean_ll, restart = self._k_p, self._k_mean_ll, self._m_restart
        self._turned(present)
        f0 = self.followers[0]
        members.conclude(
            self._states, self._ti, fw.mean, fw._mom, self._floats, self._flags, self._k_out,
            step_ll, self._holds, self._scale, self._mk, self._m_vectors, present, self._m_floats,
            self._m_bools, self._m_ints, self._buf, self._extent, self._m_out, self._m_flags,
            self._shared, self._crawl, self._k_new, self._m_top3, self._m_likely,
            self._m_likely_v, self._lengths, self._tempo_x, self._tempo_g, self._tempo_s,
            f0.onset * f0.sigma,
            self._tc, self._mc, self._taken, take_rule.TAKE_MISFIT2, self._end_history)
        progress = self._k_progress
        gb = self._bounds + self._best
        sizes = self._size.copy()   # the states' maps are views of this tick's arrays
        names, index = self._k_names, self._m_index
        # the glue below reads per member from lists and scalars: as array operations over
        # the 8 members (mask, nonzero, fancy indexing) it cost more than the values it read
        # (with resting measured once: DESIGN's tick 1.98 -> 1.86 ms thread time, interleaved
        # in one process on a machine at load 15). The rows read in one call each, the ends
        # cleared in the same loop, the samples taken by one compiled call
        # (group_steps.take_samples) and the per-template state passed as two arrays: numpy
        # calls per tick 47.5 -> 37.5, the tick's Python part 0.35 -> 0.29 ms thread time
        # (interleaved in one process, load 10-12)
        likely: list[tuple] = [()] * m
        var_l, ll_l, dist_l, prog_l = self._m_out.tolist()   # (one call for the rows)
        valid_l, shows, hold_l, new_l = self._m_flags.tolist()
        if True in shows:   # each shown member's top three not refused (members.conclude)
            top, values = self._m_likely.tolist(), self._m_likely_v.tolist()
            for i in [i for i, s in enumerate(shows) if s]:
                likely[i] = tuple((names[j], pj, gj) for j, (pj, gj) in zip(top[i], values[i])
                                  if j >= 0)
        shown = [progress] * m
        best = [names[j] for j in gb.tolist()]
        here_l = present.tolist()
        ended = self._ended
        for i, (e, eng, here) in enumerate(zip(ended.tolist(), self._m_any_engaged.tolist(),
                                               here_l)):
            if e < 0:
                continue
            if eng:   # a new gesture has begun
                if here:
                    ended[i] = -1
                continue
            # the last gesture ended and no new one has begun: it stays at its end, not driving
            j = self._bounds[i] + e
            best[i], prog_l[i] = names[j], 1.0
            shown[i] = progress.copy()
            shown[i][j] = 1.0
        out: list[FollowState] = []
        for i, (here, b, pb, var_b, val, ll, dist, restarted, hold, ix, sh, lk) in enumerate(zip(
                here_l, best, prog_l, var_l, valid_l, ll_l, dist_l, new_l, hold_l,
                index, shown, likely)):
            if not here:
                out.append(None)  # type: ignore[arg-type]
                continue
            state = self.followers[i]._state = _new_state(
                b, pb, var_b, ByName(ix, p), ByName(ix, sh), val, ll, dist, restarted,
                ByName(ix, mean_ll), lk, ByName(ix, sizes), hold)
            out.append(state)
        if any(restart.tolist()):
            self._restart(restart, gb)
        return out


_new, _set = object.__new__, object.__setattr__


def _new_state(best: str, progress: float, variance: float, probabilities: ByName,
               progress_by: ByName, valid: bool, loglik: float, distance: float, restarted: bool,
               loglik_by: ByName, likely: tuple, scale_by: ByName, holding: bool) -> FollowState:
    """``FollowState(...)`` (every field, in order) built in a sixth of the time: the
    dataclass's own ``__init__`` sets each field through the frozen ``__setattr__`` (a tick of
    8 members spent ~40 us there); its fields given as one dictionary display (``dict(zip(
    fields, values))``, as before, took twice as long: 2.1 against 1.2 us a state)."""
    state = _new(FollowState)
    _set(state, "__dict__", {"best": best, "progress": progress, "variance": variance,
                             "probabilities": probabilities, "progress_by": progress_by,
                             "valid": valid, "loglik": loglik, "distance": distance,
                             "restarted": restarted, "loglik_by": loglik_by, "likely": likely,
                             "scale_by": scale_by, "holding": holding})
    return state
