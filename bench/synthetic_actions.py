"""Synthetic action templates and performances with known progress (seeded): the MOP benches
(bench/mop.py, bench/mop_soak.py) and the MOP tests perform them."""

from __future__ import annotations

import numpy as np


def template(rng: np.random.Generator, n: int = 200, d: int = 3, harmonics: int = 3) -> np.ndarray:
    """A smooth random action (n, d): each feature a sum of low-frequency sines."""
    s = np.linspace(0.0, 1.0, n)
    out = np.zeros((n, d))
    for j in range(d):
        for f in range(1, harmonics + 1):
            out[:, j] += rng.normal() / f * np.sin(np.pi * f * s + rng.uniform(0.0, 2.0 * np.pi))
    return out


def at_phase(tpl: np.ndarray, phase: np.ndarray) -> np.ndarray:
    """The template read at fractional sample indices ``phase`` (linear interpolation)."""
    base = np.arange(tpl.shape[0])
    return np.stack([np.interp(phase, base, tpl[:, j]) for j in range(tpl.shape[1])], axis=1)


def warped_phase(rng: np.random.Generator, n: int, slow: float = 0.5,
                 fast: float = 2.0) -> np.ndarray:
    """Sample indices of a performance whose speed (template samples per live sample) swings
    between ``slow`` and ``fast`` and back, within the one performance; ends on the last sample."""
    c = rng.uniform(0.0, 2.0 * np.pi)
    f = rng.uniform(0.04, 0.08)
    phase, i, out = 0.0, 0, []
    while phase < n - 1:
        out.append(phase)
        u = 0.5 + 0.5 * np.sin(c + f * i)
        phase += float(np.exp(np.log(slow) + (np.log(fast) - np.log(slow)) * u))
        i += 1
    out.append(n - 1.0)
    return np.asarray(out)


def perform(rng: np.random.Generator, tpl: np.ndarray, phase: np.ndarray,
            noise: float = 0.1) -> np.ndarray:
    """A performance of ``tpl`` at ``phase`` with Gaussian noise of ``noise`` x each feature's
    spread."""
    x = at_phase(tpl, phase)
    return x + rng.normal(0.0, noise, x.shape) * tpl.std(axis=0)
