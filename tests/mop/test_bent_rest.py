"""A take at rest on a straight stroke (``behaviors.mop.bends.bent_rest``): a straight stroke
along the held-out getup wrist's own first direction, ended where the walk wrist turns back,
does not take the walk wrist while the puck rests; the group decides it as its followers alone."""

import numpy as np

from bench.follow_quality import puck_follower, run
from behaviors.mop import bends
from tests.mop.helpers import group_beside_alone


def _strokes(seeds=(0, 2)) -> tuple[dict[str, np.ndarray], list[np.ndarray]]:
    """The held-out getup and walk wrists, and a straight stroke along the getup's own first
    direction (``bench/follow_strokes.py``) at 0.7x, ``seeds``."""
    from bench.follow_strokes import own_strokes
    from bench.motions import MOCAP_HELD_OUT, mocap_templates, performance
    m = mocap_templates(joints=MOCAP_HELD_OUT)
    two = {n: m[n] for n in ("getup_facedown_right_wrist", "walk_left_wrist")}
    path = own_strokes(two)["stroke_getup_facedown_right_wrist"]
    return two, [performance(np.random.default_rng(s), path, 0.7)[0] for s in seeds]


def _walk_valid(two: dict[str, np.ndarray], strokes: list[np.ndarray]) -> int:
    return sum(s.valid and s.best == "walk_left_wrist"
               for x in strokes for s in run(puck_follower(two), x))


def test_a_rest_after_a_straight_stroke_does_not_take_a_turned_template(monkeypatch):
    # the walk wrist's path has turned 0.77 rad where it turns back (0.51-0.54 of it); the
    # stroke has not (under 0.1 rad). Measured: taken there 13 samples into the rest, valid
    # 9 ticks with the rule off, none with it
    # (bends.STRAYS off: its straight strokes are ones the templates stray from; the rule
    # would hide what this one measures)
    monkeypatch.setattr(bends, "STRAYS", 0.0)   # read at each step
    two, strokes = _strokes((0,))
    now = _walk_valid(two, strokes)
    monkeypatch.setattr(bends, "REST_BENT", 0.0)
    off = _walk_valid(two, strokes)
    assert now == 0 and off >= 8, (now, off)


def test_the_group_takes_nothing_at_rest_on_a_stroke_as_its_followers_alone():
    # seeds 0 and 2 cut to the shorter: 5 and 21 valid ticks, 9 and 29 with the rule off
    two, strokes = _strokes()
    n = min(len(x) for x in strokes)
    valid = group_beside_alone(lambda: puck_follower(two), [x[:n] for x in strokes])
    assert valid[0] <= 5 and valid[1] <= 21, valid


def test_a_take_at_rest_is_judged_by_the_turning_of_its_template_against_the_input():
    # traced: the walk wrist at 0.54 of it has turned 0.77 rad, the getup's stroke 0.03; the
    # roll wrist at 0.25 of it -2.07, a mirrored square's last side -0.41 (held-out seed 103,
    # twenty templates, 1.4x: its last 2 valid ticks). Only a nearly straight input is judged:
    # a true getup re-taken in its wait read 3.46 against its template's 1.22 (the wait's
    # jitter turns the input; seed 105, 1x), a true punch on its return -3.08 against 0 (102)
    assert bends.bent_rest(True, 0.77, 0.03)
    assert bends.bent_rest(True, -2.07, -0.41)
    assert not bends.bent_rest(True, 0.77, 0.60)
    assert not bends.bent_rest(True, 1.22, 3.46)
    assert not bends.bent_rest(True, 0.0, -3.08)
    assert not bends.bent_rest(False, 0.77, 0.03)
    assert not bends.bent_rest(True, 2.0 * np.pi + 0.1, 0.0)   # whole turns aside
