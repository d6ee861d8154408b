"""A figure standing near the table's edges kept on the table through an action.

Actions rise and travel (a jump's highest part 0.04 m, a punch's 0.06 m above the standing
figure's top at 0.3 m tall, view 90,15): near the edge they left the table. The drawing is
offset along the table's y (metres) by the clip's own need, looked up over the action's
generalised time and eased in ``EASE_S`` before the part that needs it and out after (the
action's postures at ``SAMPLES`` times, with the weights it started with, placed where it
started). A figure that stays inside is drawn exactly where it was (no offset).

Along x the target is kept inside (``engine._on_table``), but tracking control (equations 2-4)
swings the output past it near the table's ends: a spin kick recognised at generalised time 0.61
(view 30,20, at x 0.05) put the target's root 0.096 m away at once, the tracked root followed
over 0.3 s while the joints turning into the spinning posture reached 0.05 m beyond the clip's
own (physics changed it by at most 0.013 m): 0.072 m off the table. Near an end the drawing is
offset along x toward the needs of the tracked output predicted ``SIDE_LOOK`` ahead
(:class:`EdgeSide`). Refused: the target's x shift planned from the clip's postures and eased in
(the action starts with the leg already out: still 0.072 m off); an offset eased at
``EDGE_SPEED`` toward the output's need, the rest brought on at once (a part moved 75.5 mm in
one frame, 61.3 drawn in place); one moved at the even speed reaching the predicted needs (61.3
-> 65.5 mm).
"""

from __future__ import annotations

import numpy as np

from behaviors.touch_pose.samples import place
from behaviors.touch_pose.tracking import Tracker

#: How far inside the table's ends the target's drawn points are kept (m): the tracked output
#: lags and sways past the target by up to 0.02 m (0.019 m measured after three punches,
#: physics on).
TABLE_MARGIN = 0.02
#: How far (in figure heights) an action is planned to reach beyond the figure's drawn extent
#: when it starts: 1.5 times the farthest measured (spin kick from 0,15 near the bottom 0.078 m,
#: punch from 90,15 near the top 0.062 m, at 0.3 m tall). A figure farther from the table's top
#: and bottom is not planned (the action frame's CPU p99 at the centre 1.2 -> 2.2 ms planned).
EDGE_REACH = 0.4
#: Fastest the planned drawing offset moves (m/s; 5 mm a 30 fps frame): the plan from the clip
#: overshoots (a spin kick from 0,15 near the bottom planned 0.107 m, 0.01 needed), unlimited
#: its largest one-frame move of a drawn part was 62.3 mm, 56.5 with (52.3 drawn in place).
EDGE_SPEED = 0.15

#: Seconds over which the drawing offset is eased in before it is needed and out after.
EASE_S = 0.4
#: Generalised times at which an action's postures are looked at when it starts.
SAMPLES = 32
#: Of them planned per frame (about 0.1 ms CPU each), the nearest ahead first: a clip
#: (1.27 s and more, at most 1.6 times its pace) runs at most 0.05 of its generalised time a
#: frame; they cover 0.125.
PER_FRAME = 4


def smooth(x: np.ndarray | float) -> np.ndarray:
    """Smoothstep of ``x`` clipped to 0-1 (0 -> 0, 1 -> 1, flat at both ends)."""
    x = np.clip(x, 0.0, 1.0)
    return x * x * (3.0 - 2.0 * x)


def need(y: np.ndarray, height: float, margin: float) -> float:
    """Table-y offset (m) bringing drawn points ``y`` (m) ``margin`` inside a table ``height``
    deep; 0 when they lie inside or cannot fit."""
    lo, hi = float(y.min()), float(y.max())
    if hi - lo > height - 2.0 * margin:
        return 0.0
    if lo < margin:
        return margin - lo
    return height - margin - hi if hi > height - margin else 0.0


class EdgeLift:
    """The drawing offset (table y, m) of one character: planned when an action starts,
    eased out after it ends."""

    def __init__(self) -> None:
        self.clock: object | None = None        # the running action's clock it was planned for
        self.u = np.linspace(0.0, 1.0, SAMPLES)
        self.needs = np.zeros(SAMPLES)
        self.width_u = 1.0                      # EASE_S as generalised time
        self.seen = (0.0, 0.0)                  # generalised times the action ran through
        self.t0 = 0.0                           # seconds when it started
        self.moved: np.ndarray | None = None    # output's low/high y less the clip's at start
        self.lift = 0.0                         # the offset drawn now
        self.ended: tuple[float, float] | None = None   # (t, offset) when the action ended
        self.rest = 0.0                  # the need (m) of the posture the last action left
        self.rest_of: object | None = None   # that posture

    def plan(self, clock: object, duration: float, u: float, t: float) -> None:
        """Start planning the action ``clock`` runs, ``duration`` seconds long, started at
        generalised time ``u``, time ``t`` (s): its needs (m) at :attr:`u` are filled in
        ``PER_FRAME`` a frame (:meth:`next_samples`)."""
        self.clock, self.t0, self.moved = clock, t, None
        self.needs = np.full(SAMPLES, np.nan)
        self.width_u = EASE_S / max(duration, 1e-6)
        self.seen = (u, u)
        self.ended, self.rest, self.rest_of = None, 0.0, None

    def unplanned(self) -> bool:
        """Whether some of the action's needs are still to be planned."""
        return bool(np.isnan(self.needs).any())

    def next_samples(self, u: float, heading: int) -> np.ndarray:
        """The ``PER_FRAME`` unplanned samples to plan next: those ahead (the ``heading`` way)
        nearest ``u`` first, then those behind."""
        todo = np.flatnonzero(np.isnan(self.needs))
        behind = (self.u[todo] < u) if heading > 0 else (self.u[todo] > u)
        order = np.lexsort((np.abs(self.u[todo] - u), behind))
        return todo[order[:PER_FRAME]]

    def during(self, u: float, heading: int, t: float) -> float:
        """The eased offset at generalised time ``u`` running the ``heading`` way (+1 or -1):
        each sample's need, of the times run through or lying ahead, weighed down with its time
        distance (smoothstep over ``EASE_S``), the largest up and down taken. (Times behind the
        start left in: a spin kick started at 0.61 from 200,10 near the bottom was drawn
        0.05 m higher at once.)"""
        self.seen = (min(self.seen[0], u), max(self.seen[1], u))
        ahead = self.u > u if heading > 0 else self.u < u
        used = ahead | ((self.u >= self.seen[0]) & (self.u <= self.seen[1]))
        needs = np.where(used & ~np.isnan(self.needs), self.needs, 0.0)
        w = smooth(1.0 - np.abs(self.u - u) / self.width_u) * needs
        ease = float(smooth((t - self.t0) / EASE_S))
        return ease * float(w.max(initial=0.0) + w.min(initial=0.0))

    def after(self, t: float, rest: float) -> float:
        """The offset at time ``t`` (s) eased from where the last action left it to ``rest``
        (m), the need of the posture the action left where it rests. (Taken at once, a jump
        seen from 250,25 near the top moved every part 0.034 m in one frame as it ended.)"""
        if self.ended is None:
            self.ended = (t, self.lift)
        t0, lift = self.ended
        return float(lift + (rest - lift) * smooth((t - t0) / EASE_S))


#: Seconds of tracked output predicted ahead for the table-x offset (3 frames; about 0.3 ms CPU
#: a frame each). 0.2 and 0.15 s kept the same parts on with the same largest moves (61.3 mm
#: seen, 57.2 near the ends from 60,30 250,25 0,15), the action frame's CPU p99 near an end
#: 4.75 / 2.95 ms against 2.63 (2.14 without the offset).
SIDE_LOOK = 0.1
#: Fastest the table-x offset moves while a need comes (m/s; 30 mm a 30 fps frame). At 0.6 the
#: spin kick from 250,25 at x 0.04 fell behind the prediction and the rest brought on at once
#: moved a part 62.3 mm in one frame (57.2 drawn in place).
SIDE_SPEED = 0.9


class EdgeSide:
    """The drawing offset (table x, m) of one character near a table end: toward the needs of
    its tracked output predicted ahead during an action, back to 0 after it."""

    def __init__(self) -> None:
        self.clock: object | None = None        # the running action it predicts
        self.near = False                       # whether it started near a table end
        self.times: list[float] = []           # seconds of the predicted frames
        self.needs: list[float] = []           # their table-x needs (m)
        self.side = 0.0                         # the offset drawn now
        self.drawn: np.ndarray | None = None    # the points drawn last frame (m)
        self.peaks: list[float] = []            # predicted frames' largest move of a part (m)

    def ahead(self, t: float, dt: float, moves: np.ndarray) -> float:
        """The offset (m) ``dt`` seconds after ``t``, the drawn points moving ``moves`` (n, 2; m)
        this frame with the offset kept. Toward the largest need predicted ahead, at most
        ``SIDE_SPEED`` and at least what still reaches every need in time at that speed; of
        these steps the one nearest the need that keeps this frame's largest move of a part
        within the largest predicted ahead (the least otherwise). With no need ahead, back
        toward 0 at ``EDGE_SPEED``, no farther than the needs ahead. (Predicted needs are kept
        0 m inside: 0.005 m kept the largest move at 61.3 mm, 4 cases of 96 worse by up to
        0.7 mm, 0.01 m raised it to 65.1.)"""
        o, times = self.side, np.array(self.times)
        ahead = times > t + 1e-6
        n, lead = np.array(self.needs)[ahead], times[ahead] - t
        sign = 1.0 if o > 0.0 or n.max(initial=0.0) > -n.min(initial=0.0) else -1.0
        o, n = sign * o, np.maximum(sign * n, 0.0)
        rate = float(((n - o) / lead).max(initial=0.0))
        if rate <= 0.0:
            return sign * max(o - EDGE_SPEED * dt, float(n.max(initial=0.0)), 0.0)
        lo = max(float((n - o - (lead - dt) * SIDE_SPEED).max(initial=0.0)), 0.0)
        hi = max(lo, SIDE_SPEED * dt)
        steps = np.append(np.linspace(lo, hi, 9), min(max(float(n.max()) - o, lo), hi))
        moved = np.linalg.norm(moves[None] + np.outer(sign * steps, [1.0, 0.0])[:, None], axis=2)
        worst = moved.max(axis=1)
        budget = max(float(np.linalg.norm(moves, axis=1).max()),
                     float(np.array(self.peaks)[ahead].max(initial=0.0)))
        fine = worst <= max(budget, worst.min()) + 1e-9
        pick = np.flatnonzero(fine)[np.argmin(np.abs(steps[fine] - steps[-1]))]
        return sign * (o + float(steps[pick]))


class EdgeOffset:
    """The drawing offset of :class:`behaviors.touch_pose.engine.TouchPose` (mixed in)."""

    def _edge_lift(self, t: float, dt: float) -> float:
        """The drawing's table-y offset (m) at time ``t``: the running action's plan (made
        at its first frame), eased out after it; any part still beyond the table's y extent
        (tracking lag, physical sway) brought onto it."""
        edge = self.edge
        if self.mode == "action" and self.clock is not None:
            if edge.clock is not self.clock:
                edge.plan(self.clock, self.clock.action.duration, self.clock.u, t)
                y = self.camera.table(self._points(self.output))[:, 1]
                reach = EDGE_REACH * self.scale * self.stand_height
                if y.min() > reach and y.max() < self.table[1] - reach:
                    edge.needs[:] = 0.0     # no action reaches an edge from here: none planned
            if edge.unplanned():
                self._clip_needs()
            lift = edge.during(self.clock.u, self.clock.heading, t)
        else:
            if edge.lift == 0.0 and not self._rest_need():
                return 0.0
            lift = edge.after(t, self._rest_need())
        step = EDGE_SPEED * dt
        lift = edge.lift + min(max(lift - edge.lift, -step), step)
        return lift + need(self.camera.table(self._points(self.output))[:, 1] + lift,
                           self.table[1], 0.0)

    def _rest_need(self) -> float:
        """The drawing offset (m, table y) the posture left by the last action needs where it
        rests (a punch seen from 90,15 travels in depth: it ends 0.03 m higher on the table),
        kept after the handover until the next action."""
        if self.handover is not None and self.edge.rest_of is not self.handover.at_base:
            y = self.camera.table(self.body.points(self.handover.at_base))[:, 1]
            self.edge.rest_of = self.handover.at_base
            self.edge.rest = need(y, self.table[1], TABLE_MARGIN)
        return self.edge.rest

    def _clip_needs(self) -> None:
        """Plan ``edge.PER_FRAME`` more of the running action's drawing offsets (m, table y) at
        ``edge.SAMPLES`` times, the nearest ahead first (all at its first frame: the action
        frame's CPU p99 1.2 -> 4.8 ms): its postures with the weights of its first synthesis,
        placed where it started, their lowest and highest drawn points moved by the output's
        own against the clip's at the time it started (the clip alone: a spin kick from 30,20
        near the top was drawn 0.09 m too low)."""
        a, edge = self.clock.action, self.edge
        last = self.action_blend[1] if self.action_blend and self.action_blend[0] is a else None
        base, yaw = self.action_base

        def extent(u: float) -> np.ndarray:
            pose = place(a.model.at_time(last, u).pose, base, yaw)
            y = self.camera.table(self.body.points(pose))[:, 1]
            return np.array([y.min(), y.max()])

        if edge.moved is None:
            now = self.camera.table(self._points(self.output))[:, 1]
            edge.moved = np.array([now.min(), now.max()]) - extent(self.clock.u)
        for k in edge.next_samples(self.clock.u, self.clock.heading):
            edge.needs[k] = need(extent(edge.u[k]) + edge.moved, self.table[1], TABLE_MARGIN)

    def _edge_side(self, t: float, dt: float) -> float:
        """The drawing's table-x offset (m) at ``t``: toward the running action's predicted
        needs (:meth:`EdgeSide.ahead`; predicted only for a figure within ``EDGE_REACH``
        figure heights of an end when the action starts), back to 0 after it; any part still
        beyond the table's x extent (a drag in posing, the prediction short) brought on.
        (Predicted in posing too, toward its target held: a bow from 60,30 at x 1.16 moved a
        part 22.6 mm in a frame, 26.0 without, but a wave from 200,10 at 0.05 24.3, 18.6.)"""
        side = self.side
        acting = self.mode == "action" and self.clock is not None
        if not acting:
            side.clock, side.near, side.times, side.needs, side.peaks = None, False, [], [], []
        xy = self.camera.table(self._points(self.output))
        x = xy[:, 0]
        if acting and side.clock is not self.clock:
            reach = EDGE_REACH * self.scale * self.stand_height
            side.clock, side.near = self.clock, bool(x.min() < reach
                                                     or x.max() > self.table[0] - reach)
        if acting:
            self._predict_side(t, xy)
        drawn = xy + np.array([side.side, self.edge.lift])
        moves = drawn - (drawn if side.drawn is None else side.drawn)
        off = side.ahead(t - dt, dt, moves)
        off += need(x + off, self.table[0], 0.0)
        side.drawn = xy + np.array([off, self.edge.lift])
        return off

    def _predict_side(self, t: float, xy: np.ndarray) -> None:
        """The next ``SIDE_LOOK`` seconds of tracked output (equations 2-4, from the tracker's
        state now) toward the action's postures ahead at its recording's pace, with the weights
        of its last synthesis, placed where it started and kept on the table (``_on_table``):
        their table-x needs and largest moves of a part."""
        side, clock = self.side, self.clock
        if not side.near:
            return
        a = clock.action
        last = self.action_blend[1] if self.action_blend and self.action_blend[0] is a else None
        base, yaw = self.action_base
        tr, frame, u = self.tracker, 1.0 / 30.0, clock.u
        sim = Tracker(tr.pose, tr.k, tr.d)
        sim.omega, sim.vel = tr.omega.copy(), tr.vel.copy()
        side.times, side.needs, side.peaks = [t], [need(xy[:, 0], self.table[0], 0.0)], [0.0]
        for k in range(1, round(SIDE_LOOK / frame) + 1):
            u = min(max(u + clock.heading * frame / a.duration, 0.0), 1.0)
            target = self._on_table(place(a.model.at_time(last, u).pose, base, yaw))
            nxt = self.camera.table(self.body.points(sim.step(target, frame)))
            side.peaks.append(float(np.linalg.norm(nxt - xy, axis=1).max()))
            side.times.append(t + k * frame)
            side.needs.append(need(nxt[:, 0], self.table[0], 0.0))
            xy = nxt
