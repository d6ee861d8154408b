"""The group's compiled threshold model (behaviors.mop.threshold_kernel) against the reference
step (behaviors.mop.threshold.threshold_model_step)."""

import numpy as np

from behaviors.mop.threshold import STAY, threshold_model_step
from behaviors.mop.threshold_kernel import threshold_step


def _member(lengths: list[int]):
    """One member's templates along a line (0.1 apart), in both layouts."""
    n = sum(lengths)
    xs = np.concatenate([0.1 * np.arange(length) for length in lengths])
    means = np.zeros((n, 2), np.float32)
    means[:, 0] = xs
    offsets = np.concatenate([[0], np.cumsum(lengths)[:-1]])
    ti = np.array([[o, length, 0] for o, length in zip(offsets, lengths)], dtype=np.intp)
    return means, ti, n


def test_a_mirror_chain_holding_weight_mid_way_is_stepped_as_the_reference_over_every_state():
    # the chain of the first template holds weight at states 40..48 only (its prior reaches
    # 51): the kernel steps it only there; the reference steps every state of every chain
    lengths = [100, 60]
    means, ti, n = _member(lengths)
    k = len(lengths)
    sigma = 0.2
    z = np.array([[4.3, 0.05, 4.25], [2.0, 0.05, 4.0]])   # the mirrored twin near state 42
    log_jacobian = np.array([0.1, -0.2])
    alpha = np.zeros(2 * n, np.float32)
    alpha[:n] = 0.5 / n
    alpha[n + 40:n + 49] = np.float32(0.5 / 9)
    tops = np.zeros(3 * k)
    tops[2 * k] = float(alpha[n:].astype(np.float64).sum())
    m = np.zeros(21)
    m[19] = -0.5 / sigma ** 2
    kernel_alpha, totals = alpha.copy(), np.ones(1)
    got = threshold_step(np.ascontiguousarray(means.T), ti, m, 0, k, z, log_jacobian,
                         kernel_alpha, np.zeros(2 * n, np.float32), False, totals, 0, tops)
    want_alpha = alpha.copy()
    want = threshold_model_step(z, means, np.array(lengths), sigma, 0.0, log_jacobian,
                                want_alpha, np.zeros(2 * n, np.float32), False, STAY)
    assert abs(got - want) < 1e-5
    chain = kernel_alpha[n:n + 100] / totals[0]
    want_chain = want_alpha[n:n + 100]
    assert np.array_equal(np.flatnonzero(chain), np.flatnonzero(want_chain))
    assert np.flatnonzero(chain).max() >= 50   # the weight moved on past where it was held
    np.testing.assert_allclose(chain, want_chain, rtol=2e-5)
    np.testing.assert_allclose(kernel_alpha[:n] / totals[0], want_alpha[:n], rtol=2e-5,
                               atol=1e-30)
