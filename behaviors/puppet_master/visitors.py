"""Main paths the shipped demonstrations never saw: scripted visitors for fidelity checks.

Each is a main puck's path (n, 4) ``t, x, y, dir`` (seconds, table metres, radians) at its own
sampling rate, seeded and reproducible bit for bit.
"""

from __future__ import annotations

import math

import numpy as np

from behaviors.puppet_master.designers import (Table, _limit, _tremor, _turn_toward, _unit,
                                               designer_main_path)
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
        p = np.clip(p + v * dt, 0.05, (w - 0.05, h - 0.05))
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
