"""A follower group's new attempts (gesture spotting) over all its members at once.

Mixin of :class:`~behaviors.mop.group.FollowerGroup`: where :func:`members.conclude` chose that
a member's new attempt starts, :meth:`GestureSpotting._restart_here` for all of them at once;
the rules themselves are those of :mod:`behaviors.mop.spotting`.
"""

from __future__ import annotations

import numpy as np

from behaviors.mop import members


class GroupRules:
    """New attempts for the members of a follower group."""

    def _restart(self, how: np.ndarray, gb: np.ndarray) -> None:
        """:meth:`GestureSpotting._restart_here` for the members whose new attempt starts now
        (``how``: :data:`members.GOES_ON` and the rest per member, as :func:`members.conclude`
        chose; ``gb``: each member's best template, group index)."""
        X = self._x
        after_end, resting, waiting = how == members.AFTER_END, how == members.RESTING, how == members.WAITING
        restart = how != members.GOES_ON
        rows = np.flatnonzero(restart)
        anchor = X.copy()
        anchor[after_end] = self._end_x[after_end]
        anchor[waiting] = members.recent_mean(self._buf, self._nbuf, self._m_keep)[waiting]
        fresh = restart & ~waiting
        self._buf[fresh, -1] = X[fresh]
        self._nbuf[fresh] = 1
        self._ended[after_end | resting] = (gb - self._bounds)[after_end | resting]
        # every template of these members at its first state, no evidence
        cols = np.flatnonzero(np.isin(self._owner, rows))
        self.forward.reset_templates(cols)
        for n in ("_evidence", "_recent", "_recent_weight", "_refused", "_engaged", "_num", "_den",
                  "_misfit", "_misfit_w", "_misshaped", "_covered", "_shape", "_gone", "_least",
                  "_at_hold_end"):
            getattr(self, n)[cols] = 0
        self._acquired[rows] = -1
        self._drive_k[rows] = -1
        self._drive_moved[rows] = False
        self._turn_in[rows] = 0.0
        self._turn_has_ref[rows] = False
        self._turn_has_h[rows] = False
        self._size[cols] = 1.0
        self._judged[cols] = 1.0
        self._thr_ev[rows] = 0.0   # the threshold model starts afresh with the evidence
        self._thr_has_x[rows] = False
        for a in (self._run, self._lost, self._after_end):
            a[rows] = 0
        self._best[rows] = -1
        self._has_end[rows] = False
        self._peak[rows], self._peak_k[rows] = 0.0, -1
        self._anchor[rows] = anchor[rows]
