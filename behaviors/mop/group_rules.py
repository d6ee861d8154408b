"""A follower group's gesture spotting and shape rules over all its members at once.

Mixin of :class:`~behaviors.mop.group.FollowerGroup`: :meth:`GestureSpotting._spot`,
:meth:`Validity._judge_shape` and :meth:`GestureSpotting._leads` of every member as array
operations over the group's templates (K,) and members (M,); the rules themselves are those of
:mod:`behaviors.mop.spotting` and :mod:`behaviors.mop.validity`.
"""

from __future__ import annotations

import numpy as np

from behaviors.mop import members
from behaviors.mop.spotting import LEAD, RIVAL_PROBABILITY, SHAPE_SPREAD


class GroupRules:
    """Spotting, path misfit and shape lead for every member of a follower group."""

    def _spot(self, valid: np.ndarray, ok: np.ndarray, engaged: np.ndarray, still: np.ndarray,
              gb: np.ndarray, progress: np.ndarray, step_ll: np.ndarray, present: np.ndarray) -> None:
        """:meth:`GestureSpotting._spot` for every member at once (members with invariance
        "none" do not spot)."""
        X, spots = self._x, self._m_spots & present
        ending = spots & valid & (progress >= self._m_end) & ~self._has_end
        self._end_x[ending] = X[ending]
        self._has_end |= ending
        step_d2 = (self._m_lc - step_ll) * (2.0 / self._m_zdim)
        all_refused = np.logical_and.reduceat(self._refused, self._bounds)
        self._lost = np.where(spots, np.where(all_refused, self._lost + 1, 0), self._lost)
        spread = self._scale[gb] * self._size[gb][:, None]
        gone = members.departed(X, self._end_x, spread, self._m_dim, self._m_depart2)
        after_end, resting, abandon, waiting = members.spot(
            self._has_end, still, step_d2, self._m_null2, ok, gone, valid, progress, self._lost,
            self._m_lost_after, engaged)
        restart = spots & (after_end | resting | abandon | waiting)
        if not restart.any():
            return
        rows = np.flatnonzero(restart)
        anchor = X.copy()
        anchor[after_end] = self._end_x[after_end]
        anchor[waiting] = members.recent_mean(self._buf, self._nbuf, self._m_keep)[waiting]
        fresh = restart & ~waiting
        self._buf[fresh, -1] = X[fresh]
        self._nbuf[fresh] = 1
        self._ended[after_end | resting] = (gb - self._bounds)[after_end | resting]
        # _restart_here: every template of these members at its first state, no evidence
        cols = np.flatnonzero(np.isin(self._owner, rows))
        self.forward.reset_templates(cols)
        for n in ("_evidence", "_recent", "_recent_weight", "_refused", "_engaged", "_num", "_den",
                  "_misfit", "_misfit_w", "_misshaped", "_covered", "_shape"):
            getattr(self, n)[cols] = 0
        self._acquired[rows] = -1
        self._size[cols] = 1.0
        for r in rows:   # the threshold model starts afresh with the evidence
            self.followers[r]._threshold_ev, self.followers[r]._threshold_x = 0.0, None
        for a in (self._best, self._run, self._lost):
            a[rows] = 0
        self._has_end[rows] = False
        self._anchor[rows] = anchor[rows]

    def _judge_shape(self, g: np.ndarray, new: np.ndarray) -> None:
        """:meth:`Validity._judge_shape` for every member at once: each template's path misfit
        (kept as sums read at the current size, with hysteresis) and coverage; ``g``: followed
        states (each member's bank index)."""
        if np.count_nonzero(new):
            for n in ("_misfit", "_misfit_w", "_misshaped", "_covered"):
                getattr(self, n)[new] = 0
        own, off = self._owner, self._state_off
        u = self._x.take(own, axis=0)
        u -= np.where(self._k_none[:, None], self._k_center, self._anchor.take(own, axis=0))
        u /= self._scale
        u += self._k_ufirst
        size = np.where(self._scaled > 0, self._size, 1.0)
        gi = np.floor(g).astype(np.intp)
        ends = self._starts_local + self._lengths - 1
        c = self._k_c
        v = members.nearest_on_path(u / size[:, None] + c, self._path, gi, self._starts_local, ends, off)
        v -= c
        sums, w = self._misfit, self._misfit_w
        sums *= self._misfit_decay[:, None]
        sums[:, 0] += (u * u).sum(axis=1)
        sums[:, 1] += (u * v).sum(axis=1)
        sums[:, 2] += (v * v).sum(axis=1)
        w *= self._misfit_decay
        w += 1.0
        m2 = (sums[:, 0] / size ** 2 - 2.0 * sums[:, 1] / size + sums[:, 2]) / w
        m2 *= 1.0 / self._path_scale
        self._misshaped |= m2 > self._shape2
        self._misshaped &= ~(m2 < self._shape_accept2)
        nxt = np.minimum(gi + 1, ends) + off
        at = gi + off
        covered = self._arc[at] + (g - gi) * (self._arc[nxt] - self._arc[at])
        self._covered |= (covered >= self._arc_need) & self._engaged

    def _lead(self, gs: np.ndarray, frac: np.ndarray, gb: np.ndarray, p: np.ndarray) -> np.ndarray:
        """:meth:`GestureSpotting._leads` for every member at once (members with invariance
        "none" neither sum nor need a lead): each template's squared distance in units between
        the input and its followed state at its size, from the anchor, summed since the gesture
        began; per member, whether ``gb`` leads every likely rival by :data:`LEAD` nats."""
        own = self._owner
        q = self._rel.take(gs, axis=0)
        q += frac[:, None] * self._drel.take(gs, axis=0)
        d = (self._x - self._anchor).take(own, axis=0)
        d -= self._size[:, None] * q * self._m_units.take(own, axis=0)
        d /= self._k_radius
        self._shape += np.einsum("kd,kd->k", d, d) * self._k_spots
        rivals = ~self._refused & (p >= RIVAL_PROBABILITY)
        return members.leads(self._shape, rivals, gb, self._bounds, LEAD * 2.0 * SHAPE_SPREAD ** 2)
