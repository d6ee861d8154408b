"""Main paths the shipped demonstrations never saw: scripted visitors for fidelity checks.

Each is a main puck's path (n, 4) ``t, x, y, dir`` (seconds, table metres, radians) at its own
sampling rate, seeded and reproducible bit for bit. A :class:`Pursuer` is a visitor whose path
depends on the reactor: it goes after it (a closed loop, played one sample at a time).
"""

from __future__ import annotations

import math

import numpy as np

from behaviors.puppet_master.designers import designer_main_path
from behaviors.puppet_master.hand_motion import Table, _limit, _tremor, _turn_toward, _unit
from tabletop.frames import wrap_angle, wrap_angles


def loops_and_spins(seed: int, seconds: float = 40.0, rate_hz: float = 40.0,
                    table: Table = (1.2, 0.8), margin: float = 0.25) -> np.ndarray:
    """A visitor drawing loops with the main puck: (n, 4) ``t, x, y, dir`` (s, m, m, rad).

    Circles of 0.1-0.2 m radius in either sense at 0.1-0.3 m/s around spots on the table, now
    and then a stop (0.8-2 s) spinning the puck in place at 1-3 rad/s or holding it still, and
    a glide to the next spot. The puck looks where it goes and keeps its look when still.
    """
    rng = np.random.default_rng([seed, 7])
    w, h = table
    dt = 1.0 / rate_hz
    n = int(round(seconds * rate_hz))
    lo, hi = np.array([margin, margin]), np.array([w - margin, h - margin])
    p = rng.uniform(lo, hi)
    look = float(rng.uniform(-math.pi, math.pi))
    out = np.empty((n, 4))
    mode, left = "glide", 0.0
    goal, speed, sense, spin, centre = rng.uniform(lo, hi), 0.2, 1.0, 0.0, p.copy()
    v = np.zeros(2)
    for i in range(n):
        left -= dt
        if left <= 0.0:
            mode = str(rng.choice(["loop", "loop", "glide", "stop"]))
            left = float(rng.uniform(0.8, 2.0)) if mode == "stop" else float(rng.uniform(2.0, 5.0))
            speed = float(rng.uniform(0.1, 0.3))
            sense = float(rng.choice([-1.0, 1.0]))
            spin = float(rng.choice([0.0, 1.0, -1.0]) * rng.uniform(1.0, 3.0))
            goal = rng.uniform(lo, hi)
            radius = float(rng.uniform(0.1, 0.2))
            centre = np.clip(p + radius * np.array([-math.sin(look), math.cos(look)]) * sense,
                             lo, hi)
        if mode == "stop":
            v_des = np.zeros(2)
            look = wrap_angle(look + spin * dt)
        elif mode == "loop":
            r = p - centre
            tangent = sense * np.array([-r[1], r[0]])
            v_des = _unit(tangent) * speed + 2.0 * (0.15 - float(np.hypot(*r))) * _unit(r)
        else:
            to = goal - p
            v_des = _unit(to) * speed * min(1.0, float(np.hypot(*to)) / 0.1)
        v = v + _limit(v_des - v, 1.5 * dt)
        p = np.minimum(np.maximum(p + v * dt, 0.05), (w - 0.05, h - 0.05))   # as np.clip
        if float(np.hypot(*v)) > 0.04:
            look = _turn_toward(look, math.atan2(v[1], v[0]), 8.0 * dt)
        out[i] = (i * dt, p[0], p[1], look)
    return out


def unseen_main_paths(seed: int = 0, seconds: float = 40.0,
                      table: Table = (1.2, 0.8)) -> dict[str, np.ndarray]:
    """Main paths no shipped demonstration was made on, for fidelity checks: {name: (n, 4)
    ``t, x, y, dir``}. A slow wanderer with long pauses sampled at 30 Hz, a fast hand that
    often reverses at 60 Hz, and loops with spins in place at 45 Hz; each with a camera's
    jitter (0.8 mm, 0.01 rad)."""
    paths = {
        "slow_pauses_30hz": designer_main_path(1000 + seed, seconds, 30.0, table,
                                               speed_range=(0.05, 0.18), reversals_per_s=0.03),
        "fast_reversals_60hz": designer_main_path(2000 + seed, seconds, 60.0, table,
                                                  speed_range=(0.2, 0.45), reversals_per_s=0.3),
        "loops_spins_45hz": loops_and_spins(3000 + seed, seconds, 45.0, table),
    }
    shake = np.random.default_rng([seed, 9])
    for name, m in paths.items():
        rate = 1.0 / float(m[1, 0] - m[0, 0])
        for col, rms in ((1, 0.0008), (2, 0.0008), (3, 0.01)):
            m[:, col] = m[:, col] + _tremor(shake, len(m), rate, 3.0, 10.0, rms)
        m[:, 3] = wrap_angles(m[:, 3])
        m[:, 1] = np.clip(m[:, 1], 0.0, table[0])
        m[:, 2] = np.clip(m[:, 2], 0.0, table[1])
    return paths


class Pursuer:
    """A visitor playing with a reactor by going after it: the main puck's path is made one
    sample at a time from where the reactor is now (a closed loop; seeded, reproducible).

    The hand switches between chasing the reactor (1.5-4 s at 0.12-0.4 m/s, steering toward
    the reactor's current position at up to 3 rad/s and easing off within 0.1 m of it),
    pausing (0.5-2 s, the puck held still or spun in place at up to 2 rad/s), pulling back
    away from the reactor (0.5-1.2 s at 0.1-0.25 m/s) and wandering to a spot (1.5-3 s);
    chasing is drawn three times as often as each of the others. Accelerations are a hand's
    (1.2 m/s^2), the puck looks where it goes (6 rad/s) and keeps its look when still, and the
    camera adds its jitter (0.8 mm, 0.01 rad) to what is reported. Mode draws do not depend on
    the reactor, so the same seed gives the same schedule whatever it reacts to.

    ``times``: (n,) sample times (s); :meth:`first` the first pose; :meth:`step` the pose of
    sample ``i`` >= 1 given the reactor's position now (x, y, dir as an array).
    """

    MODES = ("chase", "chase", "pause", "pull_back", "wander")
    CHASE_S, CHASE_MPS, STEER_RADPS = (1.5, 4.0), (0.12, 0.35), 3.0

    def __init__(self, seed: int, seconds: float = 40.0, rate_hz: float = 50.0,
                 table: Table = (1.2, 0.8), margin: float = 0.15) -> None:
        self.rate_hz, self.table = rate_hz, table
        n = int(round(seconds * rate_hz))
        self.times = np.arange(n) / rate_hz
        self.rng = np.random.default_rng([seed, 11])
        self.lo, self.hi = np.array([margin, margin]), np.array([table[0] - margin,
                                                                  table[1] - margin])
        shake = np.random.default_rng([seed, 12])
        self.jitter = [_tremor(shake, n, rate_hz, 3.0, 10.0, rms) for rms in (0.0008, 0.0008,
                                                                             0.01)]
        self.p = self.rng.uniform(self.lo, self.hi)
        self.v = np.zeros(2)
        self.look = float(self.rng.uniform(-math.pi, math.pi))
        self.heading = self.look
        self.mode, self.left, self.speed, self.spin = "pause", 0.5, 0.0, 0.0
        self.goal = self.p.copy()

    def _observed(self, i: int) -> np.ndarray:
        w, h = self.table
        return np.array([min(max(self.p[0] + self.jitter[0][i], 0.0), w),
                         min(max(self.p[1] + self.jitter[1][i], 0.0), h),
                         wrap_angle(self.look + self.jitter[2][i])])

    def first(self) -> np.ndarray:
        """The first pose (x, y, dir)."""
        return self._observed(0)

    def _next_mode(self) -> None:
        rng = self.rng
        self.mode = str(rng.choice(self.MODES))
        self.left = float({"chase": rng.uniform(*self.CHASE_S), "pause": rng.uniform(0.5, 2.0),
                           "pull_back": rng.uniform(0.5, 1.2),
                           "wander": rng.uniform(1.5, 3.0)}[self.mode])
        self.speed = float(rng.uniform(*self.CHASE_MPS) if self.mode == "chase" else
                           rng.uniform(0.1, 0.25))
        self.spin = float(rng.choice([0.0, 1.0, -1.0]) * rng.uniform(0.5, 2.0))
        self.goal = rng.uniform(self.lo, self.hi)

    def step(self, i: int, prev: np.ndarray | None, react: np.ndarray) -> np.ndarray:
        """The pose (x, y, dir) of sample ``i`` with the reactor at ``react`` (x, y, ...) now;
        ``prev`` (the previous reported pose) is not needed: the hand keeps its own state."""
        dt = 1.0 / self.rate_hz
        self.left -= dt
        if self.left <= 0.0:
            self._next_mode()
        to = np.asarray(react[:2], dtype=float) - self.p
        d = float(np.hypot(*to))
        if self.mode == "chase":
            want = math.atan2(to[1], to[0])
            self.heading = _turn_toward(self.heading, want, self.STEER_RADPS * dt)
            v_des = np.array([math.cos(self.heading), math.sin(self.heading)]) * (
                self.speed * min(1.0, max(0.0, d - 0.06) / 0.1))
        elif self.mode == "pull_back":
            v_des = -_unit(to) * self.speed
        elif self.mode == "wander":
            g = self.goal - self.p
            v_des = _unit(g) * self.speed * min(1.0, float(np.hypot(*g)) / 0.1)
        else:
            v_des = np.zeros(2)
            self.look = wrap_angle(self.look + self.spin * dt)
        self.v = self.v + _limit(v_des - self.v, 1.2 * dt)
        w, h = self.table
        self.p = np.minimum(np.maximum(self.p + self.v * dt, 0.05), (w - 0.05, h - 0.05))
        if float(np.hypot(*self.v)) > 0.04:
            self.look = _turn_toward(self.look, math.atan2(self.v[1], self.v[0]), 6.0 * dt)
            if self.mode != "chase":
                self.heading = math.atan2(self.v[1], self.v[0])
        return self._observed(i)


PURSUIT = "pursuit_50hz"


def pursuer(seed: int = 0, seconds: float = 40.0, table: Table = (1.2, 0.8)) -> Pursuer:
    """The unseen pursuing visitor of path set ``seed`` (fresh: one per closed loop), sampled
    at 50 Hz: the path a character shown by chasing it (designers.CHASED) is checked on beside
    :func:`unseen_main_paths`."""
    return Pursuer(4000 + seed, seconds, 50.0, table)
