"""Reactors of one main squeezed with its disc into a corner: the bodies are kept apart before
the main's disc (step_detail's order), and three that start on one spot start apart."""

import math
from pathlib import Path

import numpy as np

from behaviors.puppet_master import apart, generation_kernel
from behaviors.puppet_master.behavior import Behavior
from behaviors.puppet_master.engine import Reactor
from tabletop import library

SIZE = 0.08     # metres: the reactors' bodies


def _together(name: str, n: int, table: tuple[float, float, float, float], rate: float,
              start: tuple[float, float], goal: tuple[float, float], seconds: float) -> float:
    """Least gap between ``n`` reactors of one main (each kept apart from the others' latest
    displayed poses, as the plugin does) while the main walks from ``start`` to ``goal`` at
    0.3 m/s and rests there; over SIZE."""
    s = library.load_behavior(Path("behaviors/library") / name)
    b = Behavior.train(s.demonstration, **s.parameters)
    rs = [Reactor(b, table, max_backlog=None) for _ in range(n)]
    poses: list = [None] * n
    (mx, my), (gx, gy) = start, goal
    least, t, dt = math.inf, 0.0, 1.0 / rate
    while t < seconds:
        d = math.hypot(gx - mx, gy - my)
        if d > 0.3 * dt:
            mx, my = mx + 0.3 * dt * (gx - mx) / d, my + 0.3 * dt * (gy - my) / d
        md = math.atan2(gy - start[1], gx - start[0])
        for i, r in enumerate(rs):
            r.obstacles = [(p[0], p[1], SIZE) for j, p in enumerate(poses)
                           if j != i and p is not None]
            poses[i] = r.update(t, mx, my, md)
        least = min([least] + [math.hypot(poses[i][0] - poses[j][0], poses[i][1] - poses[j][1])
                               for i in range(n) for j in range(i + 1, n)])
        t += dt
    return least / SIZE


def test_two_reactors_squeezed_into_a_corner_keep_their_bodies_apart():
    # 0.6 x 0.4 m table, a 36 Hz main walking into the top-left corner where two afraid ones
    # start: with the main's disc visited last it pressed one into the other (least gap 0.30
    # of the size); the bodies visited last keep them apart
    got = _together("afraid", 2, (0.0, 0.0, 0.6, 0.4), 36.4, (0.155, 0.255), (0.022, 0.378),
                    0.8)
    assert got >= 0.9                                        # measured 1.0


def test_three_reactors_starting_in_a_corner_start_apart():
    # 3.0 x 0.5 m, the main near the bottom-right corner: the third started on the first's
    # spot, pushed from one disc onto the other and back on every pass (gap 0)
    got = _together("lover", 3, (0.0, 0.0, 3.0, 0.5), 46.8, (2.883, 0.124), (2.95, 0.05), 0.5)
    assert got >= 0.9                                        # measured 0.974


def test_a_third_body_on_the_first_goes_where_neither_disc_is():
    # the first two of three in the bottom-right corner of a 3.0 x 0.5 m table; the third on
    # the first: out along an axis that ends in neither disc (+y), Python == compiled
    table = (0.0, 0.0, 3.0, 0.5)
    discs = [(3.0, 0.0, SIZE), (2.92, 0.0, SIZE)]
    got = apart.keep_apart(3.0, 0.0, discs, table)
    assert got == generation_kernel.keep_apart(3.0, 0.0, np.array(discs), np.array(table))
    assert min(math.hypot(got[0] - x, got[1] - y) for x, y, _ in discs) >= SIZE - 1e-12
