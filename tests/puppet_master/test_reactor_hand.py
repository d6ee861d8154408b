"""reactor_hand.above: the same answer as np.hypot(x, y) > most, near the bound and far from it."""

import numpy as np

from behaviors.puppet_master import designers, reactor_hand


def test_above_answers_as_np_hypot_at_and_around_the_bound() -> None:
    rng = np.random.default_rng(7)
    most = rng.uniform(0.01, 1.0, 20_000)
    angle = rng.uniform(-np.pi, np.pi, 20_000)
    # norms within a relative 1e-8 of the bound (where the squared norm cannot decide),
    # exactly on it, and far off it
    scale = np.concatenate([1.0 + rng.uniform(-1e-8, 1e-8, 10_000), np.ones(5_000),
                            rng.uniform(0.0, 3.0, 5_000)])
    x, y = most * scale * np.cos(angle), most * scale * np.sin(angle)
    want = np.hypot(x, y) > most
    got = [reactor_hand.above(a, b, m) for a, b, m in zip(x.tolist(), y.tolist(), most.tolist())]
    assert np.array_equal(np.array(got), want)
    assert 0 < int(want[:15_000].sum()) < 15_000        # both answers met near the bound


def test_a_demonstration_is_the_same_array_twice() -> None:
    a = designers.demonstrate("afraid", seconds=20.0)
    b = designers.demonstrate("afraid", seconds=20.0)
    assert np.array_equal(a, b) and a.shape == (800, 7)
