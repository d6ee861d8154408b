"""The pose a :class:`engine.Reactor` shows between its generation steps (:class:`ShownPose`,
which Reactor inherits): back along the latest step, kept on the table and apart from the
other characters, and among them slid at most the largest step's pace. Units: seconds, table
metres, radians.
"""

from __future__ import annotations

import math

import numpy as np

from behaviors.puppet_master import step_kernel as sk
from behaviors.puppet_master.apart import keep_apart
from behaviors.puppet_master.table_boundary import clamp_to_table


class ShownPose:
    """The shown pose of :class:`engine.Reactor` (its state: see Reactor.start)."""

    def shown_at(self, t: float, rows: np.ndarray | None = None) -> tuple[float, float, float]:
        """The pose shown at ``t`` after the steps due (update); ``rows``: the obstacles as
        rows (_obstacle_array), made here where None and compiled."""
        if rows is None and self.compiled:
            rows = self._obstacle_array()
        x, y, d = self.pose
        lag = t - self.t
        if self._shown is not None and (self.obstacles or self._lagging):
            return (*self._slid(x, y, t, lag, rows), d)
        if lag < self.dt and self._last_step != (0.0, 0.0):
            # back along the latest step (f in [-1, 0)): the step kept apart from the
            # obstacles; the way between must too (among obstacles: _slid)
            f = max(lag, 0.0) / self.dt - 1.0
            if rows is not None:
                x, y = sk.moved_on(x, y, *self._last_step, f, rows, self._cs)
            else:
                x, y = clamp_to_table(x + self._last_step[0] * f, y + self._last_step[1] * f,
                                      self.table)
                if self.obstacles:
                    x, y = keep_apart(x, y, self.obstacles, self.table)
        self._shown = (x, y, t)
        return x, y, d

    def _slid(self, x: float, y: float, t: float, lag: float,
              rows: np.ndarray | None) -> tuple[float, float]:
        """The shown position at ``t`` among other characters: from the last shown one toward
        the way between the last two steps (x, y: the latest step's), moved at most the
        largest step's pace (Behavior.largest_step per 1/rate) and kept apart from the
        obstacles within it.

        Pushed out of the obstacles afresh from the way between the steps, the shown pose
        went round a body one way while the step went the other, then jumped across: three
        reactors of one main (0.08 m bodies, each kept apart from the others' latest shown
        poses; unseen closed-loop scenes, 0.6 x 0.4 to 3.0 x 0.5 m, 30-60 Hz, five
        characters x 36 seeds), the largest one-frame move over that pace, seeds 12-47 /
        48-83 / 84-119: 10.8 / 15.6 / 10.4 (two: 2.9 / 1.6 / 2.0), moved so (with
        apart.no_deeper in the step) 1.0 on every set; least gap over the size 0.952 /
        0.943 / 0.138 -> 0.933 / 0.954 / 0.949 (two 0.851 / 0.856 / 0.767 -> 0.907 / 0.943 /
        0.953). With apart.no_deeper alone, three, seeds 84-119: 1.86, least 0.934. Its
        cost: the shown pose falls behind a step that goes round a body (more than two
        steps behind on 0.15% of the three afraid ones' frames, at most 9.6 steps; 0.05% /
        5.9 before). The main's disc kept here too: shares inside it 0.0613 -> 0.0131 (two,
        seeds 12-47), but least gaps 0.907 / 0.943 / 0.953 -> 0.854 / 0.915 / 0.870: not
        used (the shown pose hid from the main where its steps did not). Before the step went
        round the bodies, the push from the way between the steps capped at the largest step
        (three afraid ones, seeds 84-119: least gap 0.14 -> 0.46 but frames under 0.9 of the
        size 0.00003 -> 0.00024) or the step's own pose shown where the push exceeds it (0.11,
        0.00062) had not been used either."""
        if lag < self.dt and self._last_step != (0.0, 0.0):
            f = max(lag, 0.0) / self.dt - 1.0
            x, y = clamp_to_table(x + self._last_step[0] * f, y + self._last_step[1] * f,
                                  self.table)
        px, py, pt = self._shown
        pace = self.behavior.largest_step * max(t - pt, 0.0) / self.dt
        ax, ay, ux, uy = x, y, 0.0, 0.0
        m = math.hypot(x - px, y - py)
        if m > pace:
            ax, ay, ux, uy = px, py, (x - px) * pace / m, (y - py) * pace / m
        if rows is not None:
            sx, sy = sk.moved_on(ax, ay, ux, uy, 1.0, rows, self._cs)
        else:
            sx, sy = keep_apart(*clamp_to_table(ax + ux, ay + uy, self.table), self.obstacles,
                                self.table)
        m = math.hypot(sx - px, sy - py)
        if m > pace:                                  # the pace wins over the bodies
            sx, sy = px + (sx - px) * pace / m, py + (sy - py) * pace / m
        self._shown = (sx, sy, t)
        self._lagging = (sx, sy) != (x, y)
        return sx, sy
