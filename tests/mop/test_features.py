"""Puck path features, and puck gestures recognised end to end."""

import math

import numpy as np
import pytest

from behaviors.mop.features import PATH_FEATURE_NAMES, PathFeatures
from behaviors.mop.follower import ActionFollower


def test_a_straight_stroke_gives_offset_and_speed():
    pf = PathFeatures()
    v, rate = 0.2, 60.0
    out = [pf.step(0.5 + v * i / rate, 0.3, 0.4, 10.0 + i / rate) for i in range(61)]
    last = out[-1]
    assert PATH_FEATURE_NAMES == ("dx", "dy", "heading", "speed") and last.shape == (4,)
    assert last[0] == pytest.approx(v, abs=1e-9) and abs(last[1]) < 1e-12
    assert last[2] == pytest.approx(0.0, abs=1e-12)
    assert last[3] == pytest.approx(v, rel=0.01)


def test_heading_counts_whole_turns_and_rotate_makes_features_rotation_invariant():
    pf = PathFeatures()
    angles = np.linspace(0.0, 3 * 2 * math.pi, 300)
    for i, a in enumerate(angles):
        f = pf.step(0.2, 0.2, math.remainder(a, 2 * math.pi), i / 60)
    assert f[2] == pytest.approx(6 * math.pi, abs=1e-9)

    def stroke(theta):
        p = PathFeatures(rotate=True)
        c, s = math.cos(theta), math.sin(theta)
        return np.array([p.step(1 + c * 0.01 * i - s * 0.003 * i * i / 60,
                                1 + s * 0.01 * i + c * 0.003 * i * i / 60,
                                theta, i / 30) for i in range(40)])
    assert np.allclose(stroke(0.0), stroke(2.2), atol=1e-9)


def test_a_rest_ends_the_gesture_and_the_next_starts_where_the_puck_rests():
    pf = PathFeatures(rest_time=0.5)
    t = 0.0
    for i in range(30):  # a stroke of 0.15 m
        t = i / 30
        pf.step(0.005 * i, 0.0, 0.0, t)
    mid = pf.step(0.15, 0.0, 0.0, t + 1 / 30)
    assert mid[0] == pytest.approx(0.15)
    for i in range(40):  # resting for 1.3 s
        rest = pf.step(0.15, 0.0, 0.0, t + (i + 2) / 30)
    assert rest[0] == pytest.approx(0.0) and rest[3] < 0.02 and pf.resting
    short = PathFeatures(rest_time=5.0)
    for i in range(30):
        short.step(0.005 * i, 0.0, 0.0, i / 30)
    for i in range(40):
        kept = short.step(0.15, 0.0, 0.0, (i + 31) / 30)
    assert kept[0] == pytest.approx(0.15)
    pf.reset(1.0, 1.0, 1.0, 100.0)
    assert np.allclose(pf.step(1.0, 1.1, 1.5, 100.1)[:3], [0.0, 0.1, 0.5])
    with pytest.raises(ValueError, match="finite"):
        pf.step(math.nan, 0.0, 0.0, 101.0)


def _puck_path(shape: str, speed: float, rate: float = 30.0, rng=None) -> np.ndarray:
    """Poses (x, y, angle, t) of a puck drawing ``shape`` at ``speed`` times its recorded pace,
    starting and ending with a rest."""
    n = int(round(90 / speed))
    s = np.linspace(0.0, 1.0, n)
    s = s * s * (3 - 2 * s)  # eases in and out
    if shape == "circle":
        x, y = 0.1 * np.sin(2 * np.pi * s), 0.1 * (1 - np.cos(2 * np.pi * s))
    elif shape == "zigzag":
        x, y = 0.3 * s, 0.05 * np.abs(((6 * s) % 2) - 1)
    else:  # a twist in place then a push
        x, y = 0.15 * np.clip(2 * s - 1, 0, 1), 0.0 * s
    angle = np.where(shape == "twist", 2.5 * np.clip(2 * s, 0, 1), 0.0) * np.ones_like(s)
    x, y, angle = 0.6 + x, 0.4 + y, angle
    rest = 15
    x = np.concatenate([np.full(rest, x[0]), x, np.full(rest, x[-1])])
    y = np.concatenate([np.full(rest, y[0]), y, np.full(rest, y[-1])])
    angle = np.concatenate([np.full(rest, angle[0]), angle, np.full(rest, angle[-1])])
    if rng is not None:
        x, y = x + rng.normal(0, 0.001, x.size), y + rng.normal(0, 0.001, y.size)
        angle = angle + rng.normal(0, 0.01, angle.size)
    t = np.arange(x.size) / rate
    return np.column_stack([x, y, angle, t])


def _features(path: np.ndarray) -> np.ndarray:
    """dx, dy, heading: speed is left out because it changes with the performer's tempo."""
    pf = PathFeatures()
    return np.array([pf.step(*p)[:3] for p in path])


def test_puck_gestures_are_recognised_and_followed_at_other_speeds():
    shapes = ("circle", "zigzag", "twist")
    templates = {s: _features(_puck_path(s, 1.0))[15:-15] for s in shapes}
    follower = ActionFollower(templates, min_scale=PathFeatures.min_scale[:3])
    rng = np.random.default_rng(3)
    for shape in shapes:
        for speed in (0.6, 1.0, 1.7):
            follower.reset()
            states = [follower.step(f) for f in _features(_puck_path(shape, speed, rng=rng))]
            moving = states[15:-15]
            late = moving[int(0.6 * len(moving)):]
            assert np.mean([s.best == shape for s in late]) >= 0.9, (shape, speed)
            assert states[-16].progress >= 0.9, (shape, speed)
            assert np.mean([s.valid for s in late]) >= 0.8, (shape, speed)
