"""A straight first stroke's bend (``behaviors.mop.bends``): a diagonal is the figure eight's
first stroke, and the eight is not shown driving it just before its bend, where the input goes
on straight; the group decides it as its followers alone."""

import numpy as np

from bench.follow_quality import gesture_templates, puck_follower, run
from bench.motions import performance, unrelated_motions
from behaviors.mop import bends
from tests.mop.helpers import group_beside_alone


def _diagonal(seed: int = 5, scale: float = 1.0) -> tuple[dict[str, np.ndarray], np.ndarray]:
    """The six gestures and a diagonal as the bench draws them."""
    gestures = gesture_templates()
    rng = np.random.default_rng(seed)
    return gestures, performance(rng, unrelated_motions(rng, gestures)["diagonal"], scale)[0]


def test_the_figure_eight_is_not_shown_on_a_diagonal_before_its_bend(monkeypatch):
    # the eight's first stroke is a straight diagonal, bent from 0.28 of it on: taken on that
    # stroke, it drove the diagonal up to its bend, until the overrun stopped it. Measured at
    # 0.7 / 1 / 1.4x: 5 / 3 / 2 valid samples of 76, 9 / 6 / 4 with the rule off
    gestures = gesture_templates()
    draws = [_diagonal(scale=s)[1] for s in (0.7, 1.0, 1.4)]
    now = sum(s.valid for x in draws for s in run(puck_follower(gestures), x))
    monkeypatch.setattr(bends, "UNTURNED", 0.0)
    off = sum(s.valid for x in draws for s in run(puck_follower(gestures), x))
    assert now <= 10 and off >= 18, (now, off)


def test_the_group_hides_the_eight_as_its_followers_alone():
    # the diagonal and the figure eight itself (0.7x) over members: every state equal to the
    # followers' alone (3 and 29 valid samples)
    gestures, x = _diagonal()
    eight, _ = performance(np.random.default_rng(1), gestures["figure_eight"], 0.7)
    n = min(len(x), len(eight))
    valid = group_beside_alone(lambda: puck_follower(gestures), [x[:n], eight[:n]])
    assert valid[0] <= 3 and valid[1] >= 25, valid
