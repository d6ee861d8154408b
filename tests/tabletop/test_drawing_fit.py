"""tabletop.drawing.fit: a rigid motion found from some points carries them all."""

import math

import numpy as np

from tabletop.drawing.fit import rigid_onto


def test_a_turned_and_shifted_copy_is_carried_back_exactly():
    rng = np.random.default_rng(0)
    a = rng.random((30, 2))
    th = 0.7
    b = a @ np.array([[math.cos(th), math.sin(th)], [-math.sin(th), math.cos(th)]]) + [0.3, -0.2]
    b[10:] += rng.normal(0.0, 0.05, (20, 2))          # only the first ten are the reference
    out = rigid_onto(a, b, np.arange(10))
    assert np.allclose(out[:10], b[:10], atol=1e-12)
    assert np.allclose(np.linalg.norm(out[1:] - out[:-1], axis=1),
                       np.linalg.norm(a[1:] - a[:-1], axis=1))   # rigid: no scaling


def test_one_point_is_a_shift():
    a, b = np.array([[0.0, 0.0], [1.0, 0.0]]), np.array([[2.0, 3.0], [9.0, 9.0]])
    assert np.allclose(rigid_onto(a, b, np.array([0])), [[2.0, 3.0], [3.0, 3.0]])
