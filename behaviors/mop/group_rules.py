"""A follower group's rules over all its members at once: new attempts (gesture spotting),
the input's turning and the tempo of a new action.

Mixin of :class:`~behaviors.mop.group.FollowerGroup`: where :func:`members.conclude` chose that
a member's new attempt starts, :meth:`GestureSpotting._restart_here` for all of them at once;
the rules themselves are those of :mod:`behaviors.mop.spotting`. Before it, each member's
turning (:mod:`behaviors.mop.turning`); the arrays of the tempo
(:func:`behaviors.mop.tempo.slow_take`), which :func:`members.conclude` applies first.
"""

from __future__ import annotations

import numpy as np

from behaviors.mop import (bends, member_spotting, member_validity, members, tempo, threshold,
                          under_way)
from behaviors.mop.group_layout import FLAGS, FLOATS
from behaviors.mop.turning import FIRST_TURN_STEPS, TURN_REACH

#: Per-template state a new attempt starts at 1: a template's size and judged share.
RESTART_ONE = ("_size", "_judged")
#: Per-template state a new attempt starts at 0: the rest of the kernel's state and the misfit
#: (GestureSpotting._restart_here), taken from the layout so no name of it can be left out.
RESTART_ZERO = tuple(n for n in FLOATS + FLAGS + ("_misfit", "_probe")
                     if n not in RESTART_ONE)


class GroupRules:
    """New attempts, turning and tempo for the members of a follower group."""

    def _turning_arrays(self) -> None:
        """Each member's turning constants and state (:meth:`Turning._turned`), as rows."""
        fs, m, dmax = self.followers, len(self.followers), self._rel.shape[1]
        self._m_turning = [i for i, f in enumerate(fs) if f._turn is not None]
        self._turning = np.array([f._turn is not None for f in fs], dtype=bool)
        self._turns = np.concatenate([f._turn if f._turn is not None
                                      else np.zeros(len(f.bank.means)) for f in fs])
        self._before_bend = np.concatenate([f._before_bend for f in fs])   # (bends.before_bends)
        self._bend_hidden = np.zeros(m, dtype=bool)   # (bends.unturned)
        self._straight = np.zeros(m, dtype=bool)   # (bends.unspared, at each state's progress)
        self._source = np.concatenate([f.bank.source for f in fs]).astype(float)
        self._waits = np.concatenate([f._waits for f in fs])   # (bends.waits)
        self._turn_steps = np.array([f._turn_step for f in fs], dtype=float)
        self._turn_limits = np.array([f.turn_limit for f in fs], dtype=float)
        self._turn_in, self._turn_h = np.zeros(m), np.zeros(m)
        self._turn_ref = np.zeros((m, dmax))
        self._turn_has_ref, self._turn_has_h = np.zeros(m, dtype=bool), np.zeros(m, dtype=bool)
        self._turn_ok = np.ones(m, dtype=bool)
        # each state from its template's first (raw units; bends.strays)
        self._stroke_path = np.ascontiguousarray(np.concatenate(
            [(f._rel * f._units)[:, :2] if f._turn is not None
             else np.zeros((len(f.bank.means), 2)) for f in fs]))

    def _tempo_arrays(self) -> None:
        """The last samples and followed states of members that spot
        (:meth:`Validity._slow_take`)."""
        fs, m, dmax = self.followers, len(self.followers), self._rel.shape[1]
        w = tempo.TEMPO_SAMPLES
        self._tempo_on = np.array([f.invariance != "none" for f in fs], dtype=bool)
        self._tempo_x, self._tempo_g = np.zeros((w, m, dmax)), np.zeros((w, len(self._owner)))
        self._tempo_s = np.ones((w, len(self._owner)))   # ... and the sizes (overrun.GROWN)
        self._tempo_at, self._tempo_n = np.zeros(m, dtype=np.intp), np.zeros(m, dtype=np.intp)
        self._overran_k = np.full(m, -1, dtype=np.intp)   # (overrun.overruns' held)
        self._crawl = np.zeros((m, 2), dtype=np.intp)   # tempo.crawls: run, best

    def _turned(self, present: np.ndarray) -> None:
        """Each present member's turning since its gesture began, and whether it fits its best
        template's near the followed state (:meth:`Turning._turned`), in ``_turn_ok``
        (compiled: :func:`member_validity.turned`)."""
        if self._m_turning:
            member_validity.turned(
                self._x, self._anchor, present, self._turning, self._turn_ref,
                self._turn_has_ref, self._turn_h, self._turn_has_h, self._turn_in, self._best,
                self._bounds, self._ti, self.forward.mean, self._turns, self._turn_steps,
                self._turn_limits, TURN_REACH, FIRST_TURN_STEPS, self._turn_ok,
                self._before_bend, bends.UNTURNED, self._bend_hidden, self._waits, self._source,
                bends.STRAIGHT_TO if bends.GROWN_STRAIGHT else -np.inf, self._straight,
                self._m_rest, bends.REST_BENT, bends.REST_UNTURNED, bends.REST_TURNED,
                self._stroke_path, self._size, self._taken, self._taken_n, self._stroke_bent,
                bends.STROKE_STRAIGHT, bends.STRAYS)

    def _restart(self, how: np.ndarray, gb: np.ndarray) -> None:
        """:meth:`GestureSpotting._restart_here` for the members whose new attempt starts now
        (``how``: :data:`member_spotting.GOES_ON` and the rest per member, as
        :func:`members.conclude` chose; ``gb``: each member's best template, group index).
        Member by member, its own templates a slice of the group's arrays: as masks and fancy
        indexing over the group (about 40 numpy calls) it took 0.31-0.32 ms thread time on the
        ticks where one starts, this way 0.095-0.098 ms (DESIGN's 8 x 100 templates, 20 of 900
        ticks, load 7-9)."""
        for i, h in enumerate(how.tolist()):
            if h == member_spotting.GOES_ON:
                continue
            if h == member_spotting.AFTER_END:
                # where the end was reached, or the ended template's last point at its size
                # while the input was still coming closer to it (GestureSpotting._spot)
                anchor = self._end_x[i].copy()
                last = self._end_last[i]
                if np.sum((self._x[i] - last) ** 2) < np.sum((anchor - last) ** 2):
                    anchor = last
                shift = anchor - self._end_near[i]   # (take_rule.TAKE_FROM_NEAREST)
            elif h == member_spotting.UNSEEN:
                anchor = self._unseen_x[i].copy()   # where it was followed to its end
            elif h == member_spotting.WAITING:
                anchor = members.recent_mean(self._buf[i:i + 1], self._nbuf[i:i + 1],
                                             self._m_keep[i:i + 1])[0]
            else:
                anchor = self._x[i].copy()
            # the input's way here (validity.unbegun): over the attempt abandoned, from its anchor
            came = self._x[i] - self._anchor[i]   # (set at the member's first sample)
            returned = h == member_spotting.AFTER_END and self._end_returned[i]
            if h != member_spotting.WAITING:
                self._buf[i, -1] = self._x[i]
                self._nbuf[i] = 1
            if h in (member_spotting.AFTER_END, member_spotting.RESTING, member_spotting.UNSEEN):
                self._ended[i] = gb[i] - self._bounds[i]
            # every template of this member at its first state, no evidence
            cols = self._slices[i]
            # the threshold model's lead over the templates, carried (Refusal._threshold_lead)
            # while its mirror chains hold CARRY_CHAINED of its weight (their sums: threshold_step)
            kk = len(self._owner)
            chained = (self._thr_tops[2 * kk + cols.start:2 * kk + cols.stop].sum()
                       / self._thr_total[i])
            lead = (max(0.0, float(self._thr_ev[i] - self._evidence[cols].max()))
                    if self._thr_has_x[i] and threshold.CARRY_LEAD
                    and chained >= threshold.CARRY_CHAINED else 0.0)
            self.forward.reset_templates(cols)
            for n in RESTART_ZERO:
                getattr(self, n)[cols] = 0
            for n in RESTART_ONE:
                getattr(self, n)[cols] = 1.0
            # begun under way (under_way.underway): read over the attempt abandoned, before
            # that is forgotten
            under = h == member_spotting.ABANDONED and under_way.underway(
                float(self._step_prev[i]), float(self._step_last[i]), float(self._walk[i]),
                int(self._walk_n[i]))
            self._forget_members(i)   # the threshold model starts afresh with the evidence,
            self._thr_ev[i] = lead      # ... but for its lead
            if h == member_spotting.ABANDONED:   # the input's way here (validity.unbegun)
                self._abandoned[i], self._came[i] = True, came
                self._underway[i] = under
            self._anchor[i] = anchor
            self._begun_at_return[i] = returned
            if h == member_spotting.AFTER_END:
                self._take_shift[i] = shift

    def _forget_members(self, rows: np.ndarray | int) -> None:
        """Members ``rows`` (bool, indices or one index) forget their own part of the evidence:
        best, runs, drive, end, turning and the threshold model (ActionFollower._forget, per
        member)."""
        for a in (self._run, self._lost, self._after_end):
            a[rows] = 0
        self._best[rows] = -1
        self._blocked[rows], self._blocked_k[rows] = 0, -1
        self._barred[rows], self._freed[rows] = -1, -1
        self._once[self._owner_of(rows)] = False
        self._acquired[rows] = -1
        self._drive_k[rows] = -1
        self._drive_moved[rows] = False
        self._abandoned[rows] = False
        self._abandon_rested[rows] = False
        self._begun_at_return[rows], self._end_returned[rows] = False, False
        self._walk[rows], self._walk_n[rows] = 0.0, 0
        self._step_prev[rows], self._step_last[rows] = 0.0, 0.0
        self._underway[rows], self._underway_rested[rows] = False, False
        self._has_end[rows] = False
        self._has_unseen[rows] = False
        self._peak[rows], self._peak_k[rows] = 0.0, -1
        self._end_history_n[rows] = 0
        self._lagged[rows] = False
        self._end_nearing[rows] = False
        self._take_shift[rows] = 0.0
        self._rev_age[rows] = -1
        self._shape_n[rows] = 0.0
        self._taken_n[rows] = 0
        self._stroke_bent[rows] = False
        self._thr_ev[rows] = 0.0
        self._thr_has_x[rows] = False
        self._turn_in[rows] = 0.0
        self._turn_has_ref[rows] = False
        self._turn_has_h[rows] = False
