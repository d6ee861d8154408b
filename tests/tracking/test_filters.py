"""One Euro filter: still signals are smoothed, moving ones follow without lag, units scale."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tracking.filters import OneEuroFilter, one_euro_step, scale_beta, smoothing_factor


def _run(filt, xs, fps):
    return np.array([filt.filter(x, k / fps) for k, x in enumerate(xs)])


@pytest.mark.parametrize("fps", [30.0, 60.0])
def test_still_signal_jitter_is_reduced_more_than_fivefold(fps):
    rng = np.random.default_rng(0)
    xs = 0.5 + rng.normal(0.0, 3e-4, (600, 2))  # 0.3 mm: the detector's noise at 720p
    out = _run(OneEuroFilter(0.2, 40.0, 0.5), xs, fps)[90:]
    assert out.std(axis=0).max() * 5 <= xs[90:].std(axis=0).min()


@pytest.mark.parametrize("fps", [30.0, 60.0])
def test_ramp_lag_below_10ms_at_half_a_metre_per_second(fps):
    v = 0.5
    t = np.arange(int(5 * fps)) / fps
    rng = np.random.default_rng(1)
    xs = np.column_stack([v * t, np.zeros_like(t)]) + rng.normal(0, 3e-4, (len(t), 2))
    out = _run(OneEuroFilter(0.2, 40.0, 0.5), xs, fps)
    half = len(t) // 2
    lag_s = np.median((v * t[half:] - out[half:, 0]) / v)
    assert lag_s < 0.010


def test_beta_in_pixels_matches_beta_in_metres():
    rng = np.random.default_rng(2)
    xs = np.cumsum(rng.normal(0, 2e-3, (100, 2)), axis=0)
    scale = 900.0
    a = _run(OneEuroFilter(0.8, 30.0, 1.0), xs, 30.0)
    b = _run(OneEuroFilter(0.8, scale_beta(30.0, scale), 1.0), xs * scale, 30.0)
    assert np.allclose(a * scale, b, atol=1e-9)


def test_vectorised_step_equals_separate_filters():
    rng = np.random.default_rng(3)
    xs = rng.normal(0, 1, (20, 5, 2))
    dts = rng.uniform(0.01, 0.05, (20, 5))
    x, dx = xs[0].copy(), np.zeros((5, 2))
    singles = [OneEuroFilter(1.0, 0.3, 1.0) for _ in range(5)]
    times = np.vstack([np.zeros(5), np.cumsum(dts[1:], axis=0)])
    for i, f in enumerate(singles):
        f.reset(xs[0, i], 0.0)
    for k in range(1, 20):
        x, dx = one_euro_step(xs[k], x, dx, dts[k], 1.0, 0.3, 1.0)
        for i, f in enumerate(singles):
            assert np.allclose(f.filter(xs[k, i], times[k, i]), x[i])


def test_smoothing_factor_and_bad_parameters():
    assert float(smoothing_factor(1.0 / (2 * math.pi), 1.0)) == pytest.approx(0.5)
    with pytest.raises(ValueError):
        OneEuroFilter(min_cutoff=0.0)
