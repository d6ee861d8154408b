"""Carried by its own driving (``behaviors.mop.earned``): an action whose progress leapt while
it did not drive holds a rest only where its template rests or slows; the group decides it as
its followers alone."""

import math

import numpy as np

from bench.follow_quality import gesture_templates, puck_follower, run
from bench.motions import performance, unrelated_motions
from behaviors.mop import recognition
from behaviors.mop.earned import slow_states
from behaviors.mop.group import FollowerGroup


def _wander(seed: int = 36) -> tuple[dict[str, np.ndarray], np.ndarray]:
    """The six gestures and an aimless wander as the bench draws them, at 1.4x."""
    gestures = gesture_templates()
    rng = np.random.default_rng(seed)
    path = unrelated_motions(rng, gestures)["wander"]
    performance(rng, path, 0.7)
    performance(rng, path, 1.0)
    return gestures, performance(rng, path, 1.4)[0]


def test_a_template_slows_at_its_turns_and_ends():
    zigzag = gesture_templates()["zigzag"]
    slows = slow_states(zigzag - zigzag[0], np.array([0]), np.array([len(zigzag)]), None)
    at = lambda p: bool(slows[int(round(p * (len(zigzag) - 1)))])
    assert at(0.0) and at(1.0) and not at(0.315) and not at(0.6)


def test_an_action_carried_while_it_did_not_drive_holds_no_rest(monkeypatch):
    # the wander is taken by a template, refused, its progress carried on while it did not
    # drive, taken again and held through the rest that ends the wander. Measured 10 valid
    # ticks, 25 with the rule off (seeds 0-39 at 0.7/1/1.4x: five draws changed, none up)
    gestures, x = _wander()
    now = sum(s.valid for s in run(puck_follower(gestures), x))
    monkeypatch.setattr(recognition, "unearned_rest", lambda *a: False)
    off = sum(s.valid for s in run(puck_follower(gestures), x))
    assert now <= 12 and off >= now + 10, (now, off)


def test_a_group_holds_no_unearned_rest_as_its_followers_alone():
    # the wander and its copy drawn 1.3x larger after 60 samples: every state equal to the
    # followers' alone
    gestures, x = _wander()
    streams = [x, np.concatenate([x[:60], x[60:] * 1.3 - x[60] * 0.3])]
    alone = [puck_follower(gestures) for _ in streams]
    group = FollowerGroup([puck_follower(gestures) for _ in streams])
    valid = 0
    for t in range(len(x)):
        together = group.step([s[t] for s in streams])
        for f, s, g in zip(alone, streams, together):
            a = f.step(s[t])
            assert (a.valid, a.best) == (g.valid, g.best), t
            assert math.isclose(a.progress, g.progress, rel_tol=1e-12, abs_tol=1e-12), t
            valid += g.valid
    assert valid <= 30, valid
