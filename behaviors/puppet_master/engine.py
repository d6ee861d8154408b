"""Puppet Master engine: a trained :class:`Behavior` and live :class:`Reactor` instances.

Training lives in :mod:`behaviors.puppet_master.behavior` and its parameters in
:mod:`behaviors.puppet_master.params` (both re-exported here), the generation
step in :mod:`behaviors.puppet_master.step` (Python, the definition) and step_kernel (compiled);
the Reactor here is the live character around them: its start, the main's input resampled to
the generation rate, the steps due, the pose shown between steps (shown_pose.py). Paper
section 4.1 loop, once per generation step (1/rate seconds of main input)::

    e = BestMatch(I_t, R_t, I, R); newMovement = Generate(e); R.append(...); I.append(input)

The best match uses the windows of main and reactor up to the previous step (the paper: "new
user input is not used until the subsequent iteration"); the target relative position is then
placed in the main character's newest frame, which keeps the reaction as fresh as the input.

Everything is causal and incremental: a step uses only main samples at or before its grid time,
costs the same on the first and the millionth step, and the same past gives the same output to
the last digit (no randomness at all). Units: seconds, table metres, radians.
"""

from __future__ import annotations

import math
from collections import deque
from typing import Iterator

import numpy as np

from behaviors.kernel_cache import load
from behaviors.puppet_master import features as ft
from behaviors.puppet_master import match_step_kernel, search_kernel
from behaviors.puppet_master import step_kernel as sk
from behaviors.puppet_master.behavior import Behavior, DemonstrationError  # noqa: F401
from behaviors.puppet_master.character import (FOLLOW_SHARE, STILL_MPS, STILL_SPAN_S,
                                               still_span)
from behaviors.puppet_master.detail import DetailPatch, LookGovernor, TextureGovernor
from behaviors.puppet_master.generation import StepSmoother, capped, target_position
from behaviors.puppet_master.look import HEADING_MIN_SPEED
from behaviors.puppet_master.params import ParameterError, Params  # noqa: F401
from behaviors.puppet_master.resample import CausalResampler
from behaviors.puppet_master.apart import keep_apart
from behaviors.puppet_master.table_boundary import clamp_to_table
from behaviors.puppet_master.similarity import Balancer, CoherenceSearch, SituationSearch
from behaviors.puppet_master.shown_pose import ShownPose
from behaviors.puppet_master.step import GenerationStep
from tabletop.frames import wrap_angle

_NO_OBSTACLES = np.zeros((0, 3))
_POSE_AND_STEP = np.array([sk.RX, sk.RY, sk.LOOK, sk.STEP_X, sk.STEP_Y])


class Reactor(GenerationStep, ShownPose):
    """One live reacting character driven by a main character's poses.

    ``table``: (x0, y0, x1, y1) metres the reactor stays inside. ``max_backlog``: seconds of
    missed steps generated at once after an input gap; beyond that the grid skips ahead and
    the reactor waits where it was (None: generate every step, as ``tabletop behave`` does).

    ``compiled``: steps run as one compiled call (match_step_kernel.match_step: the searches
    and step_kernel.step, the same arithmetic as :meth:`_step` to the last bit); False runs
    :meth:`_step` itself, the readable definition (step.GenerationStep). (Measured: see
    step_kernel and match_step_kernel.)
    """

    compiled = True

    def __init__(self, behavior: Behavior, table: tuple[float, float, float, float],
                 max_backlog: float | None = 1.0) -> None:
        try:
            x0, y0, x1, y1 = (float(v) for v in table)
        except (TypeError, ValueError):
            raise ParameterError(f"table {table!r} must be four numbers x0, y0, x1, y1") from None
        if not all(math.isfinite(v) for v in (x0, y0, x1, y1)) or x1 <= x0 or y1 <= y0:
            raise ParameterError(f"table {table!r} must have x0 < x1 and y0 < y1 (metres)")
        self.behavior = behavior
        self.table = (x0, y0, x1, y1)
        # where a target is fitted (table_boundary.fit_target): the table less the demonstrated
        # character's edge margin (Behavior.edge_margin), at most a quarter of its smaller side
        m = min(behavior.edge_margin, 0.25 * min(x1 - x0, y1 - y0))
        self.target_table = (x0 + m, y0 + m, x1 - m, y1 - m)
        # the band along the edges that steps are turned off (table_boundary.turn_off_edges),
        # (x0 + m) - x0: the margin m as the fitted table holds it
        self.edge_band = self.target_table[0] - x0
        self.max_backlog = max_backlog
        p = behavior.params
        self.dt = 1.0 / p.rate_hz
        self.max_turn = behavior.turn_limit * self.dt
        self.situation = SituationSearch(behavior.situation_vectors, p.window, behavior.valid,
                                         behavior.situation_aug, p.half_life,
                                         behavior.situation_gate)
        self.coherence = CoherenceSearch(behavior.coherence_vectors, p.window, behavior.valid)
        if self.compiled:   # the kernels an update calls, loaded now: not on the first update
            load(sk.moved_on, search_kernel.situation_reset, *(
                (match_step_kernel.match_step,) if self._fusable() else (
                    sk.step, search_kernel.situation_push, search_kernel.coherence_push,
                    search_kernel.coherence_best)))
        self._xs = np.zeros(behavior.situation_vectors.shape[1])
        self._xc = np.zeros(behavior.coherence_vectors.shape[1])
        self.started = False
        self.t = math.nan
        self.pose = (math.nan, math.nan, math.nan)
        self.source = -1
        self.last_choice = "situation"
        # other characters to keep apart from: (x, y, least distance m), set by the caller
        self.obstacles: list[tuple[float, float, float]] = []
        self._obstacle_rows: np.ndarray | None = None   # as an array during update()
        self._rows = np.zeros((8, 3))   # the obstacles' rows (_obstacle_array), one spare first

    # -- life cycle ---------------------------------------------------------------------------

    def start(self, t: float, main_x: float, main_y: float, main_dir: float,
              at: tuple[float, float] | None = None) -> tuple[float, float, float]:
        """Start at time ``t``: the reactor takes the demonstration's first pose relative to its
        main, carried onto this main pose (kept on the table), or the place ``at`` (metres);
        both are taken to have been at rest for the last window. Returns the reactor pose."""
        b, p = self.behavior, self.behavior.params
        if not all(math.isfinite(v) for v in (t, main_x, main_y, main_dir)):
            raise ParameterError(f"reactor start pose ({t}, {main_x}, {main_y}, {main_dir}) "
                                 "is not finite")
        md = wrap_angle(main_dir)
        fwd, left, rel_look = b.start_pose
        rx, ry = clamp_to_table(*target_position(main_x, main_y, md, fwd, left), self.table)
        if at is not None:
            rx, ry = clamp_to_table(*at, self.table)
        elif self.obstacles:   # two reactors of one main would start on one spot
            rx, ry = keep_apart(rx, ry, self.obstacles, self.table)
        rd = wrap_angle(md + rel_look)
        self.resampler = CausalResampler(p.max_extrapolation)
        self.resampler.push(t, main_x, main_y, md)
        self.t0, self.i = t, 0
        self.t = t
        self.pose = (rx, ry, rd)
        self._last_step = (0.0, 0.0)
        self.main_motion = ft.EntityMotion(main_x, main_y, md, p.rate_hz, p.min_speed)
        self.react_motion = ft.EntityMotion(rx, ry, rd, p.rate_hz, p.min_speed)
        f, l, rl = ft.relative_pose(main_x, main_y, md, rx, ry, rd)
        ft.situation_row(self._xs, b.scales, 0.0, 0.0, f, l, rl)
        ft.still_row(self._xs, b.scales, True, ft.SITUATION_DIMS)
        self._since = 0.0               # steps since the last push: the start counts as one
        ft.since_row(self._xs, b.scales, self._since, ft.since_column(b.scales))
        ft.room_row(self._xs, b.scales, main_x, main_y, rx, ry, self.table)
        ft.coherence_row(self._xc, b.scales, 0.0, 0.0, f, l, 0.0, 0.0)
        ft.still_row(self._xc, b.scales, True, ft.COHERENCE_DIMS)
        ft.since_row(self._xc, b.scales, self._since,
                     ft.since_column(b.scales, ft.COHERENCE_DIMS))
        self.situation.reset(np.tile(self._xs, (p.window, 1)))
        self.coherence.reset(np.tile(self._xc, (p.window, 1)))
        self.balancer = Balancer(p.ratio, p.balance_gain, p.share_window)
        self.smoother = StepSmoother(p.smooth)
        self.governor = TextureGovernor(b.texture, p.rate_hz)
        self.look_governor = LookGovernor(b.look_change, p.rate_hz)
        self._ema = (0.0, 0.0)
        self._caps = (0.0, 0.0)         # the last two raw steps' caps (step.py)
        self._straight = b.straightness  # the share of the raw steps' length the smooth kept
        self.patch = DetailPatch(b.detail, p.patch)
        # the main's latest positions (still_span: STILL_SPAN_S x rate of them), to tell a main
        # that stands
        self._main_recent: deque[tuple[float, float]] = deque(
            maxlen=still_span(p.rate_hz))
        self._compiled_state(main_x, main_y, md)
        self.source = -1
        self._charge_end = -1
        self._shown: tuple[float, float, float] | None = None   # (x, y, t) last shown
        self._lagging = False           # that shown pose behind the way between the steps
        self._dart_end = -1
        self.started = True
        return self.pose

    def _compiled_state(self, main_x: float, main_y: float, md: float) -> None:
        """The state and constants of the compiled step (step_kernel indices), as start()
        left the objects the Python step uses."""
        b, p = self.behavior, self.behavior.params
        fs = self._fs = np.zeros(sk.FLOAT_STATE)
        fs[[sk.RX, sk.RY, sk.LOOK]] = self.pose
        fs[[sk.MAIN_X, sk.MAIN_Y, sk.MAIN_MOVE]] = main_x, main_y, md
        fs[[sk.REACT_X, sk.REACT_Y, sk.REACT_MOVE]] = self.pose
        gov, lg, bal = self.governor, self.look_governor, self.balancer
        fs[[sk.GOV_MS, sk.GOV_Z, sk.GOV_PREV]] = gov.ms, gov.z, gov.prev
        fs[[sk.LOOK_MS, sk.LOOK_Z]] = lg.ms, lg.z
        fs[[sk.LOG_K, sk.SHARE]] = bal.log_k, bal.share
        fs[sk.STRAIGHT] = self._straight
        fs[sk.SINCE] = self._since
        ints = self._is = np.zeros(sk.INT_STATE, dtype=np.int64)
        ints[sk.PATCH_START], ints[sk.PATCH_OFFSET] = self.patch.start, self.patch.offset
        ints[sk.SOURCE] = ints[sk.CHARGE_END] = ints[sk.DART_END] = -1
        c = self._cs = np.zeros(sk.CONSTANTS)
        c[[sk.X0, sk.Y0, sk.X1, sk.Y1]] = self.table
        c[sk.TARGET_TABLE:sk.TARGET_TABLE + 4] = self.target_table
        c[sk.EDGE_BAND] = self.edge_band
        c[[sk.DT, sk.RATE, sk.MIN_SPEED, sk.CATCH_UP, sk.GAIN]] = (
            self.dt, p.rate_hz, p.min_speed, p.catch_up, p.relative_motion)
        c[[sk.TOP_SPEED, sk.STILL_SPEED, sk.MAX_TURN]] = b.top_speed, b.still_speed, self.max_turn
        c[[sk.GOV_TARGET, sk.GOV_MIN_STEP, sk.GOV_GAIN, sk.GOV_DECAY, sk.GOV_Z_MIN,
           sk.GOV_Z_MAX]] = gov.target, gov.min_step, gov.gain, gov.decay, gov.z_min, gov.z_max
        c[[sk.LOOK_TARGET, sk.LOOK_GAIN, sk.LOOK_DECAY, sk.LOOK_Z_MIN, sk.LOOK_Z_MAX]] = (
            lg.target, lg.gain, lg.decay, lg.z_min, lg.z_max)
        c[[sk.TARGET_SHARE, sk.BALANCE_GAIN, sk.SHARE_WINDOW, sk.LOG_K_LIMIT]] = (
            bal.target_share, bal.gain, bal.window, bal.log_k_limit)
        s = b.scales
        c[[sk.S_V_MAIN, sk.S_V_REACT, sk.S_REL_POSITION, sk.S_REL_LOOK, sk.S_NORM_LOOK,
           sk.S_DDIR, sk.S_ROOM, sk.S_STILL]] = (s.v_main, s.v_react, s.rel_position,
                                                 s.rel_look, s.norm_look, s.ddir, s.room,
                                                 s.still)
        c[sk.ROOM_CLIP] = ft.ROOM_CLIP
        c[[sk.STILL_DISTANCE, sk.PATCH_LENGTH, sk.HEADING_MIN_SPEED, sk.FOLLOW_SHARE,
           sk.PERSONAL_SPACE, sk.KEEPS_PACE]] = (STILL_MPS * STILL_SPAN_S, p.patch,
                                                 HEADING_MIN_SPEED, FOLLOW_SHARE,
                                                 b.personal_space, float(b.keeps_pace))
        c[sk.WALKS_WITH_MAIN] = float(b.walks_with_main)
        c[sk.LARGEST_STEP] = b.largest_step
        c[sk.STRAIGHTNESS] = b.straightness
        c[sk.CIRCLING] = float(b.circling)
        c[sk.DARTS], c[sk.DART_SPAN] = float(b.darts), float(b.dart_span)
        c[sk.MAIN_DISC] = b.main_disc
        c[[sk.S_SINCE, sk.SINCE_CLIP, sk.TOUCH]] = b.scales.since, b.since_clip, b.live_touch
        span = min(b.stop_span, self._main_recent.maxlen - 1)    # as StepSenses._main_stopped
        c[[sk.STOP_SPAN, sk.STOP_DISTANCE]] = span, STILL_MPS * span / p.rate_hz
        self._smooth_x = np.zeros(p.smooth)
        self._smooth_y = np.zeros(p.smooth)
        self._recent = np.zeros((self._main_recent.maxlen, 2))
        self._space = np.array([[0.0, 0.0, b.main_disc]])
        c[sk.ROOM_REACH] = s.rel_position * ft.ROOM_NEAR
        self._fused = self._fusable()
        if self._fused:     # match_step's arguments but the obstacles and the main pose
            self.situation.best()       # the first best window looked for: match_step reads it
            self._packed = (fs, ints, c, b.step_table, b.bearings, self._smooth_x,
                            self._smooth_y, self._recent, self._xs, self._xc,
                            *self.situation.arrays(), *self.coherence.arrays())

    def _fusable(self) -> bool:
        """Whether the searches and the step run as one compiled call (match_step_kernel):
        the engine's own searches, the situation search's window ends one run (as training
        makes them) and its gate features.room_gate, if any."""
        gate = self.behavior.situation_gate
        return (type(self.situation) is SituationSearch
                and type(self.coherence) is CoherenceSearch and self.situation.run is not None
                and (gate is None or getattr(gate[1], "func", None) is ft.room_gate))

    def rebind(self, t: float, main_x: float, main_y: float, main_dir: float) -> None:
        """The main is another character from time ``t`` (one of several mains): its motion
        starts afresh here, so the jump between the two is not taken for a movement."""
        if not self.started:
            self.start(t, main_x, main_y, main_dir)
            return
        p = self.behavior.params
        self.resampler = CausalResampler(p.max_extrapolation)
        self.resampler.push(t, main_x, main_y, wrap_angle(main_dir))
        self.main_motion = ft.EntityMotion(main_x, main_y, wrap_angle(main_dir), p.rate_hz,
                                           p.min_speed)
        self._main_recent.clear()
        self._charge_end = self._dart_end = -1
        self._fs[[sk.MAIN_X, sk.MAIN_Y, sk.MAIN_MOVE]] = main_x, main_y, wrap_angle(main_dir)
        self._is[sk.RECENT_COUNT] = self._is[sk.RECENT_HEAD] = 0   # as the deque cleared
        self._is[sk.CHARGE_END] = self._is[sk.DART_END] = -1

    @property
    def coherence_share(self) -> float:
        """Running share (0..1) of coherence choices over the last few seconds."""
        if not self.started:
            return 0.0
        return float(self._fs[sk.SHARE]) if self.compiled else self.balancer.share

    @property
    def k(self) -> float:
        """Current balancing weight on the coherence cost."""
        if not self.started:
            return 1.0
        return math.exp(self._fs[sk.LOG_K]) if self.compiled else self.balancer.k

    def advance(self, t: float, main_x: float, main_y: float,
                main_dir: float) -> list[tuple[float, float, float, float]]:
        """Feed one main sample; returns the rows (t, x, y, dir) of every generation step now
        due (grid times <= t). The first call starts the reactor and returns its start row.
        A sample that is not finite or not later than the previous one is ignored."""
        return list(self.stepping(t, main_x, main_y, main_dir))

    def stepping(self, t: float, main_x: float, main_y: float,
                 main_dir: float) -> Iterator[tuple[float, float, float, float]]:
        """:meth:`advance` one step at a time: each row as its step is made (the reactors of
        a table stepped together move the ends apart between two, together.py)."""
        if not self.started:
            self.start(t, main_x, main_y, main_dir)
            yield (t, *self.pose)
            return
        isfinite = math.isfinite
        resampler = self.resampler
        if not (isfinite(t) and isfinite(main_x) and isfinite(main_y) and isfinite(main_dir)) \
                or t <= (resampler.last_time or -math.inf):
            return
        # plain floats from here on: numpy scalars (rows of a numpy array) carry the same
        # doubles but make every later operation of the step several times slower
        t, main_x, main_y, main_dir = float(t), float(main_x), float(main_y), float(main_dir)
        eps = 1e-9
        rate = self.behavior.params.rate_hz
        t0 = self.t0
        if self.max_backlog is not None:
            behind = t - (t0 + (self.i + 1) / rate)
            if behind > self.max_backlog:
                self.i = int(math.floor((t - self.max_backlog - t0) * rate))
        step = (self._step_fused if self._fused else self._step_compiled) if self.compiled \
            else self._step
        at = resampler.at
        while True:  # steps strictly before this sample: extrapolate from earlier samples
            g = t0 + (self.i + 1) / rate
            if g >= t - eps:
                break
            yield step(g, *at(g))
        resampler.push(t, main_x, main_y, main_dir)
        while True:
            g = t0 + (self.i + 1) / rate
            if g > t + eps:
                break
            yield step(g, *at(g))

    def update(self, t: float, main_x: float, main_y: float,
               main_dir: float) -> tuple[float, float, float]:
        """Feed one main sample and return the reactor pose at ``t``: between the last two
        steps' positions, at the share of a step's time since the latest (the latest step's
        look), so a display faster than the generation rate sees smooth motion, one step
        (1/rate) behind the generation; kept apart from the obstacles, as the step was, and
        among them moved from where it was last shown at most the largest step's pace (_slid).

        The latest step's pose moved on by that step's velocity (as it was) overshot wherever
        the next step turned: at 60 Hz on a scripted visitor's 40 s (bench-like, puck 1 of the
        synthetic camera) the displayed bully moved up to 0.036 m in a frame (its largest
        demonstrated step, in 1.5 frames' time, 0.026 m) and back, on 0.3% of frames more
        than that largest step (afraid 1.0%, lover and playful friend 0.08%); between the
        last two steps none does (per frame at most 0.013, 0.011, 0.0065, 0.013 m)."""
        if self.compiled:    # the obstacles as rows once per call, for steps and display
            self._obstacle_rows = self._obstacle_array()
        try:
            self.advance(t, main_x, main_y, main_dir)
        finally:
            rows, self._obstacle_rows = self._obstacle_rows, None
        return self.shown_at(t, rows)

    def shift(self, dx: float, dy: float) -> None:
        """The latest step's end moved by (dx, dy) metres, the step with it, cut to the
        largest step (Behavior.largest_step) from where it began; a push by another body, not
        the character's own motion (its next velocity starts from there). Counted as its own
        motion, two of one main beside a scripted visitor (60 s, 60 Hz) left their lone
        figures: the bully's speed while the main stands over moving 1.27 -> 0.83 (stepped in
        turn 1.01; so 1.19), the afraid one's orbit 0.42 -> 0.58 rad/s (in turn 0.49; so
        0.45)."""
        x, y, d = self.pose
        sx, sy = self._last_step
        bx, by = x - sx, y - sy
        sx, sy = capped(sx + dx, sy + dy, self.behavior.largest_step)
        x, y = clamp_to_table(bx + sx, by + sy, self.table)
        sx, sy = x - bx, y - by
        self.pose, self._last_step = (x, y, d), (sx, sy)
        self._fs[[sk.RX, sk.RY, sk.STEP_X, sk.STEP_Y]] = x, y, sx, sy
        self._fs[[sk.REACT_X, sk.REACT_Y]] = x, y
        self.react_motion.x, self.react_motion.y = x, y

    def _obstacle_array(self) -> np.ndarray:
        """The obstacles as rows (k, 3) (x, y, least distance m): a view of a buffer kept
        between calls, with a row spare before them for the main's personal space
        (_step_compiled). Made afresh (np.array of the list, then np.vstack with the personal
        space) they were two to three allocations a step and a call of the plugin's."""
        k = len(self.obstacles)
        if not k:
            return _NO_OBSTACLES
        if len(self._rows) <= k:
            self._rows = np.zeros((2 * k + 2, 3))
        rows = self._rows[1:k + 1]
        rows[:] = self.obstacles
        return rows

    # -- one generation step ------------------------------------------------------------------

    @property
    def last_choice(self) -> str:
        """What the latest step was generated from: "situation", "coherence", "charge" (a
        charge kept whole) or "dart" (a dart kept whole)."""
        if self._choice is None:        # a compiled step's, read from its state when asked
            ints = self._is
            return ("dart" if ints[sk.KEPT_DART] else "charge" if ints[sk.KEPT_CHARGE] else
                    "coherence" if ints[sk.USED_COHERENCE] else "situation")
        return self._choice

    @last_choice.setter
    def last_choice(self, choice: str) -> None:
        self._choice = choice

    def _obstacles(self, mx: float, my: float) -> np.ndarray:
        """The rows (k, 3) a compiled step keeps apart from: the main's disc first
        (Behavior.main_disc, at the main's position (mx, my)), then the obstacles."""
        rows = self._obstacle_rows
        if rows is None:
            rows = self._obstacle_array()
        disc = self.behavior.main_disc
        if disc <= 0.0:
            return rows
        if len(rows):           # the main's disc (Behavior.main_disc), then the others'
            obstacles = self._rows[:len(rows) + 1]
            obstacles[0] = mx, my, disc
            return obstacles
        obstacles = self._space     # the main's disc alone (see _step)
        obstacles[0, 0], obstacles[0, 1] = mx, my
        return obstacles

    def _step_fused(self, g: float, mx: float, my: float,
                    md: float) -> tuple[float, float, float, float]:
        """:meth:`_step` as one compiled call, the searches in it (match_step_kernel)."""
        self.source, rx, ry, look, sx, sy = match_step_kernel.match_step(
            *self._packed, self._obstacles(mx, my), mx, my, md)
        self._choice = None
        self.i += 1
        self.t = g
        self.pose = (rx, ry, look)
        self._last_step = (sx, sy)
        return g, rx, ry, look

    def _step_compiled(self, g: float, mx: float, my: float,
                       md: float) -> tuple[float, float, float, float]:
        """:meth:`_step` as four compiled calls (step_kernel.step, the searches around it),
        where match_step does not apply (Reactor._fused)."""
        js, cost_s = self.situation.best()
        jc, cost_c = self.coherence.best()
        b = self.behavior
        self.source = target = sk.step(
            self._fs, self._is, self._cs, b.step_table, b.bearings, self._smooth_x,
            self._smooth_y, self._recent, self._obstacles(mx, my), self._xs, self._xc, mx, my,
            md, js, cost_s, jc, cost_c)
        self._choice = None
        self.situation.push(self._xs)
        self.coherence.push(self._xc, target)
        self.i += 1
        self.t = g
        rx, ry, look, sx, sy = self._fs.take(_POSE_AND_STEP).tolist()
        self.pose = (rx, ry, look)
        self._last_step = (sx, sy)
        return g, rx, ry, look
