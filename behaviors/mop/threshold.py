"""Threshold model: what an action must explain better than before it may drive.

In the spirit of Lee & Kim's HMM threshold model (a garbage model built from the gesture
models' own states), a follower keeps one more model beside its templates: an *ergodic* model
over every state of every loaded template, each state keeping the templates' self weight and
jumping to any state (of any template, uniformly) otherwise. It sees the live sample as every
template does (each in its own map and size), with the same Gaussian, so it explains any path
stitched from pieces of the templates in any order, but pays for every jump what the ordered
templates do not. Its per-sample log-likelihood is summed with the evidence's forgetting and
enters the probabilities as one more, never driving, competitor: an action drives only while
its probability, the threshold model counted, is at least ``min_probability``.

A still input is no evidence either way: the threshold model's state simply stays where the
sample is while an ordered template's prior moves on (a performer pausing mid-gesture), so while
the input has not moved by :data:`STILL_RADII` still radii since the last sample the threshold
model's log-likelihood is at most the best template's.

Figures (``bench/follow_quality.py``): see :mod:`behaviors.mop.validity`.
"""

from __future__ import annotations

import numpy as np

#: Self weight of every state of the threshold model (the templates' own ``transitions[0]``).
STAY = 0.3
#: Moving by less than this (in still radii, any column) since the last sample counts as still.
STILL_RADII = 2.0


def state_logliks(z: np.ndarray, means: np.ndarray, lengths: np.ndarray, sigma: float,
                  log_constant: float, log_jacobian: np.ndarray) -> np.ndarray:
    """Log-density (N,) of the raw sample under every state of every template: ``z`` (K, d) the
    sample in each template's standardised units, ``means`` (N, d) their states (template after
    template, ``lengths`` (K,) states each), ``log_jacobian`` (K,) each map's log |dz / dx|."""
    d = np.repeat(z, lengths, axis=0) - means
    ll = np.einsum("nd,nd->n", d, d)
    ll *= -0.5 / (sigma * sigma)
    ll += log_constant
    ll += np.repeat(log_jacobian, lengths)
    return ll


def threshold_step(alpha: np.ndarray, ll: np.ndarray, fresh: bool) -> float:
    """One step of the ergodic threshold model, in place on its state ``alpha`` (N,) (uniform
    when ``fresh``): returns the sample's log-likelihood ``log sum_j prior_j b_j``."""
    n = ll.size
    if fresh:
        alpha.fill(1.0 / n)
    top = float(ll.max())
    alpha *= STAY
    alpha += (1.0 - STAY) / n
    alpha *= np.exp(ll - top)
    total = float(alpha.sum())
    alpha /= total
    return top + float(np.log(total))


def gated(step: float, best_step: float, x: np.ndarray, previous: np.ndarray | None,
          still_radius: np.ndarray) -> float:
    """The threshold model's step, at most ``best_step`` (the best template's) while the input
    stayed within :data:`STILL_RADII` still radii of the ``previous`` sample."""
    if previous is None or not np.any(np.abs(x - previous) > STILL_RADII * still_radius):
        return min(step, best_step)
    return step
