"""One Euro filter: still signals are smoothed, moving ones follow without lag, units scale."""

from __future__ import annotations

import numpy as np
import pytest

from tracking.filters import one_euro_floats, scale_beta


def _run(xs: np.ndarray, fps: float, min_cutoff: float, beta: float,
         d_cutoff: float) -> np.ndarray:
    """The filtered rows of ``xs`` sampled at ``fps``, the first passed through (as the puck
    tracker starts a track)."""
    value, derivative = xs[0].tolist(), [0.0] * xs.shape[1]
    out = [value]
    for x in xs[1:]:
        value, derivative = one_euro_floats(x.tolist(), value, derivative, 1.0 / fps,
                                            min_cutoff, beta, d_cutoff)
        out.append(value)
    return np.array(out)


def test_one_step_follows_the_first_order_low_pass_alpha():
    """A step with cutoffs of 1/(2 pi) Hz, beta 0 and dt 1 s has alpha = 1 / (1 + tau / dt) =
    0.5: the value moves halfway to the sample and the derivative halfway to the raw rate
    (dt 0.5 s: alpha 1/3). A cutoff read without its 2 pi gives other figures."""
    f = 1.0 / (2.0 * np.pi)
    value, derivative = one_euro_floats([3.0, -1.0], [1.0, 1.0], [0.4, 0.0], 1.0, f, 0.0, f)
    assert value == pytest.approx([2.0, 0.0], abs=1e-12)
    assert derivative == pytest.approx([1.2, -1.0], abs=1e-12)     # raw rate (2, -2)
    value, derivative = one_euro_floats([3.0, -1.0], [1.0, 1.0], [0.4, 0.0], 0.5, f, 0.0, f)
    assert value == pytest.approx([1.0 + 2.0 / 3.0, 1.0 - 2.0 / 3.0], abs=1e-12)
    assert derivative == pytest.approx([0.4 + 3.6 / 3.0, -4.0 / 3.0], abs=1e-12)  # raw (4, -4)


@pytest.mark.parametrize("fps", [30.0, 60.0])
def test_still_signal_jitter_is_reduced_more_than_fivefold(fps):
    rng = np.random.default_rng(0)
    xs = 0.5 + rng.normal(0.0, 3e-4, (600, 2))  # 0.3 mm: the detector's noise at 720p
    out = _run(xs, fps, 0.2, 40.0, 0.5)[90:]
    assert out.std(axis=0).max() * 5 <= xs[90:].std(axis=0).min()


@pytest.mark.parametrize("fps", [30.0, 60.0])
def test_ramp_lag_below_10ms_at_half_a_metre_per_second(fps):
    v = 0.5
    t = np.arange(int(5 * fps)) / fps
    rng = np.random.default_rng(1)
    xs = np.column_stack([v * t, np.zeros_like(t)]) + rng.normal(0, 3e-4, (len(t), 2))
    out = _run(xs, fps, 0.2, 40.0, 0.5)
    half = len(t) // 2
    lag_s = np.median((v * t[half:] - out[half:, 0]) / v)
    assert lag_s < 0.010


def test_beta_in_pixels_matches_beta_in_metres():
    rng = np.random.default_rng(2)
    xs = np.cumsum(rng.normal(0, 2e-3, (100, 2)), axis=0)
    scale = 900.0
    a = _run(xs, 30.0, 0.8, 30.0, 1.0)
    b = _run(xs * scale, 30.0, 0.8, scale_beta(30.0, scale), 1.0)
    assert np.allclose(a * scale, b, atol=1e-9)
