"""Scripted designers: seeded, human-like demonstrations of the five example personalities.

A designer moves the main puck around the table (wandering between spots, pausing, turning,
sometimes pulling it back the way it came) while the other hand plays the reactor: a lover, a
bully, a playful friend, a stalker or an afraid character. The reactor's hand perceives the main
puck with a human reaction delay, accelerates and turns at hand-like limits, stops at the table's
edge, and both hands shake a little (band-limited tremor on position and look direction).

Every function is pure: the same arguments give the same array, bit for bit. A demonstration is a
float array (n, 7) with columns ``t, main_x, main_y, main_dir, react_x, react_y, react_dir``:
seconds from 0 at ``rate_hz``, table metres, look directions in radians wrapped to (-pi, pi].
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from behaviors.puppet_master import chased, reactor_hand
from behaviors.puppet_master.hand_motion import (Policy, Table, Vec, _Seen, _tremor, _turn_toward,
                                                 _unit)
from behaviors.puppet_master.reactor_hand import CONTACT, MainHand
from behaviors.puppet_master.sequential import main_at
from tabletop.frames import wrap_angle, wrap_angles

COLUMNS = ("t", "main_x", "main_y", "main_dir", "react_x", "react_y", "react_dir")
PERSONALITIES = ("lover", "bully", "playful_friend", "stalker", "afraid")
SEEDS = {"lover": 11, "bully": 23, "playful_friend": 37, "stalker": 41, "afraid": 53}
# a demonstration's length (s) where not 60 s: a character shown chased is shown in two kinds
# of situation, calm and chased (chased.py: the longer demonstration and its figures)
DURATION_S = {"afraid": 80.0}
# 80 s for the others measured (bench/fidelity.py's figures against the longer
# demonstration; misses, the engine's alone, seeds 0-5 / 8-13): the lover 30 (5) / 34 (11)
# against 16 (6) / 15 (6), its longer demonstration touching its main (contact missed on 21
# paths); the stalker 14 (7) / 10 (6) against 11 (5) / 13 (8). Not used.

def designer_main_path(seed: int, seconds: float = 60.0, rate_hz: float = 40.0,
                       table: Table = (1.2, 0.8), margin: float = 0.15,
                       speed_range: tuple[float, float] = (0.08, 0.3),
                       reversals_per_s: float = 0.08) -> np.ndarray:
    """A designer's hand moving the main puck: (n, 4) array ``t, x, y, dir`` (s, m, m, rad).

    The hand wanders between random spots at ``speed_range`` m/s, pauses on some (0.6-2.5 s,
    sometimes turning the puck in place), and now and then (``reversals_per_s`` while moving)
    pulls the puck back the way it came (a sudden reversal). The puck looks where it goes,
    with a short lag, and holds its look when still. No shake is added here (see
    :func:`demonstrate`).
    """
    rng = np.random.default_rng(seed)
    w, h = table
    lo, hi = np.array([margin, margin]), np.array([w - margin, h - margin])
    dt = 1.0 / rate_hz
    n = int(round(seconds * rate_hz))
    p = rng.uniform(lo, hi)
    look = float(rng.uniform(-math.pi, math.pi))
    goal, speed, pause, spin = rng.uniform(lo, hi), float(np.clip(0.18, *speed_range)), 0.0, 0.0
    wander = _tremor(rng, n, rate_hz, 0.05, 0.5, 0.5).tolist()  # the hand's path curves, rad
    # plain floats, the same operations in the same order as on 2-vectors (np.hypot, not
    # math.hypot: it differs in the last bit on 0.6% of pairs), so the same path bit for bit;
    # with the policies and reactor_hand on floats, 10 takes 2.11 -> 0.48 CPU s
    hypot, turn, above = np.hypot, _turn_toward, reactor_hand.above
    px, py, gx, gy, vx, vy = float(p[0]), float(p[1]), float(goal[0]), float(goal[1]), 0.0, 0.0
    dv_most, turn_most, chance = 0.9 * dt, 6.0 * dt, reversals_per_s * dt
    rows = []
    for i in range(n):
        if pause > 0.0:
            pause -= dt
            dx = dy = 0.0
            look = wrap_angle(look + spin * dt)
            if pause <= 0.0:
                goal, speed = rng.uniform(lo, hi), float(rng.uniform(*speed_range))
                gx, gy = float(goal[0]), float(goal[1])
        else:
            tx, ty = gx - px, gy - py
            d = float(hypot(tx, ty))
            if d < 0.03:
                if rng.random() < 0.4:
                    pause = float(rng.uniform(0.6, 2.5))
                    spin = float(rng.choice([0.0, 0.0, rng.uniform(-1.5, 1.5)]))
                goal, speed = rng.uniform(lo, hi), float(rng.uniform(*speed_range))
                gx, gy = float(goal[0]), float(goal[1])
                tx, ty = gx - px, gy - py
                d = float(hypot(tx, ty))
            elif above(vx, vy, 0.08) and rng.random() < chance:
                back = np.array((px, py)) - _unit(np.array((vx, vy))) * float(
                    rng.uniform(0.2, 0.4))
                goal = np.clip(back, lo, hi)            # pulled back the way it came
                gx, gy = float(goal[0]), float(goal[1])
                tx, ty = gx - px, gy - py
                d = float(hypot(tx, ty))
            c, s_ = math.cos(wander[i]), math.sin(wander[i])
            ux, uy = (tx / d, ty / d) if d > 1e-9 else (0.0, 0.0)    # _unit
            f = speed * min(1.0, d / 0.1)
            dx, dy = (c * ux - s_ * uy) * f, (s_ * ux + c * uy) * f
        ax, ay = dx - vx, dy - vy
        if above(ax, ay, dv_most):                  # _limit
            f = dv_most / float(hypot(ax, ay))
            ax, ay = ax * f, ay * f
        vx, vy = vx + ax, vy + ay
        px = min(max(px + vx * dt, 0.0), w)         # np.clip's values
        py = min(max(py + vy * dt, 0.0), h)
        if above(vx, vy, 0.04):
            heading = math.atan2(vy, vx)
            step = min(turn_most, abs(wrap_angle(heading - look)) * dt / 0.15)  # lag, rate limit
            look = turn(look, heading, step)
        rows.append((i * dt, px, py, look))
    return np.array(rows).reshape(n, 4)


# The policies run every sample on plain floats: the same operations in the same order as on
# 2-vectors, so the same floats (reactor_hand's module doc); they return 2-vectors.


def _lover(rng: np.random.Generator) -> Policy:
    """Approaches, stays close (about 0.12 m) facing the main, nuzzling side to side."""
    phase = float(rng.uniform(0, math.tau))
    hypot, sin, cos, atan2 = np.hypot, math.sin, math.cos, math.atan2

    def policy(t: float, p: Vec, v: Vec, look: float, m: _Seen) -> tuple[Vec, float]:
        (mx, my), (mvx, mvy), (px, py) = m.p.tolist(), m.v.tolist(), p.tolist()
        rx, ry = mx - px, my - py
        d = float(hypot(rx, ry))
        face = atan2(ry, rx)
        ux, uy = (rx / d, ry / d) if d > 1e-9 else (0.0, 0.0)        # _unit
        k = min(max(2.0 * (d - 0.12), -0.15), 0.35)                   # np.clip's value
        vx, vy = ux * k + 0.8 * mvx, uy * k + 0.8 * mvy
        if d < 0.2:
            nuzzle = sin(2 * math.pi * 0.8 * t + phase)
            vx, vy = vx + -sin(face) * 0.06 * nuzzle, vy + cos(face) * 0.06 * nuzzle
        return np.array((vx, vy)), face
    return policy


def _bully(rng: np.random.Generator, dt: float) -> Policy:
    """Lurks facing the main, charges at it, pushes into it, then backs off; again and again."""
    mode, left, side = "lurk", float(rng.uniform(1.0, 2.5)), 1.0
    hypot, atan2 = np.hypot, math.atan2

    def policy(t: float, p: Vec, v: Vec, look: float, m: _Seen) -> tuple[Vec, float]:
        nonlocal mode, left, side
        (mx, my), (mvx, mvy), (px, py) = m.p.tolist(), m.v.tolist(), p.tolist()
        rx, ry = mx - px, my - py
        d = float(hypot(rx, ry))
        face = atan2(ry, rx)
        ux, uy = (rx / d, ry / d) if d > 1e-9 else (0.0, 0.0)        # _unit
        left -= dt
        if mode == "lurk":
            sx, sy = -uy * side, ux * side
            k = d - 0.3
            vx, vy = ux * 1.5 * k + sx * 0.08 + mvx, uy * 1.5 * k + sy * 0.08 + mvy
            if left <= 0:
                mode = "charge"
        elif mode == "charge":
            vx, vy = ux * 0.65, uy * 0.65
            if d < 0.07:
                mode, left = "push", float(rng.uniform(0.3, 0.6))
        elif mode == "push":
            vx, vy = ux * 0.2 + mvx, uy * 0.2 + mvy
            if left <= 0:
                mode, left = "back", float(rng.uniform(0.8, 1.4))
        else:
            vx, vy = -ux * 0.28 + mvx * 0.5, -uy * 0.28 + mvy * 0.5
            if left <= 0 or d > 0.4:
                mode, left = "lurk", float(rng.uniform(1.0, 2.5))
                side = float(rng.choice([-1.0, 1.0]))
        return np.array((vx, vy)), face
    return policy


def _playful_friend(rng: np.random.Generator, dt: float) -> Policy:
    """Circles counter-clockwise around the main, darting in close and out again."""
    theta: float | None = None
    dart, dart_t = float(rng.uniform(1.5, 3.0)), -10.0
    hypot, sin, cos, atan2 = np.hypot, math.sin, math.cos, math.atan2

    def policy(t: float, p: Vec, v: Vec, look: float, m: _Seen) -> tuple[Vec, float]:
        nonlocal theta, dart, dart_t
        (mx, my), (mvx, mvy), (px, py) = m.p.tolist(), m.v.tolist(), p.tolist()
        rx, ry = px - mx, py - my
        if theta is None:
            theta = atan2(ry, rx)
        theta += 2.4 * dt
        dart -= dt
        if dart <= 0:
            dart_t, dart = t, float(rng.uniform(2.0, 4.0))
        age = t - dart_t
        r = 0.17 - (0.11 * sin(math.pi * age / 0.6) if age < 0.6 else 0.0)
        r += 0.03 * sin(1.3 * t)
        c, s_ = cos(theta), sin(theta)
        gx, gy = mx + r * c, my + r * s_
        k = 2.4 * r
        vx, vy = mvx + k * -s_ + 5.0 * (gx - px), mvy + k * c + 5.0 * (gy - py)
        (ox, oy) = v.tolist()
        sp = float(hypot(ox, oy))
        face = atan2(oy, ox) if sp > 0.05 else atan2(-ry, -rx)
        return np.array((vx, vy)), face
    return policy


def _stalker(rng: np.random.Generator) -> Policy:
    """Follows about 0.35 m behind the main, watching it; stops when it stops."""
    heading: float | None = None
    hypot, atan2 = np.hypot, math.atan2

    def policy(t: float, p: Vec, v: Vec, look: float, m: _Seen) -> tuple[Vec, float]:
        nonlocal heading
        (mx, my), (mvx, mvy), (px, py) = m.p.tolist(), m.v.tolist(), p.tolist()
        rx, ry = mx - px, my - py
        d = float(hypot(rx, ry))
        face = atan2(ry, rx)
        ux, uy = (rx / d, ry / d) if d > 1e-9 else (0.0, 0.0)        # _unit
        if m.speed > 0.03:
            heading = atan2(mvy, mvx)
        if heading is None or m.speed <= 0.03:
            if d < 0.22:                     # discovered: back off a little
                return np.array((-ux * 0.12, -uy * 0.12)), face
            return np.zeros(2), face
        gx, gy = mx - 0.35 * math.cos(heading), my - 0.35 * math.sin(heading)
        vx, vy = mvx + 2.0 * (gx - px), mvy + 2.0 * (gy - py)
        if d < 0.22:
            vx, vy = vx - ux * 0.2, vy - uy * 0.2
        return np.array((vx, vy)), face
    return policy


CHASED = ("afraid",)   # personalities whose designer shows them by chasing them (chased.py)


def _policy(personality: str, rng: np.random.Generator, table: Table,
            dt: float) -> tuple[Policy, float, float]:
    """The policy, its hand's top speed (m/s) and acceleration (m/s^2)."""
    if personality == "lover":
        return _lover(rng), 0.4, 1.2
    if personality == "bully":
        return _bully(rng, dt), 0.7, 2.5
    if personality == "playful_friend":
        return _playful_friend(rng, dt), 0.8, 3.0
    if personality == "stalker":
        return _stalker(rng), 0.45, 1.2
    if personality == "afraid":
        return chased.afraid(rng, table, dt), 0.65, 2.5
    raise ValueError(f"unknown personality {personality!r}; "
                     f"expected one of {', '.join(PERSONALITIES)}")


# Hand shake per personality: (position tremor RMS m, look tremor RMS rad, tremor band Hz).
SHAKE = {"lover": (0.0012, 0.02, (3.0, 8.0)), "bully": (0.0025, 0.04, (3.0, 10.0)),
         "playful_friend": (0.002, 0.03, (3.0, 10.0)), "stalker": (0.0012, 0.02, (3.0, 8.0)),
         "afraid": (0.0025, 0.05, (5.0, 12.0))}


def demonstrate(personality: str, seed: int | None = None, seconds: float | None = None,
                rate_hz: float = 40.0, table: Table = (1.2, 0.8),
                main: np.ndarray | None = None, delay_s: float = 0.15,
                chaser: MainHand | None = None) -> np.ndarray:
    """A scripted designer's demonstration of ``personality``: (n, 7) array (see module doc).

    ``seconds``: by default the personality's DURATION_S, else 60. ``main``: the main path
    (n, 4) ``t, x, y, dir`` to react to; by default the designer's own
    (:func:`designer_main_path` with the same seed). ``delay_s``: the reactor hand's reaction time.
    ``chaser``: a main hand that reacts to the reactor (``step(i, previous main pose, reactor
    position)`` gives the main pose x, y, dir of sample ``i``, e.g. visitors.Pursuer); ``main``
    then gives the times and the first pose.
    """
    seed = SEEDS.get(personality, 0) if seed is None else seed
    seconds = DURATION_S.get(personality, 60.0) if seconds is None else seconds
    rng = np.random.default_rng([seed, 1])
    dt = 1.0 / rate_hz
    policy, top_speed, accel = _policy(personality, rng, table, dt)
    if chaser is not None:
        if main is None:
            raise ValueError("demonstrate: a chaser needs the main path's times and first pose")
        main = np.array(main, dtype=float)
    elif main is None:
        main = designer_main_path(seed, seconds, rate_hz, table)
        if personality in CHASED:           # the designer's main hand goes after the reactor
            chaser = chased.ChasingHand(np.random.default_rng([seed, 3]), main, table, dt)
            main = main.copy()
    w, h = table
    n = len(main)
    mp = main[:, 1:3]
    mv = np.gradient(mp, dt, axis=0) if n > 1 else np.zeros((n, 2))
    lag = int(round(delay_s * rate_hz))
    start = mp[0] + np.array([math.cos(main[0, 3]), math.sin(main[0, 3])]) * 0.3
    edge = 0.05
    p = np.clip(start, edge, (w - edge, h - edge))
    if float(np.hypot(*(p - mp[0]))) < 0.1:
        p = np.clip(mp[0] - (start - mp[0]), edge, (w - edge, h - edge))
    look = math.atan2(mp[0, 1] - p[1], mp[0, 0] - p[0])
    react = reactor_hand.react(policy, main, mv, p, look, lag, dt, top_speed, accel, table,
                               edge, chaser)
    pos_rms, ang_rms, (lo_hz, hi_hz) = SHAKE.get(personality, (0.0015, 0.03, (3.0, 10.0)))
    shake = np.random.default_rng([seed, 2])
    out = np.empty((n, 7))
    out[:, 0] = main[:, 0] - main[0, 0]
    for col, base, rms in ((1, main[:, 1], 0.0012), (2, main[:, 2], 0.0012),
                           (4, react[:, 0], pos_rms), (5, react[:, 1], pos_rms)):
        out[:, col] = base + _tremor(shake, n, rate_hz, lo_hz, hi_hz, rms)
    out[:, 3] = wrap_angles(main[:, 3] + _tremor(shake, n, rate_hz, lo_hz, hi_hz, 0.02))
    out[:, 6] = wrap_angles(react[:, 2] + _tremor(shake, n, rate_hz, lo_hz, hi_hz, ang_rms))
    out[:, (1, 4)] = np.clip(out[:, (1, 4)], 0.0, w)
    out[:, (2, 5)] = np.clip(out[:, (2, 5)], 0.0, h)
    return out


def sequential_takes(personality: str, seed: int | None = None, seconds: float | None = None,
                     rate_hz: float = 60.0, table: Table = (1.2, 0.8), phase: float = 0.5,
                     latency_s: float = 1.0 / 60.0) -> tuple[np.ndarray, np.ndarray]:
    """A scripted designer's sequential take (paper section 3.1, as the studio records it):
    (main take (n, 4), reactor take (m, 4)), each ``t, x, y, dir``. The main take is the main
    hand of :func:`demonstrate` on the designer's own unchased main path at ``rate_hz`` (its
    shake included); the reactor take is the same designer's reaction to that take's playback,
    on camera frames ``phase`` of a frame after the main's (times on the main take's base), the
    playback seen ``latency_s`` late (the frame drawn after the one it was computed for)."""
    seed = SEEDS.get(personality, 0) if seed is None else seed
    path, t = sequential_frames(personality, seed, seconds, rate_hz, table, phase)
    main_take = demonstrate(personality, seed, rate_hz=rate_hz, table=table,
                            main=path.copy())[:, :4]
    hand = demonstrate(personality, seed, rate_hz=rate_hz, table=table,
                       main=path_at(path, t, latency_s))
    return main_take, np.column_stack([t, hand[:, 4:7]])


def sequential_frames(personality: str, seed: int, seconds: float | None = None,
                      rate_hz: float = 60.0, table: Table = (1.2, 0.8), phase: float = 0.5
                      ) -> tuple[np.ndarray, np.ndarray]:
    """The main path (n, 4) of ``personality``'s sequential take (:func:`sequential_takes`;
    ``seconds`` by default its DURATION_S, else 60) and the times (s) of the reactor's camera
    frames, ``phase`` of a frame after the main's at ``rate_hz``."""
    seconds = DURATION_S.get(personality, 60.0) if seconds is None else seconds
    path = designer_main_path(seed, seconds, rate_hz, table)
    return path, np.arange(phase / rate_hz, float(path[-1, 0]), 1.0 / rate_hz)


def path_at(path: np.ndarray, t: np.ndarray, late_s: float = 0.0) -> np.ndarray:
    """A main path (n, 4) ``t, x, y, dir`` as seen at times ``t`` (s) ``late_s`` late: (len(t),
    4), read as pair_takes reads a main take (sequential.main_at)."""
    return np.column_stack([t, main_at(path, t - late_s)])


def reaction_on_grid(personality: str, main: np.ndarray, rate_hz: float,
                     table: Table = (1.2, 0.8)) -> tuple[np.ndarray, np.ndarray]:
    """The scripted designer's own ``personality`` reacting to another main path ``main``
    (n, 4) ``t, x, y, dir`` at its own sampling rate: (times (m,) s from the path's start on a
    ``rate_hz`` grid, reactor poses (m, 3) x, y, look on that grid). The reference a generated
    reactor on the same path is set beside (bench/fidelity.py)."""
    main = np.asarray(main, dtype=float)
    path_rate = (len(main) - 1) / float(main[-1, 0] - main[0, 0])
    d = demonstrate(personality, rate_hz=path_rate, table=table, main=main.copy())
    t, _, react = _on_grid(d, rate_hz)
    return t + float(main[0, 0]), react


def _on_grid(d: np.ndarray, rate_hz: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A demonstration (n, 7) on a ``rate_hz`` grid from its start: times (m,), main poses
    (m, 3) and reactor poses (m, 3), x, y, look."""
    t = np.arange(0.0, float(d[-1, 0]), 1.0 / rate_hz)

    def poses(c: int) -> np.ndarray:
        return np.column_stack([np.interp(t, d[:, 0], d[:, c]),
                                np.interp(t, d[:, 0], d[:, c + 1]),
                                wrap_angles(np.interp(t, d[:, 0], np.unwrap(d[:, c + 2])))])
    return t, poses(1), poses(4)


def pursued_on_grid(personality: str, chaser: Any, rate_hz: float,
                    table: Table = (1.2, 0.8)) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The scripted designer's own ``personality`` played against a main hand that reacts to
    it (``chaser``, fresh, e.g. visitors.Pursuer: ``times``, ``rate_hz``, ``first()`` and
    ``step``): (times (m,) s on a ``rate_hz`` grid, main poses (m, 3), reactor poses (m, 3)).
    The closed-loop counterpart of :func:`reaction_on_grid`."""
    main = np.zeros((len(chaser.times), 4))
    main[:, 0] = chaser.times
    main[:, 1:4] = chaser.first()     # at rest until the hand moves (no false first velocity)
    d = demonstrate(personality, rate_hz=chaser.rate_hz, table=table, main=main, chaser=chaser)
    t, m, react = _on_grid(d, rate_hz)
    return t + float(main[0, 0]), m, react


def lover(seed: int = SEEDS["lover"], seconds: float = 60.0, rate_hz: float = 40.0,
          table: Table = (1.2, 0.8)) -> np.ndarray:
    """A lover: approaches and stays close, facing the main (see :func:`demonstrate`)."""
    return demonstrate("lover", seed, seconds, rate_hz, table)


def bully(seed: int = SEEDS["bully"], seconds: float = 60.0, rate_hz: float = 40.0,
          table: Table = (1.2, 0.8)) -> np.ndarray:
    """A bully: charges at the main, pushes into it, backs off (see :func:`demonstrate`)."""
    return demonstrate("bully", seed, seconds, rate_hz, table)


def playful_friend(seed: int = SEEDS["playful_friend"], seconds: float = 60.0,
                   rate_hz: float = 40.0, table: Table = (1.2, 0.8)) -> np.ndarray:
    """A playful friend: circles counter-clockwise around the main and darts in and out."""
    return demonstrate("playful_friend", seed, seconds, rate_hz, table)


def stalker(seed: int = SEEDS["stalker"], seconds: float = 60.0, rate_hz: float = 40.0,
            table: Table = (1.2, 0.8)) -> np.ndarray:
    """A stalker: follows at a distance behind the main and stops when it stops."""
    return demonstrate("stalker", seed, seconds, rate_hz, table)


def afraid(seed: int = SEEDS["afraid"], seconds: float = DURATION_S["afraid"],
           rate_hz: float = 40.0, table: Table = (1.2, 0.8)) -> np.ndarray:
    """Afraid: keeps away from the main and flees when it approaches."""
    return demonstrate("afraid", seed, seconds, rate_hz, table)
