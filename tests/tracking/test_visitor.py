"""The scripted visitor: reproducible, on the table, human-like speeds, pauses and turns."""

import numpy as np
import pytest

from tracking.visitor import ScriptedVisitor

TABLE = (1.2, 0.8)
RATE = 60.0


def path(seed: int, seconds: float = 60.0, puck: int = 1) -> np.ndarray:
    v = ScriptedVisitor(TABLE, (1, 2), seed=seed)
    ts = np.arange(0.0, seconds, 1.0 / RATE)
    return np.array([[x, y, a] for t in ts for pid, x, y, a in v.poses(t) if pid == puck])


def test_same_seed_same_path_in_any_query_order():
    a = ScriptedVisitor(TABLE, seed=5)
    b = ScriptedVisitor(TABLE, seed=5)
    late = b.poses(40.0)
    assert a.poses(10.0) == b.poses(10.0)
    assert a.poses(40.0) == late
    assert ScriptedVisitor(TABLE, seed=6).poses(10.0) != a.poses(10.0)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_motion_is_human_like(seed):
    p = path(seed)
    assert (p[:, 0] >= 0).all() and (p[:, 0] <= TABLE[0]).all()
    assert (p[:, 1] >= 0).all() and (p[:, 1] <= TABLE[1]).all()
    speed = np.hypot(*np.diff(p[:, :2], axis=0).T) * RATE
    assert 0.05 < speed.mean() < 0.3  # m/s
    assert speed.max() < 0.8
    assert 0.1 < (speed < 0.005).mean() < 0.5  # pauses, but mostly moving
    turn = np.abs(np.angle(np.exp(1j * np.diff(p[:, 2])))) * RATE
    assert np.percentile(turn, 99) < 6.0  # rad/s: no snapping round
    accel = np.abs(np.diff(speed)) * RATE
    assert np.percentile(accel, 99) < 3.0  # m/s^2: smooth starts and stops


def test_heading_follows_the_direction_of_travel():
    p = path(3)
    d = np.diff(p[:, :2], axis=0)
    moving = np.hypot(*d.T) * RATE > 0.1
    travel = np.arctan2(d[moving, 1], d[moving, 0])
    err = np.abs(np.angle(np.exp(1j * (p[1:][moving, 2] - travel))))
    assert np.median(err) < 0.2
