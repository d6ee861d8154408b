"""The compiled loops' tools: the vectorising exponential matches the library's."""

import math

import numba
import numpy as np

from behaviors.mop.compiled import exp_neg


@numba.njit
def _exp_all(x: np.ndarray, out: np.ndarray) -> None:
    for i in range(x.size):
        out[i] = exp_neg(x[i])


def test_the_forward_exponential_is_within_two_ulp_of_the_library_over_its_range():
    rng = np.random.default_rng(5)
    x = np.concatenate([-np.linspace(0.0, 200.0, 400_001), -708.0 * rng.random(400_000),
                        [-0.0, -1e-300, -math.log(2.0) / 2, -708.0]])
    got = np.empty_like(x)
    _exp_all(x, got)
    want = np.array([math.exp(v) for v in x])
    rel = np.abs(got - want) / want
    assert rel.max() <= 4.5e-16, x[np.argmax(rel)]     # 2 ulp
    assert got[-4] == 1.0 and np.all(np.diff(got[:400_001]) <= 0)   # exact at 0, monotone
