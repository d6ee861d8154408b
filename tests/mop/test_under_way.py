"""No action taken in an attempt abandoned while the input sweeps on (``behaviors.mop.under_way``):
a spiral's second turn, begun at full pace through its start, is no circle's onset; the group
decides it as its followers alone."""

import numpy as np

from bench.follow_quality import gesture_templates, puck_follower
from behaviors.mop import under_way
from tests.mop.helpers import group_beside_alone, run, solo, unrelated_at_1x


def _spiral_with_the_circle(seed: int = 11) -> tuple[dict[str, np.ndarray], np.ndarray]:
    """The circle alone and a spiral (two turns, the second a loop the circle's way round
    through its start) as the bench draws them, at 1.0x."""
    circle = {"circle": gesture_templates()["circle"]}
    return circle, unrelated_at_1x(circle, "spiral", seed)


def test_no_action_is_taken_in_an_attempt_abandoned_under_way(monkeypatch):
    # under_way.underway: every template refused the spiral's first turn; abandoned as the input
    # swept through the spiral's start at full pace, the new attempt was anchored there and
    # the circle followed the second turn as a circle begun from rest. Measured 0 valid ticks,
    # 36 with the rule off
    # (a group of one: under_way.underway reads UNDERWAY at each call; equal to the follower
    # alone on this spiral either way, 0 and 36 valid ticks)
    circle, x = _spiral_with_the_circle()
    now = sum(s.valid for s in run(solo(puck_follower(circle)), x))
    monkeypatch.setattr(under_way, "UNDERWAY", 0.0)
    off = sum(s.valid for s in run(solo(puck_follower(circle)), x))
    assert now <= 5 and off >= now + 25, (now, off)


def test_a_group_refuses_an_attempt_abandoned_under_way_as_its_followers_alone():
    # the same over members (group.FollowerGroup, its attempt's pace kept per member): every
    # state equal to the followers' alone (the spiral, and its second turn drawn 1.3x larger)
    circle, x = _spiral_with_the_circle()
    streams = [x, np.concatenate([x[:40], x[40:] * 1.3 - x[40] * 0.3])]
    valid = sum(group_beside_alone(lambda: puck_follower(circle), streams))
    assert valid <= 10, valid   # measured 0 (36 on the spiral with the rule off)
