"""A follower group reads the rules' constants its member scalars hold where it is built
(:data:`behaviors.mop.group_layout.MEMBER_SCALARS`): built with one changed, it follows that
value at every tick as its followers alone do, which read it at each step."""

import math

import numpy as np
import pytest

from bench.follow_quality import puck_follower
from bench.motions import gesture_templates, paused, performance, unrelated_motions
from behaviors.mop import (coverage, gesture_end, shape_lead, spotting, take_rule, tempo,
                           threshold, validity)
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


def _paused(seed: int, name: str) -> np.ndarray:
    """``name`` of the six gestures paused 1.5 s part way as ``tests/mop/test_pauses.py`` draws
    it with ``seed`` (the draws before it made and dropped)."""
    rng = np.random.default_rng(seed)
    for key, tpl in gesture_templates().items():
        x = paused(rng, tpl, float(rng.uniform(0.8, 1.2)), 1.5, (0.3, 0.7))[0]
        if key == name:
            return x
    raise KeyError(name)


def _chain(seed: int) -> np.ndarray:
    """The six gestures back to back in a random order at 0.8-1.2x as
    ``tests/mop/test_spotting.py``'s ended-gesture test draws them with ``seed``."""
    from tests.mop.helpers import chain
    gestures = gesture_templates()
    rng = np.random.default_rng(seed)
    order = list(rng.permutation(list(gestures)))
    return chain(rng, gestures, order, lambda: float(rng.uniform(0.8, 1.2)))[0]


def _mirrored_line(seed: int, scale: float) -> np.ndarray:
    """The line mirrored (out along -x, back) at ``scale`` as ``tests/mop/test_refusal.py``'s
    abandoned-turn test draws it with ``seed`` (0.7, 1.0, 1.4x in turn)."""
    rng = np.random.default_rng(seed)
    mirrored = gesture_templates()["line"] * np.array([-1.0, 1.0])
    for s in (0.7, 1.0, 1.4):
        x = performance(rng, mirrored, s)[0]
        if s == scale:
            return x
    raise KeyError(scale)


def _draw(seed: int, scale) -> np.ndarray:
    """The wander at ``scale`` (a number), or the gesture ``scale`` paused (:func:`_paused`) or
    performed there and back (``"back " + name``: ``tests/mop/test_quality.py``'s draw), or
    the six gestures back to back (``"chain N"``, :func:`_chain`'s first N samples), or the
    line mirrored (``"mirrored line"``, at 1x: :func:`_mirrored_line`)."""
    from tests.mop.test_quality import _there_and_back
    if isinstance(scale, str) and scale.startswith("chain "):
        return _chain(seed)[:int(scale[6:])]
    if scale == "mirrored line":
        return _mirrored_line(seed, 1.0)
    if isinstance(scale, str) and scale.startswith("back "):
        return _there_and_back(gesture_templates(), scale[5:], seed)
    return _paused(seed, scale) if isinstance(scale, str) else _wander(seed, scale)


# each constant changed as a test switches its rule off, and a draw it changes: measured valid ticks
# with the group of one (rule on / changed) seed 1 0.7x 7 / 39 (CARRY_FIRST), seed 4 1.4x 13 / 19
# (CRAWL_SAMPLES, CRAWL_HOVERS), seed 6 1.4x 1 / 10 (TAKE_SIZES), seed 5 1x 0 / 21
# (UNJUDGED_AT_REST), seed 4 1.4x 13 / 2 (TAKEN_PERFORMED), seed 2 1x 6 / 22 (EARLY_FIT), seed 2
# 0.7x 0 / 6 (LATE_FIT); the zigzag paused, seed 0 104 / 75 (UNWEIGHED_AT_REST); the wave there and
# back, seed 1, with the last samples' fit (take_rule.TAKE_MISFIT2, read at each step) lifted in
# both: 61 / 88 (REST_BEHIND); the six gestures back to back, seed 2, its first 60 samples: 19 / 23
# (TEMPO_END_FROM), 19 / 21 (ARRIVE_RADIUS), its first 210: 102 / 103 (shape_lead.LEAD, read at each
# step; the whole chain 213 / 218, 222, 214); the mirrored line, seed 3 1x, with the threshold model
# afresh at an abandonment (threshold.CARRY_LEAD, read at each step) in both: 0 / 18 (RESTED_LIFTS)
@pytest.mark.parametrize("module, name, value, seed, scale", [
    (validity, "CARRY_FIRST", -1.0, 1, 0.7),
    (tempo, "CRAWL_SAMPLES", 0, 4, 1.4),
    (tempo, "CRAWL_HOVERS", False, 4, 1.4),
    (take_rule, "TAKE_SIZES", (0.7, 0.8, 0.9, 1.0, 1.12, 1.25, 1.4), 6, 1.4),
    (validity, "UNJUDGED_AT_REST", False, 5, 1.0),
    (validity, "UNWEIGHED_AT_REST", False, 0, "zigzag"),
    (validity, "REST_BEHIND", -1.0, 1, "back wave"),
    (validity, "TAKEN_PERFORMED", math.inf, 4, 1.4),
    (coverage, "EARLY_FIT", math.inf, 2, 1.0),
    (coverage, "LATE_FIT", math.inf, 2, 0.7),
    (spotting, "TEMPO_END_FROM", 9.0, 2, "chain 60"),
    (gesture_end, "ARRIVE_RADIUS", 0.0, 2, "chain 60"),
    (shape_lead, "LEAD", 0.0, 2, "chain 210"),
    (validity, "RESTED_LIFTS", False, 3, "mirrored line"),
])
def test_a_group_built_with_a_rule_constant_changed_follows_it_as_its_followers_alone(
        monkeypatch, module, name, value, seed, scale):
    gestures = gesture_templates()
    x = _draw(seed, scale)
    if name == "REST_BEHIND":
        monkeypatch.setattr(take_rule, "TAKE_MISFIT2", math.inf)
    if name == "RESTED_LIFTS":
        monkeypatch.setattr(threshold, "CARRY_LEAD", False)
    group = FollowerGroup([puck_follower(gestures)])
    on = sum(s.valid for s in (group.step([v])[0] for v in x))
    monkeypatch.setattr(module, name, value)
    changed = group_beside_alone(lambda: puck_follower(gestures), [x])[0]
    assert changed != on, (name, on, changed)
