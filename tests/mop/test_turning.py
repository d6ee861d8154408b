"""The input's signed turning against its template's (:mod:`behaviors.mop.turning`): blind to
size and tempo, it tells a mirror."""

import numpy as np
import pytest


def test_turning_is_blind_to_size_and_tempo_and_tells_a_mirror():
    # the signed turning a new action must share with its template (turning.turning)
    from behaviors.mop.turning import turn_fits, turning
    u = np.linspace(0.0, 1.0, 200)
    circle = np.stack([np.sin(2 * np.pi * u), 1 - np.cos(2 * np.pi * u)], axis=1) * 0.05
    for size, n in ((0.7, 60), (1.4, 200)):
        path = circle[np.linspace(0, 199, n).astype(int)] * size
        assert turning(path, 0.003)[-1] == pytest.approx(2 * np.pi, abs=0.4)
    assert turning(circle * [-1.0, 1.0], 0.003)[-1] == pytest.approx(-2 * np.pi, abs=0.4)
    line = np.stack([u, 0 * u], axis=1) * 0.1
    assert abs(turning(line, 0.003)[-1]) < 1e-9
    # a hairpin is +pi or -pi by the jitter: both fit; a quarter turn the other way does not
    assert turn_fits(np.array([np.pi]), -np.pi + 0.1, 1.3)
    assert not turn_fits(np.array([0.5 * np.pi]), -0.5 * np.pi, 1.3)
