"""What a generation step perceives and shows, in Python (:class:`step.GenerationStep` inherits
it; the compiled step, step_kernel, repeats it): the main's standing and stopped states read
from its last positions, the new look at a limited turn rate (look.py), and the new sample
pair's features (paper section 4.2) pushed into the search windows. Units: seconds, table
metres, radians.
"""

from __future__ import annotations

import math

from behaviors.puppet_master import features as ft
from behaviors.puppet_master.behavior import STILL_MPS, STILL_SPAN_S, TOUCH_M
from behaviors.puppet_master.generation import limit_turn
from behaviors.puppet_master.look import HEADING_MIN_SPEED, desired_look
from tabletop.frames import wrap_angle


class StepSenses:
    """The main's states, the look and the features of :class:`engine.Reactor`'s step (its
    state: see Reactor.start)."""

    def _look(self, texture: tuple, sx: float, sy: float, heading: float, mx: float,
              my: float, md: float, rx: float, ry: float) -> float:
        """The new look (radians) of the reactor stepped to (rx, ry) by (sx, sy)."""
        p = self.behavior.params
        look = self.pose[2]
        _, frame, angle, still_frame, still_angle, look_detail = texture
        # the look: its frame and smooth angle from the patch's source (continuous within a
        # patch, like the texture), plus the demonstrated look texture
        moving = math.hypot(sx, sy) * p.rate_hz >= HEADING_MIN_SPEED
        desired = desired_look(frame, angle, still_frame, still_angle, moving, heading, md,
                               math.atan2(my - ry, mx - rx))
        lg = self.look_governor
        desired += lg.detail_gain * look_detail
        turned = limit_turn(look, look + lg.alpha * wrap_angle(desired - look), self.max_turn)
        lg.observe_look(wrap_angle(turned - look))
        return turned

    def _main_stands(self, mx: float, my: float) -> bool:
        """Whether the main at (mx, my) is within the still distance (STILL_MPS over
        STILL_SPAN_S, metres) of the oldest of its last positions (``_main_recent``)."""
        ox, oy = self._main_recent[0]
        return math.hypot(mx - ox, my - oy) < STILL_MPS * STILL_SPAN_S

    def _main_stopped(self, mx: float, my: float) -> bool:
        """Whether the main at (mx, my) is within STILL_MPS x the stop span (metres) of each of
        its last Behavior.stop_span positions before it (behavior.STOP_SPAN_S)."""
        r, k = self._main_recent, min(self.behavior.stop_span, len(self._main_recent) - 1)
        d = STILL_MPS * k / self.behavior.params.rate_hz
        return k >= 1 and all(math.hypot(mx - r[-1 - j][0], my - r[-1 - j][1]) < d
                              for j in range(1, k + 1))

    def _features(self, target: int, mx: float, my: float, md: float, rx: float, ry: float,
                  look: float) -> None:
        """The new sample pair's features (section 4.2) into the search windows."""
        b = self.behavior
        vm, _, _ = self.main_motion.step(mx, my)
        vr, move_r, ddir_r = self.react_motion.step(rx, ry)
        fwd, left, rel_look = ft.relative_pose(mx, my, md, rx, ry, look)
        ft.situation_row(self._xs, b.scales, vm, vr, fwd, left, rel_look)
        still = self._main_stands(mx, my)
        ft.still_row(self._xs, b.scales, still, ft.SITUATION_DIMS)
        if b.scales.since > 0.0:    # the steps since the last push (features.since_step)
            self._since = ft.since_step(self._since, math.hypot(fwd, left), TOUCH_M,
                                        b.since_clip)
            ft.since_row(self._xs, b.scales, self._since, ft.since_column(b.scales))
        ft.room_row(self._xs, b.scales, mx, my, rx, ry, self.table)
        self.situation.push(self._xs)
        ft.coherence_row(self._xc, b.scales, wrap_angle(look - move_r), ddir_r, fwd, left, vr,
                         vm)
        ft.still_row(self._xc, b.scales, still, ft.COHERENCE_DIMS)
        ft.since_row(self._xc, b.scales, self._since,
                     ft.since_column(b.scales, ft.COHERENCE_DIMS))
        self.coherence.push(self._xc, target)
