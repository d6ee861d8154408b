"""The scripted designer's reactor hand, sample by sample (used by
:func:`behaviors.puppet_master.designers.demonstrate`).

The loop is sequential (each sample's hand reacts to where the last one left it, and a chasing
main hand to where the reactor is), so it runs on plain floats: the same operations in the same
order as on 2-vectors, hence the same floats bit for bit. A 2-vector numpy op costs ~1 us, a
float op ~30 ns. Norms are np.hypot's (math.hypot differs in the last bit on 0.6% of pairs);
where a norm is only compared with a bound, :func:`above` decides from the squared norm and
calls np.hypot only within a relative 1e-9 of the bound.

Positions in table metres, velocities in m/s, times in seconds, angles in radians.
"""

from __future__ import annotations

from typing import Protocol

import numpy as np

from behaviors.puppet_master.hand_motion import Policy, Table, Vec, _Seen, _turn_toward, _unit

CONTACT = 0.055  # metres between puck centres when two pucks touch
# the squared norm's rounding is a few 1e-16 relative and np.hypot's under one unit in the last
# place: outside (1 -+ 1e-9) of the squared bound the comparison is decided without it
_BELOW, _OVER = 1.0 - 1e-9, 1.0 + 1e-9


class MainHand(Protocol):
    """A main hand that reacts to the reactor: the main pose (x, y, dir) of sample ``i`` from
    the previous one and the reactor's position now."""

    def step(self, i: int, prev: np.ndarray, react: Vec) -> np.ndarray: ...


def above(x: float, y: float, most: float) -> bool:
    """``np.hypot(x, y) > most``, the same answer, np.hypot called only near the bound."""
    s, m2 = x * x + y * y, most * most
    if s < m2 * _BELOW:
        return False
    if s > m2 * _OVER:
        return True
    return float(np.hypot(x, y)) > most


def react(policy: Policy, main: np.ndarray, mv: np.ndarray, p0: Vec, look: float, lag: int,
          dt: float, top_speed: float, accel: float, table: Table, edge: float,
          chaser: MainHand | None) -> np.ndarray:
    """The reactor hand's poses (n, 3) x, y, look on ``main`` (n, 4) ``t, x, y, dir`` (its
    velocities ``mv`` (n, 2); both filled in as a ``chaser`` moves the main), from ``p0``
    looking ``look``, seeing the main ``lag`` samples late, at most ``top_speed`` m/s and
    ``accel`` m/s^2, stopped ``edge`` m inside the table's edges."""
    hypot, turn, seen = np.hypot, _turn_toward, _Seen
    w, h = table
    hi_x, hi_y, near = w - edge, h - edge, edge + 0.01
    far_x, far_y = w - edge - 0.01, h - edge - 0.01
    step_a, turn_most = accel * dt, 8.0 * dt
    touch = CONTACT * CONTACT * _OVER
    n = len(main)
    mp = main[:, 1:3]
    mpx, mpy, mdir = main[:, 1].tolist(), main[:, 2].tolist(), main[:, 3].tolist()
    speed = np.hypot(mv[:, 0], mv[:, 1]).tolist()    # as _Seen's own, element by element
    px, py = float(p0[0]), float(p0[1])
    vx = vy = 0.0
    rows = []
    for i in range(n):
        if chaser is not None and i > 0:
            main[i, 1:4] = chaser.step(i, main[i - 1], np.array((px, py)))
            mv[i] = (mp[i] - mp[i - 1]) / dt
            mpx[i], mpy[i], mdir[i] = main[i, 1:4].tolist()
            speed[i] = float(hypot(mv[i, 0], mv[i, 1]))
        j = i - lag if i > lag else 0
        v_des, look_des = policy(i * dt, np.array((px, py)), np.array((vx, vy)), look,
                                 seen(mp[j], mv[j], mdir[j], speed[j]))
        dx, dy = v_des.tolist()
        if above(dx, dy, top_speed):          # _limit
            f = top_speed / float(hypot(dx, dy))
            dx, dy = dx * f, dy * f
        # the hand stops at the table's edge
        if (px <= near and dx < 0) or (px >= far_x and dx > 0):
            dx = 0.0
        if (py <= near and dy < 0) or (py >= far_y and dy > 0):
            dy = 0.0
        ax, ay = dx - vx, dy - vy
        if above(ax, ay, step_a):
            f = step_a / float(hypot(ax, ay))
            ax, ay = ax * f, ay * f
        vx, vy = vx + ax, vy + ay
        px = min(max(px + vx * dt, edge), hi_x)          # np.clip's values
        py = min(max(py + vy * dt, edge), hi_y)
        gx, gy = px - mpx[i], py - mpy[i]
        if gx * gx + gy * gy < touch and float(hypot(gx, gy)) < CONTACT:
            # two pucks cannot overlap: pushed aside (rare: on the vectors, as it was written)
            gap, v = np.array((gx, gy)), np.array((vx, vy))
            d = float(hypot(gx, gy))
            p = mp[i] + (gap / d if d > 1e-9 else np.array([1.0, 0.0])) * CONTACT
            v = v - min(0.0, float(np.dot(v, _unit(gap)))) * _unit(gap)
            px, py, vx, vy = float(p[0]), float(p[1]), float(v[0]), float(v[1])
        look = turn(look, look_des, turn_most)
        rows.append((px, py, look))
    return np.array(rows).reshape(n, 3)
