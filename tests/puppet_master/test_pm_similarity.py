"""BestMatch parts: incremental situation distances, coherence candidates, balancing."""

import numpy as np

from behaviors.puppet_master.similarity import (Balancer, CoherenceSearch, SituationSearch,
                                                window_sums)


def window_distances(live: np.ndarray, train: np.ndarray) -> np.ndarray:
    """Brute-force distances of ``live`` (n, d) to every full training window: ``out[j]`` for
    window ends j = n-1 .. N-1, shape (N - n + 1,)."""
    n = live.shape[0]
    win = np.lib.stride_tricks.sliding_window_view(train, n, axis=0)  # (N-n+1, d, n)
    diff = win - live.T[None]
    return np.einsum("jdn,jdn->j", diff, diff)


def test_window_sums_match_direct_sums():
    rng = np.random.default_rng(0)
    v = rng.random(50)
    out = window_sums(v, 7)
    for j in range(50):
        assert abs(out[j] - v[max(0, j - 6):j + 1].sum()) < 1e-12


def test_incremental_situation_distances_equal_brute_force_after_many_steps():
    rng = np.random.default_rng(1)
    N, n, d = 600, 40, 6
    train = rng.normal(size=(N, d)) * [1, 2, 0.5, 3, 1, 1]
    valid = np.zeros(N, bool)
    valid[n - 1:N - 1] = True
    s = SituationSearch(train, n, valid)
    live = list(rng.normal(size=(n, d)))
    s.reset(np.array(live))
    for _ in range(3000):
        x = rng.normal(size=d) * 2
        s.push(x)
        live.append(x)
    window = np.array(live[-n:])
    exact = window_distances(window, train)          # window ends n-1 .. N-1
    got = s.distances()[n - 1:N - 1]
    # single-precision terms, double-precision sums: within 1e-6 after 3,000 steps (2.5e-8)
    assert np.max(np.abs(got - exact[:-1]) / exact[:-1]) < 1e-6
    j, cost = s.best()
    assert j == n - 1 + int(np.argmin(exact[:-1]))
    assert abs(cost - exact[:-1].min()) < 1e-6 * exact.min()


def test_situation_search_finds_a_copied_training_window_exactly():
    rng = np.random.default_rng(2)
    N, n, d = 400, 20, 6
    train = rng.normal(size=(N, d))
    valid = np.zeros(N, bool)
    valid[n - 1:N - 1] = True
    s = SituationSearch(train, n, valid)
    s.reset(rng.normal(size=(n, d)))
    for row in train[200 - n + 1:201]:   # live window now equals the training window ending at 200
        s.push(row)
    j, cost = s.best()
    assert j == 200 and cost < 1e-4                  # single-precision terms (measured 9e-6)


def test_coherence_candidates_are_sources_advanced_by_age():
    N, n, d = 300, 5, 3
    train = np.arange(N * d, dtype=float).reshape(N, d)
    valid = np.zeros(N, bool)
    valid[n - 1:N - 1] = True
    c = CoherenceSearch(train, n, valid)
    c.reset(np.zeros((n, d)))
    assert c.best() == (-1, float("inf"))     # no sources yet: nothing to continue
    for k, src in enumerate([100, 101, 50, 51, 52]):
        c.push(train[src], src)
    # ages 4..0: 100+4, 101+3, 50+2, 51+1, 52+0
    assert c.candidates().tolist() == [52, 104]
    jc, cost = c.best()
    # the live window is train[100],[101],[50],[51],[52]; neither candidate matches it fully
    assert jc in (52, 104) and cost > 0
    for src in range(200, 205):
        c.push(train[src], src)
    assert c.best() == (204, 0.0)


def test_balancer_holds_the_target_share_when_coherence_always_looks_better():
    # a coherence loop: the coherence cost keeps shrinking against the situation cost
    for ratio, share in ((1.0, 0.5), (3.0, 0.25)):
        b = Balancer(ratio=ratio)
        for step in range(4000):
            b.choose(1.0, 1e-3 * 0.999 ** step)
        assert abs(b.coherence_choices / b.choices - share) < 0.04
        assert abs(b.share - share) < 0.1


def test_static_weight_lets_coherence_take_over():
    b = Balancer(ratio=1.0, gain=1e-12)
    for step in range(1000):
        b.choose(1.0, 1e-3)
    assert b.coherence_choices / b.choices > 0.99


def test_recency_weighted_distances_equal_brute_force():
    rng = np.random.default_rng(3)
    N, n, d, h = 500, 40, 6, 10.0
    train = rng.normal(size=(N, d))
    valid = np.zeros(N, bool)
    valid[n - 1:N - 1] = True
    s = SituationSearch(train, n, valid, half_life=h)
    live = list(rng.normal(size=(n, d)))
    s.reset(np.array(live))
    for _ in range(1500):
        x = rng.normal(size=d)
        s.push(x)
        live.append(x)
    window = np.array(live[-n:])
    w = 0.5 ** (np.arange(n - 1, -1, -1) / h)          # oldest first: the oldest weighs least
    exact = np.array([np.sum(w * np.sum((train[j - n + 1:j + 1] - window) ** 2, axis=1))
                      for j in range(n - 1, N - 1)])
    got = s.distances()[n - 1:N - 1]
    assert np.max(np.abs(got - exact) / exact) < 1e-6
    assert s.best()[0] == n - 1 + int(np.argmin(exact))
