"""Reactors of one main never jump on the table: a step goes round another character's body,
not through it (apart.no_deeper), and the shown pose slides from where it was shown, at most
the largest step's pace (engine.Reactor.update)."""

import math
from pathlib import Path

import numpy as np

from behaviors.puppet_master import apart, generation_kernel
from behaviors.puppet_master.behavior import Behavior
from behaviors.puppet_master.engine import Reactor
from tabletop import library

SIZE = 0.08     # metres: the reactors' bodies
TABLE = (0.0, 0.0, 0.6, 0.4)


def _shown(b: Behavior, n: int, compiled: bool, table: tuple[float, float, float, float],
           rate: float, start: tuple[float, float], goal: tuple[float, float],
           seconds: float) -> np.ndarray:
    """Shown positions (frames, n, 2) of ``n`` reactors of one main (each kept apart from the
    others' latest shown poses, as the plugin does) while the main walks from ``start`` to
    ``goal`` at 0.3 m/s and rests there."""
    rs = [Reactor(b, table, max_backlog=None) for _ in range(n)]
    for r in rs:
        r.compiled = compiled
    poses: list = [None] * n
    (mx, my), (gx, gy) = start, goal
    md = math.atan2(gy - my, gx - mx)
    out, t, dt = [], 0.0, 1.0 / rate
    while t < seconds:
        d = math.hypot(gx - mx, gy - my)
        if d > 0.3 * dt:
            mx, my = mx + 0.3 * dt * (gx - mx) / d, my + 0.3 * dt * (gy - my) / d
        for i, r in enumerate(rs):
            r.obstacles = [(p[0], p[1], SIZE) for j, p in enumerate(poses)
                           if j != i and p is not None]
            poses[i] = r.update(t, mx, my, md)
        out.append([p[:2] for p in poses])
        t += dt
    return np.array(out)


def _trained(name: str) -> Behavior:
    s = library.load_behavior(Path("behaviors/library") / name)
    return Behavior.train(s.demonstration, **s.parameters)


def _largest_move(b: Behavior, shown: np.ndarray, rate: float) -> float:
    """The largest one-frame move of any shown reactor over the largest step's pace."""
    move = np.hypot(*np.diff(shown, axis=0).transpose(2, 0, 1))
    return move.max() / (b.largest_step * b.params.rate_hz / rate)


def test_three_afraid_ones_in_a_corner_never_jump_and_keep_apart():
    # a 41 Hz main walks into the top-right corner where three afraid ones start: one went
    # through another's body at its largest step while its shown pose, pushed out of the
    # bodies from the step's pose, went round the other way, then jumped across (4.85x the
    # largest step's pace in one frame, least gap 0.138 of the size)
    b = _trained("afraid")
    args = (TABLE, 41.17, (0.3728, 0.2056), (0.4910, 0.38), 1.0)
    shown = _shown(b, 3, True, *args)
    assert np.array_equal(shown, _shown(b, 3, False, *args))         # Python == compiled
    assert _largest_move(b, shown, 41.17) <= 1.0 + 1e-9                  # measured 0.82
    gap = min(np.hypot(*(shown[:, i] - shown[:, j]).T).min()
              for i in range(3) for j in range(i + 1, 3))
    assert gap / SIZE >= 0.9, gap / SIZE                                 # measured 0.97


def test_the_shown_pose_slides_at_the_steps_pace_among_bodies():
    # three lovers beside a 35 Hz main on 2.0 x 1.2 m: pushed out of the others' bodies
    # afresh from the way between its steps, one shown pose moved 1.34x the largest step's
    # pace in a frame (1.86x with its steps round the bodies, apart.no_deeper)
    b = _trained("lover")
    args = ((0.0, 0.0, 2.0, 1.2), 34.8, (1.1547, 0.9562), (0.7931, 1.18), 1.0)
    shown = _shown(b, 3, True, *args)
    assert np.array_equal(shown, _shown(b, 3, False, *args))         # Python == compiled
    assert _largest_move(b, shown, 34.8) <= 1.0 + 1e-9                   # measured 1.0


def test_a_step_goes_round_a_body_not_into_it():
    # a step from beside a body at (0.3, 0.2) toward its centre ends on its disc, no deeper;
    # one from inside it (shoved there) ends no deeper than it began; Python == compiled
    bodies = [(0.3, 0.2, SIZE), (0.5, 0.2, SIZE)]
    rows, table = np.array(bodies), np.array(TABLE)
    for (rx, ry), (x, y) in [((0.39, 0.21), (0.38, 0.205)), ((0.35, 0.2), (0.34, 0.19)),
                             ((0.3, 0.28), (0.3, 0.27))]:
        got = apart.no_deeper(rx, ry, x, y, bodies, TABLE)
        assert got == generation_kernel.no_deeper(rx, ry, x, y, rows, table)
        for ox, oy, least in bodies:
            keep = min(least, math.hypot(rx - ox, ry - oy))
            assert math.hypot(got[0] - ox, got[1] - oy) >= keep - 1e-12
    # pressed toward a body along the table's top edge: slides along the edge
    got = apart.no_deeper(0.385, 0.4, 0.375, 0.4, [(0.3, 0.38, SIZE)], TABLE)
    assert got[1] == 0.4 and math.hypot(got[0] - 0.3, 0.02) >= SIZE - 1e-12
