"""A follower group reads the rules' constants its member scalars hold where it is built
(:data:`behaviors.mop.group_layout.MEMBER_SCALARS`): built with one changed, it follows that
value at every tick as its followers alone do, which read it at each step."""

import numpy as np
import pytest

from bench.follow_quality import puck_follower
from bench.motions import gesture_templates, performance, unrelated_motions
from behaviors.mop import take_rule, tempo, validity
from behaviors.mop.group import FollowerGroup
from tests.mop.helpers import group_beside_alone


def _wander(seed: int, scale: float) -> np.ndarray:
    """The wander of ``bench/follow_quality.py``'s unrelated motions drawn with ``seed`` at
    ``scale`` (0.7, 1.0, 1.4x in turn), the six gestures loaded."""
    rng = np.random.default_rng(seed)
    path = unrelated_motions(rng, gesture_templates())["wander"]
    for s in (0.7, 1.0, 1.4):
        x = performance(rng, path, s)[0]
        if s == scale:
            return x
    raise KeyError(scale)


# each constant changed as a test switches its rule off, and a wander it changes: measured
# valid ticks with the group of one (rule on / changed) seed 1 0.7x 7 / 39 (CARRY_FIRST), seed
# 4 1.4x 13 / 19 (CRAWL_SAMPLES, CRAWL_HOVERS), seed 6 1.4x 1 / 10 (TAKE_SIZES)
@pytest.mark.parametrize("module, name, value, seed, scale", [
    (validity, "CARRY_FIRST", -1.0, 1, 0.7),
    (tempo, "CRAWL_SAMPLES", 0, 4, 1.4),
    (tempo, "CRAWL_HOVERS", False, 4, 1.4),
    (take_rule, "TAKE_SIZES", (0.7, 0.8, 0.9, 1.0, 1.12, 1.25, 1.4), 6, 1.4),
])
def test_a_group_built_with_a_rule_constant_changed_follows_it_as_its_followers_alone(
        monkeypatch, module, name, value, seed, scale):
    gestures = gesture_templates()
    x = _wander(seed, scale)
    group = FollowerGroup([puck_follower(gestures)])
    on = sum(s.valid for s in (group.step([v])[0] for v in x))
    monkeypatch.setattr(module, name, value)
    changed = group_beside_alone(lambda: puck_follower(gestures), [x])[0]
    assert changed != on, (name, on, changed)
