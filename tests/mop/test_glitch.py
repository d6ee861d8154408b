"""One far sample (a tracker's glitch) is held as lost, alone and in a group; a departure that
persists is followed."""

import numpy as np
import pytest

from behaviors.mop.follower import ActionFollower
from behaviors.mop.group import FollowerGroup
from tests.mop.test_group import _step_both


def _glitched(gestures: dict[str, np.ndarray], value: float = 5.0) -> np.ndarray:
    """The example circle performed as recorded, its dx at row 11 misread as ``value``."""
    perf = gestures["circle"].copy()
    perf[11, 0] = value
    return perf


@pytest.mark.parametrize("invariance", ["none", "scale"])
@pytest.mark.parametrize("value", [5.0, 0.3, 1e150])
def test_one_glitched_sample_leaves_the_circle_followed_as_with_it_lost(gestures, invariance,
                                                                        value):
    # without the rule: dx = 5 (and 1e150) ended on the zigzag ("none") or the line ("scale"),
    # valid on no row; 0.3 m valid on 31 of 61 rows ("none"), ended on the line ("scale")
    lost = gestures["circle"].copy()
    lost[11] = np.nan
    ref = ActionFollower(gestures, invariance=invariance)
    want = [ref.step(x) for x in lost]
    f = ActionFollower(gestures, invariance=invariance)
    got = [f.step(x) for x in _glitched(gestures, value)]
    assert got[-1].best == "circle" and got[-1].probabilities["circle"] > 0.99
    assert sum(s.valid for s in got) >= 40
    assert [(s.best, s.valid, s.progress) for s in got] == [
        (s.best, s.valid, s.progress) for s in want]
    assert f.glitches == 1


def test_a_departure_that_persists_is_followed_from_its_second_sample(gestures):
    perf = gestures["circle"].copy()
    perf[11:, 0] += 0.5   # the performer (or the puck) is somewhere else from row 11 on
    f = ActionFollower(gestures, invariance="scale")
    states = [f.step(x) for x in perf]
    assert f.glitches == 1   # row 11 held, row 12 followed from row 10: a departure
    assert states[12].loglik != states[11].loglik   # not a held copy
    assert not any(s.valid for s in states[12:])


def test_a_group_holds_a_glitch_as_its_follower_alone(gestures):
    perfs = [_glitched(gestures), gestures["circle"].copy(), _glitched(gestures, 0.3)]
    perfs[1][11] = np.nan   # lost in the same tick
    perfs[2][12, 1] = -0.3  # two far samples in a row: row 12 followed, row 13 (back) held
    kinds = ["none", "scale", "scale"]
    alone = [ActionFollower(gestures, invariance=k) for k in kinds]
    group = FollowerGroup([ActionFollower(gestures, invariance=k) for k in kinds])
    _step_both(alone, group, perfs)
    end = group.followers[0]._state
    assert end.best == "circle" and end.valid
    assert [f.glitches for f in group.followers] == [f.glitches for f in alone] == [1, 0, 2]


def test_a_group_fed_absurd_samples_keeps_stepping_as_its_follower_alone(gestures):
    # two samples of 1e30 in a row (a broken stream, under the inputs' 1e100 bound): the
    # compiled group divided by zero on every tick from there on (ZeroDivisionError: the
    # MOP engine stopped for good) where the follower, in numpy, went on; after a rest the
    # next circle is recognised by both
    perf = gestures["circle"].copy()
    perf[11:13, 0] = 1e30
    rest = np.repeat(gestures["circle"][-1:], 40, axis=0)
    stream = np.vstack([perf, rest, gestures["circle"], rest])
    alone = ActionFollower(gestures, invariance="scale")
    group = FollowerGroup([ActionFollower(gestures, invariance="scale")])
    with np.errstate(all="ignore"):
        pairs = [(group.step([x])[0], alone.step(x)) for x in stream]
    assert [(g.best, g.valid) for g, _ in pairs] == [(a.best, a.valid) for _, a in pairs]
    again = pairs[len(perf) + len(rest):][:len(gestures["circle"])]
    assert again[-1][0].best == "circle" and sum(g.valid for g, _ in again) >= 30
