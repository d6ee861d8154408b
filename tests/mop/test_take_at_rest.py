"""A new action is not taken while the performer rests (``behaviors.mop.validity.TAKE_AT_REST``):
a straight stroke along the held-out walk wrist's first direction, ended where its path turns
back, and the rest after it; the group decides it as its followers alone."""

import numpy as np

from bench.follow_quality import puck_follower, run
from bench.follow_strokes import own_strokes
from bench.motions import MOCAP_HELD_OUT, mocap_templates, performance
from behaviors.mop import recognition
from tests.mop.helpers import group_beside_alone


def _strokes(seeds: range) -> tuple[dict[str, np.ndarray], list[np.ndarray], list[int]]:
    """The walk wrist alone and its own stroke at 1x (``bench/follow_strokes.py``), one draw
    per seed: (templates, samples, the last moving sample of each)."""
    walk = {"walk_left_wrist": mocap_templates(joints=MOCAP_HELD_OUT)["walk_left_wrist"]}
    path = own_strokes(walk)["stroke_walk_left_wrist"]
    draws = [performance(np.random.default_rng(s), path, 1.0) for s in seeds]
    return walk, [x for x, _ in draws], [int(np.flatnonzero(np.isfinite(p[:, 0]))[-1])
                                         for _, p in draws]


def test_the_walk_wrist_is_not_taken_in_the_rest_after_a_stroke(monkeypatch):
    # at rest the gesture's last samples hold the rest alone and fit where the walk turns back
    # (0.54 of it). Measured, seeds 1-5: 0 valid ticks; taken at rest too, 62 (58 of them after
    # the stroke ended)
    walk, xs, ends = _strokes(range(1, 6))
    now = sum(s.valid for x in xs for s in run(puck_follower(walk), x))
    monkeypatch.setattr(recognition, "TAKE_AT_REST", True)
    at_rest = sum(s.valid and t > end for x, end in zip(xs, ends)
                  for t, s in enumerate(run(puck_follower(walk), x)))
    assert now == 0 and at_rest >= 40, (now, at_rest)


def test_the_group_takes_nothing_at_rest_as_its_followers_alone():
    # seeds 2-3 (15 and 12 valid ticks at rest when taken there): every state equal
    walk, xs, _ = _strokes(range(2, 4))
    n = min(len(x) for x in xs)
    assert group_beside_alone(lambda: puck_follower(walk), [x[:n] for x in xs]) == [0, 0]
