"""Resampling to the generation rate: offline (demonstrations) and causal (live input)."""

import math

import numpy as np

from behaviors.puppet_master.resample import CausalResampler, grid_times, resample_uniform


def test_grid_includes_the_last_time():
    g = grid_times(1.0, 2.0, 40.0)
    assert g.size == 41 and g[0] == 1.0 and abs(g[-1] - 2.0) < 1e-12


def test_uniform_resampling_interpolates_angles_through_pi():
    t = np.array([0.0, 0.1, 0.2])
    vals = np.array([[0.0, 3.0], [1.0, -3.0], [2.0, -2.9]])   # 3.0 -> -3.0 is a 0.28 rad turn
    tg, out = resample_uniform(t, vals, (1,), 40.0)
    assert tg.size == 9
    assert np.allclose(out[:, 0], tg * 10.0)
    mid = out[2, 1]                                            # t = 0.05
    assert abs(math.remainder(mid - (3.0 + (math.tau - 6.0) / 2), math.tau)) < 1e-12


def test_causal_resampler_extrapolates_straight_motion_exactly_from_the_past_only():
    r = CausalResampler(max_extrapolation=0.1)
    for t in (0.0, 1 / 30, 2 / 30):
        r.push(t, 0.2 * t, 0.1 - 0.1 * t, 0.5)
    x, y, d = r.at(0.075)              # after the newest sample
    assert abs(x - 0.015) < 1e-12 and abs(y - (0.1 - 0.0075)) < 1e-12 and d == 0.5
    assert not r.push(2 / 30, 9.0, 9.0, 0.0)      # not later: ignored
    assert not r.push(0.1, math.nan, 0.0, 0.0)    # not finite: ignored
    assert r.at(0.075) == (x, y, d)


def test_causal_resampler_holds_after_a_long_gap():
    r = CausalResampler(max_extrapolation=0.1)
    r.push(0.0, 0.0, 0.0, 0.0)
    r.push(0.1, 0.1, 0.0, 0.0)
    assert r.at(5.0)[0] == r.at(0.2)[0] == 0.2     # at most one input interval ahead
