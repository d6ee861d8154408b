"""A puck's trail keeps its recent path: points at least TRAIL_STEP_M apart, none older than
TRAIL_S, at most its limit, oldest first, the same over long runs as a bounded queue of points."""

from __future__ import annotations

import collections
import math
import random

import numpy as np

from tabletop.drawing.life import TRAIL_S, TRAIL_STEP_M, Traces
from tabletop.frames import Puck


def test_trails_keep_the_recent_path_within_their_limit_over_long_runs():
    rng = random.Random(5)
    traces = Traces()
    model: dict[int, collections.deque] = {}
    pos = {i: [rng.random(), rng.random()] for i in range(4)}
    t, longest = 0.0, 0
    for _ in range(1200):
        t += 0.2 if rng.random() < 0.01 else 0.002          # now and then a pause
        here = []
        for i, p in pos.items():
            p[0] += rng.gauss(0.0, 0.03 if i < 2 else 0.002)   # fast and slow pucks
            p[1] += rng.gauss(0.0, 0.03)
            if i == 0 or rng.random() < 0.9:                   # the others leave now and then
                here.append(Puck(id=i, x=p[0], y=p[1], angle=0.0))
        drawn = traces.update(t, here)
        for gone in set(model) - set(traces.traces):          # left long ago: forgotten
            del model[gone]
        for p in here:
            q = model.setdefault(p.id, collections.deque(maxlen=64))
            if not q or math.hypot(p.x - q[-1][0], p.y - q[-1][1]) >= TRAIL_STEP_M:
                q.append((p.x, p.y, t))
        for tr, _, _ in drawn:
            q = model[tr.puck.id]
            while q and t - q[0][2] > TRAIL_S:
                q.popleft()
            pts = tr.path.points()
            assert np.array_equal(pts, np.array(q, dtype=np.float64).reshape(-1, 3))
            assert len(pts) <= 64 and np.all(t - pts[:, 2] <= TRAIL_S)
            assert np.all(np.diff(pts[:, 2]) > 0)
            longest = max(longest, len(pts))
    assert longest == 64                                       # the limit was reached
