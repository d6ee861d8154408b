"""A follower group's gesture spotting over all its members at once.

Mixin of :class:`~behaviors.mop.group.FollowerGroup`: :meth:`GestureSpotting._spot` of every
member as array operations over the group's templates (K,) and members (M,); the rules
themselves are those of :mod:`behaviors.mop.spotting` (the per-template shape rules are in
:mod:`behaviors.mop.group_kernel`).
"""

from __future__ import annotations

import numpy as np

from behaviors.mop import members


class GroupRules:
    """Gesture spotting for every member of a follower group."""

    def _spot(self, valid: np.ndarray, ok: np.ndarray, engaged: np.ndarray, still: np.ndarray,
              gb: np.ndarray, progress: np.ndarray, step_ll: np.ndarray, present: np.ndarray) -> None:
        """:meth:`GestureSpotting._spot` for every member at once (members with invariance
        "none" do not spot)."""
        X, spots = self._x, self._m_spots & present
        ending = spots & valid & (progress >= self._m_end) & ~self._has_end
        self._end_x[ending] = X[ending]
        self._has_end |= ending
        step_d2 = (self._m_lc - step_ll) * (2.0 / self._m_zdim)
        all_refused = self._m_all_refused
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
        for a in (self._best, self._run, self._lost):
            a[rows] = 0
        self._has_end[rows] = False
        self._anchor[rows] = anchor[rows]
