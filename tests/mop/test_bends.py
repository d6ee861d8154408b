"""A straight first stroke waits for its bend (``behaviors.mop.bends``): a diagonal is the figure
eight's first stroke, and drives it no more; the group decides it as its followers alone."""

import math

import numpy as np

from bench.follow_quality import gesture_templates, puck_follower, run
from bench.motions import performance, unrelated_motions
from behaviors.mop import bends
from behaviors.mop.group import FollowerGroup


def _diagonal(seed: int = 5) -> tuple[dict[str, np.ndarray], np.ndarray]:
    """The six gestures and a diagonal as the bench draws them, at 0.7x."""
    gestures = gesture_templates()
    rng = np.random.default_rng(seed)
    return gestures, performance(rng, unrelated_motions(rng, gestures)["diagonal"], 0.7)[0]


def test_the_figure_eight_waits_for_its_bend_on_a_diagonal(monkeypatch):
    # the figure eight's first stroke is a straight diagonal, bent from 0.28 of it on: taken on
    # that stroke, it drove the diagonal until the overrun stopped it. Measured 0 valid ticks,
    # 9 with the rule off (seeds 5-11 at 0.7/1/1.4x: 0 each, 2-15 off)
    gestures, x = _diagonal()
    now = sum(s.valid for s in run(puck_follower(gestures), x))
    monkeypatch.setattr(bends, "BEND", 0.0)
    off = sum(s.valid for s in run(puck_follower(gestures), x))
    assert now == 0 and off >= 5, (now, off)


def test_the_figure_eight_and_its_followers_wait_alike_in_a_group():
    # the diagonal and the figure eight itself (0.7x) over members: every state equal to the
    # followers' alone
    gestures, x = _diagonal()
    eight, _ = performance(np.random.default_rng(1), gestures["figure_eight"], 0.7)
    n = min(len(x), len(eight))
    streams = [x[:n], eight[:n]]
    alone = [puck_follower(gestures) for _ in streams]
    group = FollowerGroup([puck_follower(gestures) for _ in streams])
    valid = [0, 0]
    for t in range(n):
        together = group.step([s[t] for s in streams])
        for j, (f, s, g) in enumerate(zip(alone, streams, together)):
            a = f.step(s[t])
            assert (a.valid, a.best) == (g.valid, g.best), t
            assert math.isclose(a.progress, g.progress, rel_tol=1e-12, abs_tol=1e-12), t
            valid[j] += g.valid
    assert valid[0] == 0 and valid[1] >= 20, valid
