"""Reactors of one table stepped together (behaviors.puppet_master.together): each plans
against the others' previous shown poses, then the ends of their steps and their shown poses
move apart jointly, each by its share."""

import math
import random

import numpy as np

from behaviors.puppet_master.engine import Reactor
from behaviors.puppet_master.together import apart_together, update_together
from tests.puppet_master.test_pm_round_bodies import SIZE, _trained


def test_apart_together_moves_each_by_its_share_whatever_the_order():
    table = (0.0, 0.0, 1.0, 1.0)
    least = [[0.08] * 2] * 2
    xy = [[0.40, 0.5], [0.46, 0.5]]
    apart_together(xy, least, [math.inf] * 2, table)
    assert np.allclose(xy, [[0.39, 0.5], [0.47, 0.5]])             # 1 cm each
    xy = [[0.0, 0.5], [0.06, 0.5]]                                  # the first at the edge
    apart_together(xy, least, [math.inf] * 2, table)
    assert np.allclose(xy, [[0.0, 0.5], [0.08, 0.5]])
    xy = [[0.40, 0.5], [0.46, 0.5]]                                 # the first has no room
    apart_together(xy, least, [0.0, math.inf], table)
    assert np.allclose(xy, [[0.40, 0.5], [0.48, 0.5]])
    # five bodies in a heap: apart, and the same places whatever order they are given in
    rng = random.Random(3)
    heap = [[0.5 + rng.uniform(-0.03, 0.03), 0.5 + rng.uniform(-0.03, 0.03)] for _ in range(5)]
    least = [[0.08] * 5] * 5
    done = [p[:] for p in heap]
    apart_together(done, least, [math.inf] * 5, table, passes=64)
    gaps = [math.dist(done[i], done[j]) for i in range(5) for j in range(i + 1, 5)]
    assert min(gaps) >= 0.08 * 0.99, min(gaps)                      # measured 0.0800
    for _ in range(3):
        order = list(range(5))
        rng.shuffle(order)
        again = [heap[k][:] for k in order]
        apart_together(again, least, [math.inf] * 5, table, passes=64)
        assert all(again[i] == done[k] for i, k in enumerate(order))


def _together(b, compiled: bool, table, rate, start, goal, speed, seconds):
    """Shown poses (frames, 3, 2) and generation poses of three reactors of one main stepped
    together while the main walks from ``start`` to ``goal`` at ``speed`` m/s."""
    rs = [Reactor(b, table, max_backlog=None) for _ in range(3)]
    for r in rs:
        r.compiled = compiled
    (mx, my), (gx, gy) = start, goal
    md = math.atan2(gy - my, gx - mx)
    shown, gen, t, dt = [], [], 0.0, 1.0 / rate
    while t < seconds:
        d = math.hypot(gx - mx, gy - my)
        if d > speed * dt:
            mx, my = mx + speed * dt * (gx - mx) / d, my + speed * dt * (gy - my) / d
        poses = update_together(rs, t, [(mx, my, md)] * 3, [SIZE] * 3, table)
        shown.append([p[:2] for p in poses])
        gen.append([r.pose[:2] for r in rs])
        t += dt
    return np.array(shown), np.array(gen)


def test_three_lovers_keep_apart_and_their_shown_poses_follow_their_steps():
    # three lovers of a 33 Hz main on 1.2 x 0.8 m: stepped in turn, each against the others'
    # latest shown poses, one's shown pose fell 7.01 largest steps behind its generation pose
    # (its step went round a body the shown pose could not pass)
    b = _trained("lover")
    args = ((0.0, 0.0, 1.2, 0.8), 32.59, (0.7634, 0.5855), (1.0569, 0.3636), 0.406, 2.0)
    shown, gen = _together(b, True, *args)
    py_shown, py_gen = _together(b, False, *args)
    assert np.array_equal(shown, py_shown) and np.array_equal(gen, py_gen)  # Python == compiled
    lag = np.hypot(*(shown - gen).transpose(2, 0, 1)).max() / b.largest_step
    assert lag <= 1.5, lag                                               # measured 1.20
    gap = min(np.hypot(*(shown[:, i] - shown[:, j]).T).min()
              for i in range(3) for j in range(i + 1, 3))
    assert gap / SIZE >= 0.95, gap / SIZE                                # measured 1.00
    move = np.hypot(*np.diff(shown, axis=0).transpose(2, 0, 1)).max()
    assert move <= b.largest_step * b.params.rate_hz / 32.59 + 1e-9      # at the steps' pace
