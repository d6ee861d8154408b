"""Seeded demonstration and input generators for the Puppet Master tests and benchmark.

A main path is a puck pushed around a table (metres) by a steering hand: it heads for random
spots with a limited turn rate and changing speed, pauses, and optionally reverses suddenly.
Reactors are scripted controllers of that path: follow-behind, keep-away, circling, and a
shaky variant with a hand's wobble. Arrays: main (n, 4) t, x, y, dir; demo (n, 7).
"""

from __future__ import annotations

import functools
import math

import numpy as np

from behaviors.puppet_master import fidelity, visitors
from behaviors.puppet_master.engine import Behavior
from tabletop import examples, library
from tabletop.frames import wrap_angle

TABLE = (1.6, 1.0)


class Steerer:
    """A hand pushing the main puck: heads for spots with a limited turn rate and changing
    speed, pauses now and then, and (optionally) reverses suddenly. Seeded."""

    def __init__(self, seed: int, rate_hz: float = 60.0, table: tuple[float, float] = TABLE,
                 stops: bool = True, reversals: bool = False,
                 speed: tuple[float, float] = (0.08, 0.3), margin: float = 0.2) -> None:
        self.rng = np.random.default_rng(seed)
        self.w, self.h = table
        self.dt = 1.0 / rate_hz
        self.stops, self.reversals, self.speed, self.margin = stops, reversals, speed, margin
        self.pos = np.array([self.w / 2, self.h / 2]) + self.rng.uniform(-0.1, 0.1, 2)
        self.heading = float(self.rng.uniform(-math.pi, math.pi))
        self.spot = self.new_spot()
        self.v_target = float(self.rng.uniform(*speed))
        self.v = 0.0
        self.pause = 0.0

    def new_spot(self) -> np.ndarray:
        m = self.margin
        return np.array([self.rng.uniform(m, self.w - m), self.rng.uniform(m, self.h - m)])

    def step(self, chase: np.ndarray | None = None) -> None:
        """Advance one sample; ``chase`` (x, y) replaces the current spot when given."""
        rng, dt, m = self.rng, self.dt, self.margin
        if self.pause > 0:
            self.pause -= dt
            self.v = 0.0
            return
        if self.stops and rng.random() < 0.12 * dt:
            self.pause = float(rng.uniform(0.5, 1.5))
            return
        if self.reversals and rng.random() < 0.1 * dt:
            self.heading = wrap_angle(self.heading + math.pi)
            self.spot = self.pos + 0.5 * np.array([math.cos(self.heading), math.sin(self.heading)])
            self.spot = np.clip(self.spot, m, [self.w - m, self.h - m])
        if rng.random() < 0.3 * dt:
            self.v_target = float(rng.uniform(*self.speed))
        spot = self.spot if chase is None else np.asarray(chase, dtype=float)
        to = spot - self.pos
        if chase is None and np.hypot(*to) < 0.08:
            self.spot = self.new_spot()
            to = self.spot - self.pos
        want = math.atan2(to[1], to[0])
        turn = float(np.clip(wrap_angle(want - self.heading), -2.5 * dt, 2.5 * dt))
        self.heading = wrap_angle(self.heading + turn)
        self.v += float(np.clip(self.v_target - self.v, -0.8 * dt, 0.8 * dt))
        heading = np.array([math.cos(self.heading), math.sin(self.heading)])
        self.pos = self.pos + self.v * dt * heading
        self.pos = np.clip(self.pos, 0.05, [self.w - 0.05, self.h - 0.05])


def main_path(seed: int, duration: float, rate_hz: float = 60.0, table: tuple[float, float] = TABLE,
              stops: bool = True, reversals: bool = False, speed: tuple[float, float] = (0.08, 0.3),
              margin: float = 0.2) -> np.ndarray:
    """A main puck's path (n, 4): t, x, y, look = heading (radians)."""
    s = Steerer(seed, rate_hz, table, stops, reversals, speed, margin)
    n = int(round(duration * rate_hz)) + 1
    out = np.empty((n, 4))
    for i in range(n):
        out[i] = (i * s.dt, s.pos[0], s.pos[1], s.heading)
        s.step()
    return out


def _look_along(prev_look: float, step: np.ndarray, rate_hz: float) -> float:
    if np.hypot(*step) * rate_hz < 0.01:
        return prev_look
    return math.atan2(step[1], step[0])


def follow_behind(main: np.ndarray, distance: float = 0.3, gain: float = 6.0,
                  max_speed: float = 0.6, wobble: float = 0.0,
                  wobble_hz: float = 6.0) -> np.ndarray:
    """Demo (n, 7): a reactor chasing the point ``distance`` behind the main's look direction.
    ``wobble`` (radians) turns each step by a sinusoid: a shaky hand."""
    dt = float(main[1, 0] - main[0, 0])
    rate = 1.0 / dt
    r = main[0, 1:3] - distance * np.array([math.cos(main[0, 3]), math.sin(main[0, 3])])
    look = float(main[0, 3])
    out = np.empty((main.shape[0], 7))
    for i, (t, mx, my, md) in enumerate(main):
        out[i] = (t, mx, my, md, r[0], r[1], look)
        target = np.array([mx, my]) - distance * np.array([math.cos(md), math.sin(md)])
        step = (target - r) * min(1.0, gain * dt)
        sp = np.hypot(*step)
        if sp > max_speed * dt:
            step *= max_speed * dt / sp
        if wobble:
            a = wobble * math.sin(2 * math.pi * wobble_hz * t)
            c, s = math.cos(a), math.sin(a)
            step = np.array([c * step[0] - s * step[1], s * step[0] + c * step[1]])
        r = r + step
        look = _look_along(look, step, rate)
    return out


def _keep_away_step(r: np.ndarray, m: np.ndarray, radius: float, gain: float, max_speed: float,
                    table: tuple[float, float], dt: float,
                    prev: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """One step of the keep-away hand: (new position, step); ``prev`` is the previous step
    (the hand keeps its escape direction rather than dithering between two)."""
    w, h = table
    d = r - m
    dist = float(np.hypot(*d))
    step = np.zeros(2)
    if dist < radius + 0.1:
        u = d / max(dist, 1e-9)
        # the hand sees the edges coming: of 32 headings, the one most away from the main
        # among those that leave 0.3 m of room before an edge
        ang = np.linspace(-math.pi, math.pi, 32, endpoint=False)
        dirs = np.column_stack([np.cos(ang), np.sin(ang)])
        ahead = r + 0.3 * dirs
        room = ((ahead[:, 0] > 0.08) & (ahead[:, 0] < w - 0.08)
                & (ahead[:, 1] > 0.08) & (ahead[:, 1] < h - 0.08))
        score = dirs @ u
        p = float(np.hypot(*prev))
        if p > 1e-12:
            score = score + 0.7 * (dirs @ (prev / p))
        if room.any():
            score = np.where(room, score, -np.inf)
        else:
            score = dirs @ (np.array([w / 2, h / 2]) - r)
        flee = dirs[int(np.argmax(score))]
        sp = min(max_speed, gain * (radius + 0.1 - dist))
        step = flee * sp * dt
    new = np.clip(r + step, 0.05, [w - 0.05, h - 0.05])
    return new, new - r


def keep_away(seed: int, duration: float, rate_hz: float = 60.0, radius: float = 0.45,
              gain: float = 5.0, max_speed: float = 0.7, table: tuple[float, float] = TABLE,
              chase: float = 0.6) -> np.ndarray:
    """Demo (n, 7): the main hand wanders or (a share ``chase`` of the time) chases the reactor,
    which backs off whenever the main comes closer than ``radius``, sliding along the table's
    edges when cornered, and otherwise waits facing the main."""
    s = Steerer(seed, rate_hz, table, stops=True, reversals=True)
    rng = np.random.default_rng(seed + 1000)
    dt = s.dt
    n = int(round(duration * rate_hz)) + 1
    r = np.clip(s.pos + 0.5 * np.array([math.cos(s.heading), math.sin(s.heading)]),
                0.05, [table[0] - 0.05, table[1] - 0.05])
    look = wrap_angle(s.heading + math.pi)
    chasing = False
    step = np.zeros(2)
    out = np.empty((n, 7))
    for i in range(n):
        m = s.pos.copy()
        out[i] = (i * dt, m[0], m[1], s.heading, r[0], r[1], look)
        if rng.random() < dt / 3.0:
            chasing = rng.random() < chase
        s.step(r if chasing else None)
        r, step = _keep_away_step(r, s.pos, radius, gain, max_speed, table, dt, step)
        if np.hypot(*step) / dt >= 0.01:
            look = math.atan2(step[1], step[0])
        else:
            look = math.atan2(s.pos[1] - r[1], s.pos[0] - r[0])
    return out


def circling(main: np.ndarray, radius: float = 0.25, omega: float = 2.0,
             table: tuple[float, float] = TABLE) -> np.ndarray:
    """Demo (n, 7): a reactor circling the main counter-clockwise at ``omega`` rad/s."""
    dt = float(main[1, 0] - main[0, 0])
    rate = 1.0 / dt
    out = np.empty((main.shape[0], 7))
    theta = float(main[0, 3]) + math.pi
    look = theta + math.pi / 2
    prev = None
    for i, (t, mx, my, md) in enumerate(main):
        r = np.array([mx + radius * math.cos(theta), my + radius * math.sin(theta)])
        if prev is not None:
            look = _look_along(look, r - prev, rate)
        out[i] = (t, mx, my, md, r[0], r[1], wrap_angle(look))
        prev = r
        theta += omega * dt
    return out


def shipped(name: str) -> Behavior:
    """The shipped behaviour ``name`` (examples' library), trained with its stored parameters."""
    stored = library.load_behavior(examples.DEFAULT_OUT / name)
    return Behavior.train(stored.demonstration, **stored.parameters)


def chased(b: Behavior, seed: int, seconds: float = 40.0) -> tuple[np.ndarray, dict]:
    """``b`` chased by the unseen visitor of ``seed`` for ``seconds`` on the example table:
    the generated rows (t, x, y, dir) and bench/fidelity.py's figures of them."""
    table = (0.0, 0.0, *examples.TABLE)
    main, rows = fidelity.pursue(b, visitors.pursuer(seed, seconds, examples.TABLE), table)
    f = fidelity.figures(fidelity.main_on_grid(main, rows[:, 0]), rows[:, 1:],
                         b.params.rate_hz, b.turn_limit, table)
    return rows, f


@functools.cache
def _unseen(seed: int, seconds: float, table: tuple[float, float]) -> dict[str, np.ndarray]:
    return visitors.unseen_main_paths(seed, seconds, table)


def unseen_main_paths(seed: int = 0, seconds: float = 40.0,
                      table: tuple[float, float] = examples.TABLE) -> dict[str, np.ndarray]:
    """visitors.unseen_main_paths ({name: (n, 4) ``t, x, y, dir``}, ``seconds`` s on a
    ``table`` m table), made once a process for each seed, length and table (0.08-0.09 CPU s
    each, asked for 84 times by 26 seeds in these tests); every call returns fresh arrays, so
    no test's edit reaches the next."""
    return {k: v.copy() for k, v in _unseen(seed, float(seconds), tuple(table)).items()}
