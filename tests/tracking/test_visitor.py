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


def test_gesture_performer_draws_its_gestures_at_the_chosen_speeds():
    from tracking.visitor import GesturePerformer

    ts = np.linspace(0.0, 2.0, 41)
    circle = np.column_stack([ts, 0.1 * np.cos(np.pi * ts) - 0.1, 0.1 * np.sin(np.pi * ts)])
    line = np.column_stack([ts, 0.15 * ts, np.zeros_like(ts)])
    p = GesturePerformer([circle, line], home=(0.5, 0.4), seed=3, speed=(0.5, 2.0))
    q = GesturePerformer([circle, line], home=(0.5, 0.4), seed=3, speed=(0.5, 2.0))
    assert p.pose(30.0) == q.pose(30.0) and p.pose(3.0) == q.pose(3.0)  # any query order
    assert len(p.performed) >= 6
    assert {g for _, _, g, _ in p.performed} == {0, 1}
    for t0, t1, g, speed in p.performed:
        assert 0.5 <= speed <= 2.0 and t1 - t0 == pytest.approx(2.0 / speed)
        x0, y0, _ = p.pose(t0 + 1e-9)
        assert (x0, y0) == pytest.approx((0.5, 0.4), abs=0.03)  # starts from home
        xm, ym, _ = p.pose((t0 + t1) / 2)
        shape = (circle if g == 0 else line)[20]
        assert (xm - x0, ym - y0) == pytest.approx((shape[1], shape[2]), abs=1e-9)
