"""The generation step's arithmetic (engine.Reactor._step) compiled as one call.

The readable definition is the Python step, ``engine.Reactor._step`` (step.py), and the
functions it calls; this module (the step: the balancing of BestMatch, paper section 4.3.3,
the stages of Output Generation, 4.4, the look and the new sample pair's features, 4.2) with
generation_kernel (the general trajectory's functions, 4.4.1) and step_math (CPython's
arithmetic) repeats them operation for operation, so a compiled step gives the same pose to
the last bit (tests/puppet_master/test_pm_step_kernel.py runs both side by side). A change to
any of these must be made here too:

- step.GenerationStep, Reactor's ``_step`` and its stages (from the balancing, with a charge
  kept whole, to the features of the new sample pair)
- similarity.Balancer.choose
- generation: target_position, fit_target, clamp_to_table, step_around, step_toward,
  share_around, less_approach, rotate_step, keep_on_table, keep_apart, limit_turn, turn_between,
  StepSmoother.turn, push and lose_inward
- table_boundary.turn_off_edges, apart.out_of_way (EDGE_TURN, LEAD frozen into the compiled step)
- detail: DetailPatch.next and restart, TextureGovernor.alpha / detail_gain / update /
  observe, LookGovernor.observe_look
- look.desired_look
- features: EntityMotion.step, relative_pose, situation_row, since_step, since_row, room_row,
  coherence_row
- darts (darts_kernel): dart_goes_on, span_approach, less_inward
- the look and the pair's motion (step_senses_kernel): desired_look, EntityMotion.step,
  relative_pose
- tabletop.frames.wrap_angle and math.remainder, math.hypot as CPython 3.11 computes them

In Python the step cost about 60-100 us of interpreter time in 40 small helpers (the
searches aside); the compiled call costs 2-10 us. Measured interleaved in one process (8
reactors, thread CPU time, loaded 2-core machine), with the compiled searches on both sides:
about 0.66x the tick at 24,000 training samples and 0.55x at 3,200. The state of the step's small
objects lives in two arrays (indices below); the per-training-sample values the step reads
are one table (columns below, engine.Behavior.step_table).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from behaviors.puppet_master import (apart, character, darts, darts_kernel,
                                     generation_kernel, step_math, step_senses_kernel,
                                     table_boundary)
from behaviors.puppet_master.generation_kernel import (  # noqa: F401 (engine: sk.moved_on)
    X0, X1, Y0, Y1, capped, fit_target, keep_apart, kept_straightness,
    keep_on_table, less_approach, limit_turn, lose_inward, mean_capped, moved_on, no_deeper,
    out_of_way, share_around, step_around, table_reach, turn_between, turn_off_edges)
from behaviors.puppet_master.darts_kernel import dart_goes_on, less_inward
from behaviors.puppet_master.step_senses_kernel import _motion, desired_look, relative_pose
from behaviors.puppet_master.step_math import _max, _min, hypot, remainder, wrap_angle
from behaviors.kernel_cache import compiled

# float state (Reactor._fs)
RX, RY, LOOK, MAIN_X, MAIN_Y, MAIN_MOVE, REACT_X, REACT_Y, REACT_MOVE, EMA_X, EMA_Y, \
    GOV_MS, GOV_Z, GOV_PREV, LOOK_MS, LOOK_Z, LOG_K, SHARE, STEP_X, STEP_Y, CAP_1, \
    CAP_2, STRAIGHT, SINCE = range(24)
FLOAT_STATE = 24
# integer state (Reactor._is)
PATCH_START, PATCH_OFFSET, SMOOTH_I, RECENT_COUNT, RECENT_HEAD, CHOICES, COHERENCE_CHOICES, \
    SOURCE, USED_COHERENCE, CHARGE_END, KEPT_CHARGE, DART_END, KEPT_DART = range(13)
INT_STATE = 13
# constants (Reactor._cs): the table X0, Y0, X1, Y1 (generation_kernel), then
DT, RATE, MIN_SPEED, CATCH_UP, GAIN, TOP_SPEED, STILL_SPEED, MAX_TURN, \
    GOV_TARGET, GOV_MIN_STEP, GOV_GAIN, GOV_DECAY, GOV_Z_MIN, GOV_Z_MAX, \
    LOOK_TARGET, LOOK_GAIN, LOOK_DECAY, LOOK_Z_MIN, LOOK_Z_MAX, \
    TARGET_SHARE, BALANCE_GAIN, SHARE_WINDOW, LOG_K_LIMIT, \
    S_V_MAIN, S_V_REACT, S_REL_POSITION, S_REL_LOOK, S_NORM_LOOK, S_DDIR, \
    STILL_DISTANCE, PATCH_LENGTH, HEADING_MIN_SPEED, FOLLOW_SHARE, PERSONAL_SPACE, \
    KEEPS_PACE, S_ROOM, ROOM_CLIP, TARGET_TABLE = range(4, 42)
WALKS_WITH_MAIN = 45  # after TARGET_TABLE: x0, y0, x1, y1 of Reactor.target_table
LARGEST_STEP = 46
S_STILL = 47          # the weight of the main's still/moving state (0: not a feature)
STOP_SPAN, STOP_DISTANCE = 48, 49   # Behavior.stop_span (held to the ring) and its distance
STRAIGHTNESS = 50     # Behavior.straightness
S_SINCE, SINCE_CLIP, TOUCH = 51, 52, 53   # the steps since the last push (0: not a feature)
CIRCLING = 54         # Behavior.circling (1.0: the smooth turns with the bearing)
MAIN_DISC = 55        # Behavior.main_disc (metres; 0: none)
EDGE_BAND = 56        # Reactor.edge_band (metres)
DARTS = 57            # Behavior.darts (1.0: its darts kept whole, their inward step held)
DART_SPAN = 58        # Behavior.dart_span (samples of the main's span read)
ROOM_REACH = 59       # features.room_gate's reach: Scales.rel_position x ROOM_NEAR
CONSTANTS = 60
# per training sample (Behavior.step_table)
T_PLACE, T_BEARING_TURN, T_DISTANCE, T_FWD, T_LEFT, T_SPEED, T_K, T_U_RAD, T_U_TAN, T_DFX, \
    T_DFY, T_SPAN_STEP, T_WALKED, T_DETAIL, T_FRAME, T_ANGLE, T_STILL_FRAME, T_STILL_ANGLE, \
    T_LOOK_DETAIL, T_CHARGE_END, T_CHARGE_TOUCH, T_MAIN_APPROACH, T_DART_END, \
    T_SPAN_APPROACH = range(24)

PLACE_WORLD = 1.0

_f8 = numba.float64
_F1, _F2, _I1 = numba.float64[::1], numba.float64[:, ::1], numba.int64[::1]


@compiled(_f8(_f8, _f8, _f8), step_math)
def _detail_gain(z: float, z_min: float, z_max: float) -> float:
    """TextureGovernor.detail_gain."""
    return _min(_max(1.0 + z, 0.0), 1.0 + z_max)


@compiled(_f8(_f8), step_math)
def _alpha(z: float) -> float:
    """TextureGovernor.alpha."""
    return 1.0 if z >= -1.0 else _max(0.2, 1.0 + 0.8 * (z + 1.0))


@compiled(numba.void(_F1, numba.int64, numba.int64, _f8, _f8, _f8, _f8, _f8, _f8), step_math)
def _update(s: np.ndarray, ms: int, z: int, value: float, target: float, gain: float,
            decay: float, z_min: float, z_max: float) -> None:
    """TextureGovernor.update on s[ms], s[z]."""
    s[ms] += (value - s[ms]) * decay
    s[z] += gain * (target - s[ms]) / target
    s[z] = _min(_max(s[z], z_min), z_max)


@compiled(numba.boolean(_F2, _I1, _f8, _f8, _f8), step_math)
def main_stands(recent: np.ndarray, ints: np.ndarray, mx: float, my: float,
                distance: float) -> bool:
    """StepSenses._main_stands: the main at (mx, my) within ``distance`` metres of the
    oldest of its last positions (the ring ``recent``, its first slot while not yet full)."""
    o = ints[RECENT_HEAD] if ints[RECENT_COUNT] == recent.shape[0] else 0
    return hypot(mx - recent[o, 0], my - recent[o, 1]) < distance


@compiled(numba.boolean(_F2, _I1, _f8, _f8, numba.int64, _f8), step_math)
def main_stopped(recent: np.ndarray, ints: np.ndarray, mx: float, my: float, span: int,
                 distance: float) -> bool:
    """StepSenses._main_stopped: the main at (mx, my) within ``distance`` metres of each
    of the ``span`` positions before the newest in the ring ``recent``."""
    m = recent.shape[0]
    for j in range(1, span + 1):
        o = (ints[RECENT_HEAD] - 1 - j) % m
        if not hypot(mx - recent[o, 0], my - recent[o, 1]) < distance:
            return False
    return span >= 1


@compiled(numba.boolean(_F1, numba.int64[::1], _F1, _f8, _f8), step_math)
def choose(fs: np.ndarray, ints: np.ndarray, c: np.ndarray, situation_cost: float,
           coherence_cost: float) -> bool:
    """similarity.Balancer.choose."""
    if not math.isfinite(coherence_cost):
        return False
    use = math.exp(fs[LOG_K]) * coherence_cost < situation_cost
    chosen = 1.0 if use else 0.0
    log_k = fs[LOG_K] + c[BALANCE_GAIN] * (chosen - c[TARGET_SHARE])
    limit = c[LOG_K_LIMIT]
    fs[LOG_K] = _min(_max(log_k, -limit), limit)
    ints[CHOICES] += 1
    ints[COHERENCE_CHOICES] += 1 if use else 0
    alpha = _max(1.0 / ints[CHOICES], 1.0 / c[SHARE_WINDOW])
    fs[SHARE] += alpha * (chosen - fs[SHARE])
    return use


@compiled(numba.int64(_F1, _I1, _F1, _F2, _F2, _F1, _F1, _F2, _F2, _F1, _F1,
                      _f8, _f8, _f8, numba.int64, _f8, numba.int64, _f8),
          step_math, generation_kernel, table_boundary, apart, darts_kernel, darts,
          character, step_senses_kernel)
def step(fs: np.ndarray, ints: np.ndarray, c: np.ndarray, table: np.ndarray,
         bearings: np.ndarray, smooth_x: np.ndarray, smooth_y: np.ndarray,
         recent: np.ndarray, obstacles: np.ndarray, xs: np.ndarray, xc: np.ndarray,
         mx: float, my: float, md: float, js: int, cost_s: float, jc: int,
         cost_c: float) -> int:
    """One generation step (engine.Reactor._step) from the main pose (mx, my, md) and the
    searches' best matches; updates the state arrays, writes the new sample pair's situation
    and coherence vectors into ``xs``, ``xc`` and returns the target (the training index
    the step came from). ``recent``: (m, 2) ring of the main's latest positions."""
    use_c = choose(fs, ints, c, cost_s, cost_c)
    target = (jc if use_c else js) + 1
    ints[USED_COHERENCE] = 1 if use_c else 0
    # a dart the match has entered is kept whole to its bottom (darts.py)
    ints[KEPT_DART] = 0
    if 0 <= ints[SOURCE] < ints[DART_END] and hypot(
            fs[RX] - fs[MAIN_X], fs[RY] - fs[MAIN_Y]) > table[ints[SOURCE], T_DISTANCE] \
            and dart_goes_on(recent, ints[RECENT_COUNT], ints[RECENT_HEAD], int(c[DART_SPAN]),
                             table[ints[SOURCE] + 1, T_SPAN_APPROACH], c[DT], mx, my,
                             fs[RX] - fs[MAIN_X], fs[RY] - fs[MAIN_Y]):
        target = ints[SOURCE] + 1
        ints[KEPT_DART] = 1
    else:
        ints[DART_END] = int(table[target, T_DART_END])
    # a charge the match has entered is kept whole to the end of its push
    ended = False
    if ints[KEPT_DART] == 1:
        ints[KEPT_CHARGE] = 0
    elif 0 <= ints[SOURCE] < ints[CHARGE_END]:
        target = ints[SOURCE] + 1
        ints[KEPT_CHARGE] = 1
    else:
        ints[KEPT_CHARGE] = 0
        ended = ints[CHARGE_END] >= 0
        ints[CHARGE_END] = int(table[target, T_CHARGE_END])
        if ints[CHARGE_END] >= 0:
            ints[PATCH_OFFSET] = int(c[PATCH_LENGTH])     # DetailPatch.restart
    ints[SOURCE] = target
    rx, ry, look = fs[RX], fs[RY], fs[LOOK]
    row = table[target]
    place, bearing_turn, dist = row[T_PLACE], row[T_BEARING_TURN], row[T_DISTANCE]
    fwd_t, left_t, speed = row[T_FWD], row[T_LEFT], row[T_SPEED]
    m = recent.shape[0]                 # the main's last positions (still or not)
    head = ints[RECENT_HEAD]
    recent[head, 0], recent[head, 1] = mx, my
    head = (head + 1) % m
    ints[RECENT_HEAD] = head
    if ints[RECENT_COUNT] < m:
        ints[RECENT_COUNT] += 1
    if place == PLACE_WORLD:
        phi = math.atan2(ry - my, rx - mx) + bearing_turn
        tx, ty = mx + dist * math.cos(phi), my + dist * math.sin(phi)
    elif (c[PERSONAL_SPACE] > 0.0 and c[WALKS_WITH_MAIN] == 0.0 and row[T_WALKED] == 0.0
          and ints[RECENT_COUNT] == m and main_stands(recent, ints, mx, my,
                                                      c[STILL_DISTANCE])):
        # StepSenses._stood_place: its distance on the live bearing
        phi = math.atan2(ry - my, rx - mx)
        tx, ty = mx + dist * math.cos(phi), my + dist * math.sin(phi)
    else:
        cm, sm = math.cos(md), math.sin(md)
        tx, ty = mx + cm * fwd_t - sm * left_t, my + sm * fwd_t + cm * left_t
    tx, ty = fit_target(mx, my, tx, ty, rx, ry, c[TARGET_TABLE:TARGET_TABLE + 4], bearings)
    dt = c[DT]
    if c[CATCH_UP] > 0.0 and speed >= 3.0 * c[MIN_SPEED]:
        speed = _max(speed, _min(c[CATCH_UP] * hypot(tx - rx, ty - ry), c[TOP_SPEED]))
    gain = c[GAIN]
    mean_cap = math.inf
    step_cap = math.inf
    keep_length = 0.0                   # the smooth's length kept up to this (step.py)
    if gain > 0.0 and target > 0:
        mxp, myp = fs[MAIN_X], fs[MAIN_Y]
        if place == PLACE_WORLD:
            k, u_rad, u_tan = row[T_K], row[T_U_RAD], row[T_U_TAN]
            ax, ay = rx - mxp, ry - myp
            rho = hypot(ax, ay)
            if rho > 1e-9:
                ex, ey = ax / rho, ay / rho
            else:
                ex, ey = 1.0, 0.0
            sx = k * (mx - mxp) + u_rad * ex - u_tan * ey + gain * (tx - rx)
            sy = k * (my - myp) + u_rad * ey + u_tan * ex + gain * (ty - ry)
            if ints[CHARGE_END] >= 0:      # in a charge: the main's step along the bearing
                along = (mx - mxp) * ex + (my - myp) * ey
                sx -= k * ((mx - mxp) - along * ex)
                sy -= k * ((my - myp) - along * ey)
        else:
            cm, s_ = math.cos(md), math.sin(md)
            dfx, dfy = row[T_DFX], row[T_DFY]
            cx, cy = gain * (tx - rx), gain * (ty - ry)
            if ints[CHARGE_END] < 0 and c[PERSONAL_SPACE] <= 0.0:
                cx, cy = share_around(mx, my, rx, ry, tx, ty, gain)
            most = math.inf                         # the drift correction's longest
            if row[T_K] >= c[FOLLOW_SHARE]:
                most = row[T_SPAN_STEP]
            elif ints[CHARGE_END] < 0 and c[KEEPS_PACE] != 0.0:
                most = speed * dt                   # at the moment's pace
            corr = hypot(cx, cy)
            if corr > most:
                cx, cy = cx * most / corr, cy * most / corr
            if ints[CHARGE_END] < 0 and c[KEEPS_PACE] != 0.0:
                cx, cy = less_approach(mx - mxp, my - myp, rx - mx, ry - my,
                                       row[T_MAIN_APPROACH], cx, cy)
            sx = (mx - mxp) + cm * dfx - s_ * dfy + cx
            sy = (my - myp) + s_ * dfx + cm * dfy + cy
            if c[DARTS] != 0.0 and ints[CHARGE_END] < 0:
                sx, sy = less_inward(sx, sy, cm * dfx - s_ * dfy, s_ * dfx + cm * dfy,
                                     rx - mxp, ry - myp, dist, c[MAIN_DISC])
        if ints[CHARGE_END] >= 0:
            # a charge kept whole closes the live distance beyond the demonstrated one
            touch = int(row[T_CHARGE_TOUCH])
            lx, ly = mx - rx, my - ry
            live = hypot(lx, ly)
            gap = live - dist
            if gap > 0.0 and live > 1e-9:
                gap /= max(1, touch - target + 1)
                sx, sy = sx + gap * lx / live, sy + gap * ly / live
        cap = (speed if place == PLACE_WORLD else c[TOP_SPEED]) * dt
        if ints[RECENT_COUNT] == m and (row[T_WALKED] != 0.0 or (
                c[WALKS_WITH_MAIN] != 0.0 and place != PLACE_WORLD)):
            if main_stopped(recent, ints, mx, my, int(c[STOP_SPAN]), c[STOP_DISTANCE]) if (
                    c[KEEPS_PACE] != 0.0) else main_stands(recent, ints, mx, my,
                                                           c[STILL_DISTANCE]):
                cap = _min(cap, c[STILL_SPEED] * dt)
        if place == PLACE_WORLD and ints[CHARGE_END] < 0 and c[WALKS_WITH_MAIN] != 0.0:
            # the mean of three raw steps held to the cap (generation.mean_capped)
            size = smooth_x.size
            i = ints[SMOOTH_I]
            px, py = 0.0, 0.0
            for q in range(size):
                if q != i:
                    px += smooth_x[q]
                    py += smooth_y[q]
            sx, sy = mean_capped(px, py, sx, sy, cap, size)
            mean_cap = _max(cap, _max(fs[CAP_1], fs[CAP_2]))
            keep_length = cap
        else:
            sx, sy = capped(sx, sy, cap)
        step_cap = cap
    else:
        sx, sy = step_around(mx, my, rx, ry, tx, ty, speed * dt)
    if ended:           # a kept charge has ended: the smooths restart at the raw step
        for q in range(smooth_x.size):
            smooth_x[q], smooth_y[q] = sx, sy
        fs[EMA_X], fs[EMA_Y] = sx, sy
    size = smooth_x.size
    if c[CIRCLING] > 0.0:   # a circling character's smooth turns with its bearing (step.py)
        ct, st = turn_between(rx - fs[STEP_X] - fs[MAIN_X], ry - fs[STEP_Y] - fs[MAIN_Y],
                              rx - mx, ry - my)
        for q in range(size):       # StepSmoother.turn
            x, y = smooth_x[q], smooth_y[q]
            smooth_x[q], smooth_y[q] = ct * x - st * y, st * x + ct * y
    # StepSmoother.push
    i = ints[SMOOTH_I]
    smooth_x[i], smooth_y[i] = sx, sy
    ints[SMOOTH_I] = (i + 1) % size
    tot_x, tot_y = 0.0, 0.0
    for q in range(size):
        tot_x += smooth_x[q]
    for q in range(size):
        tot_y += smooth_y[q]
    sx, sy = tot_x / size, tot_y / size
    if keep_length > 0.0:
        sx, sy, kept = kept_straightness(sx, sy, smooth_x, smooth_y, c[STRAIGHTNESS],
                                         fs[STRAIGHT], c[GOV_DECAY], keep_length)
        fs[STRAIGHT] = kept
    fs[CAP_2], fs[CAP_1] = fs[CAP_1], step_cap
    sx, sy = capped(sx, sy, mean_cap)
    a = _alpha(fs[GOV_Z])
    sx = a * sx + (1.0 - a) * fs[EMA_X]
    sy = a * sy + (1.0 - a) * fs[EMA_Y]
    fs[EMA_X], fs[EMA_Y] = sx, sy
    heading = math.atan2(sy, sx)
    # DetailPatch.next
    if ints[PATCH_OFFSET] >= c[PATCH_LENGTH]:
        ints[PATCH_START], ints[PATCH_OFFSET] = target, 0
    i_detail = ints[PATCH_START] + ints[PATCH_OFFSET]
    ints[PATCH_OFFSET] += 1
    if not (0 <= i_detail < table.shape[0]):
        i_detail = -1
    tex = table[i_detail if i_detail >= 0 else target]
    if i_detail >= 0 and ints[CHARGE_END] < 0:
        angle = _detail_gain(fs[GOV_Z], c[GOV_Z_MIN], c[GOV_Z_MAX]) * tex[T_DETAIL]
        ca, sa = math.cos(angle), math.sin(angle)
        sx, sy = ca * sx - sa * sy, sa * sx + ca * sy
    sx, sy = turn_off_edges(rx, ry, sx, sy, c, c[EDGE_BAND])
    sx, sy = keep_on_table(rx, ry, sx, sy, c)
    if obstacles.shape[0] > 0:
        nx, ny = rx + sx, ry + sy
        if c[MAIN_DISC] > 0.0:       # the main's way ahead (step_detail.py)
            nx, ny = out_of_way(nx, ny, mx, my, mx - fs[MAIN_X], my - fs[MAIN_Y], c[MAIN_DISC],
                                c[LARGEST_STEP], c)
        nx, ny = keep_apart(nx, ny, obstacles, c)
        if c[KEEPS_PACE] != 0.0 and hypot(rx + sx - mx, ry + sy - my) < c[MAIN_DISC]:
            lose_inward(smooth_x, smooth_y, nx - mx, ny - my)     # pushed aside (step.py)
        sx, sy = nx - rx, ny - ry
        sx, sy = capped(sx, sy, c[LARGEST_STEP])     # shoved (step_detail.py)
        bodies = obstacles[1:] if c[MAIN_DISC] > 0.0 else obstacles
        if bodies.shape[0] > 0:                       # round the bodies (step_detail.py)
            nx, ny = no_deeper(rx, ry, rx + sx, ry + sy, bodies, c)
            sx, sy = capped(nx - rx, ny - ry, c[LARGEST_STEP])
    # TextureGovernor.observe
    if hypot(sx, sy) <= c[GOV_MIN_STEP]:
        fs[GOV_PREV] = math.nan
    else:
        h = math.atan2(sy, sx)
        if fs[GOV_PREV] == fs[GOV_PREV]:
            turn = remainder(h - fs[GOV_PREV], math.tau)
            _update(fs, GOV_MS, GOV_Z, turn * turn, c[GOV_TARGET], c[GOV_GAIN], c[GOV_DECAY],
                    c[GOV_Z_MIN], c[GOV_Z_MAX])
        fs[GOV_PREV] = h
    rx, ry = rx + sx, ry + sy
    moving = hypot(sx, sy) * c[RATE] >= c[HEADING_MIN_SPEED]
    desired = desired_look(tex[T_FRAME], tex[T_ANGLE], tex[T_STILL_FRAME], tex[T_STILL_ANGLE],
                           moving, heading, md, math.atan2(my - ry, mx - rx))
    desired += _detail_gain(fs[LOOK_Z], c[LOOK_Z_MIN], c[LOOK_Z_MAX]) * tex[T_LOOK_DETAIL]
    turned = limit_turn(look, look + _alpha(fs[LOOK_Z]) * wrap_angle(desired - look),
                        c[MAX_TURN])
    _update(fs, LOOK_MS, LOOK_Z, abs(wrap_angle(turned - look)), c[LOOK_TARGET], c[LOOK_GAIN],
            c[LOOK_DECAY], c[LOOK_Z_MIN], c[LOOK_Z_MAX])
    look = turned
    # features of the new sample pair
    vm, _, _ = _motion(fs, MAIN_X, mx, my, c[RATE], c[MIN_SPEED])
    vr, move_r, ddir_r = _motion(fs, REACT_X, rx, ry, c[RATE], c[MIN_SPEED])
    fwd, left, rel_look = relative_pose(mx, my, md, rx, ry, look)
    xs[0] = c[S_V_MAIN] * vm
    xs[1] = c[S_V_REACT] * vr
    xs[2] = c[S_REL_POSITION] * fwd
    xs[3] = c[S_REL_POSITION] * left
    xs[4] = c[S_REL_LOOK] * math.cos(rel_look)
    xs[5] = c[S_REL_LOOK] * math.sin(rel_look)
    at = 6
    still = 0.0
    if c[S_STILL] > 0.0:            # the main's still/moving state (features.still_row)
        if main_stands(recent, ints, mx, my, c[STILL_DISTANCE]):
            still = c[S_STILL]
        xs[6] = still
        at = 7
    if c[S_SINCE] > 0.0:            # the steps since the last push (features.since_step)
        if hypot(fwd, left) < c[TOUCH]:
            fs[SINCE] = 0.0
        else:
            fs[SINCE] = _min(fs[SINCE] + 1.0, c[SINCE_CLIP])
        xs[at] = c[S_SINCE] * fs[SINCE]
        at += 1
    if xs.shape[0] > at:            # the reactor's room on the table (features.room_row)
        rho = hypot(rx - mx, ry - my)
        clip = c[ROOM_CLIP]
        back, side = clip, 0.0
        if rho > 1e-9:
            ux, uy = (rx - mx) / rho, (ry - my) / rho
            back = _max(0.0, _min(table_reach(rx, ry, ux, uy, c), clip))
            side = (_max(0.0, _min(table_reach(rx, ry, -uy, ux, c), clip))
                    - _max(0.0, _min(table_reach(rx, ry, uy, -ux, c), clip)))
        xs[at] = c[S_ROOM] * back
        xs[at + 1] = c[S_ROOM] * side
    norm_look = wrap_angle(look - move_r)
    xc[0] = c[S_NORM_LOOK] * math.cos(norm_look)
    xc[1] = c[S_NORM_LOOK] * math.sin(norm_look)
    xc[2] = c[S_DDIR] * math.cos(ddir_r)
    xc[3] = c[S_DDIR] * math.sin(ddir_r)
    xc[4] = c[S_REL_POSITION] * fwd
    xc[5] = c[S_REL_POSITION] * left
    xc[6] = c[S_V_REACT] * vr
    xc[7] = c[S_V_MAIN] * vm
    if c[S_STILL] > 0.0:
        xc[8] = still
    if c[S_SINCE] > 0.0:            # features.since_column
        xc[9 if c[S_STILL] > 0.0 else 8] = c[S_SINCE] * fs[SINCE]
    fs[RX], fs[RY], fs[LOOK] = rx, ry, look
    fs[STEP_X], fs[STEP_Y] = sx, sy
    return target

