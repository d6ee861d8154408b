"""shape_lead.take_fits: its early exits give the answer of the least misfit over every size."""

import numpy as np

from behaviors.mop import shape_lead


def least_misfit2(samples: np.ndarray, path: np.ndarray, scale: np.ndarray, first: np.ndarray,
                  size: float, lo: float, hi: float, decay: float, norm: float) -> float:
    """The least over TAKE_SIZES of the forgotten mean square distance to the path's segments,
    every sample and size visited (numpy)."""
    a, ab = path[:-1], np.diff(path, axis=0)
    weights = decay ** np.arange(len(samples))[::-1]      # the last sample weighs most
    least = np.inf
    for f in shape_lead.TAKE_SIZES:
        z = samples / scale / min(max(size * f, lo), hi) + first
        t = np.clip(np.einsum("nsd,sd->ns", z[:, None, :] - a, ab)
                    / np.maximum((ab * ab).sum(1), 1e-12), 0.0, 1.0)
        near = ((z[:, None, :] - a - t[..., None] * ab) ** 2).sum(2).min(1)
        least = min(least, float((weights * near).sum() / weights.sum() / norm))
    return least


def test_take_fits_answers_as_the_least_misfit_over_every_size():
    rng = np.random.default_rng(7)
    answers, near_limit = [], 0
    for _ in range(1500):
        n, d, m = int(rng.integers(1, 25)), int(rng.integers(1, 5)), int(rng.integers(2, 35))
        path = np.cumsum(rng.normal(size=(m, d)) * 0.3, axis=0)
        samples = np.cumsum(rng.normal(size=(n, d)) * rng.uniform(0.05, 1.0), axis=0)
        scale, first = rng.uniform(0.5, 2.0, d), path[0] + rng.normal(size=d) * 0.1
        size, decay, norm = rng.uniform(0.5, 1.6), rng.uniform(0.8, 1.0), rng.uniform(0.2, 3.0)
        limit = rng.uniform(0.01, 1.0)
        least = least_misfit2(samples, path, scale, first, size, 0.6, 1.5, decay, norm)
        if abs(least - limit) < 1e-9 * limit:
            continue                                    # a tie only rounding decides
        fits = shape_lead.take_fits(samples, path, scale, first, size, 0.6, 1.5, decay, norm,
                                    shape_lead.outwards(shape_lead.TAKE_SIZES), limit)
        assert fits == (least <= limit), (least, limit)
        answers.append(fits)
        near_limit += abs(least - limit) < 0.05 * limit
    # both answers, and cases close to the limit (18 here), are among those checked
    assert 0.2 < np.mean(answers) < 0.8 and near_limit > 10, (np.mean(answers), near_limit)
