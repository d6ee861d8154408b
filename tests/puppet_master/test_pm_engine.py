"""The engine's API: training checks, starting, live robustness, causality, the table."""

import math

import numpy as np
from tests.puppet_master import demos as pm_demos
import pytest

from behaviors.puppet_master.engine import Behavior, DemonstrationError, ParameterError, Reactor
from tabletop.frames import InputError

TABLE = (0.0, 0.0, 1.6, 1.0)


@pytest.fixture(scope="module")
def demo() -> np.ndarray:
    return pm_demos.follow_behind(pm_demos.main_path(31, 20))


@pytest.fixture(scope="module")
def behavior(demo) -> Behavior:
    return Behavior.train(demo)


def test_training_resamples_to_the_generation_rate(demo, behavior):
    assert issubclass(DemonstrationError, InputError)
    assert behavior.samples == 801                          # 20 s at 40 Hz, both ends
    assert np.allclose(np.diff(behavior.t), 0.025)
    b20 = Behavior.train(demo, rate_hz=20.0, window=20)
    assert b20.samples == 401 and b20.params.window == 20


@pytest.mark.parametrize("mutate, words", [
    (lambda d: d[:30], ["lasts", "needs at least", "window of 40"]),
    (lambda d: np.where((np.arange(d.shape[0])[:, None] == 7) & (np.arange(7) == 1), np.nan, d),
     ["row 8", "main_x", "nan"]),
    (lambda d: d[[0, 1, 2, 4, 3] + list(range(5, d.shape[0]))], ["row 5", "strictly increase"]),
    (lambda d: d[:, :6], ["shape", "react_dir"]),
    (lambda d: d[:1], ["1 row"]),
])
def test_bad_demonstrations_get_clear_messages(demo, mutate, words):
    with pytest.raises(DemonstrationError) as err:
        Behavior.train(mutate(demo.copy()))
    for w in words:
        assert w in str(err.value)


def test_bad_parameters_get_clear_messages(demo):
    with pytest.raises(ParameterError, match="unknown behaviour parameter.*wobble"):
        Behavior.train(demo, wobble=1)
    with pytest.raises(ParameterError, match=r"parameter\(s\) windw \(window\?\), wobble;"):
        Behavior.train(demo, windw=40, wobble=1)     # a behavior.yaml edited by hand
    with pytest.raises(ParameterError, match="window"):
        Behavior.train(demo, window=0)
    with pytest.raises(ParameterError, match="rate_hz"):
        Behavior.train(demo, rate_hz=-1.0)
    with pytest.raises(ParameterError, match="table"):
        Reactor(Behavior.train(demo), (1.0, 0.0, 0.0, 1.0))


def test_start_carries_the_demonstrated_relative_pose_onto_the_main(demo, behavior):
    r = Reactor(behavior, TABLE)
    x, y, d = r.start(5.0, 0.8, 0.5, math.pi / 2)
    # the demonstration starts 0.3 m behind its main, looking the same way
    assert abs(x - 0.8) < 1e-9 and abs(y - 0.2) < 1e-9 and abs(d - math.pi / 2) < 1e-9
    assert r.coherence_share == 0.5                     # the target share until choices are made


def test_rows_come_on_the_generation_grid_and_depend_only_on_the_past(behavior):
    live = pm_demos.main_path(32, 10, rate_hz=30)
    a = Reactor(behavior, TABLE, max_backlog=None)
    rows = [row for s in live for row in a.advance(*s)]
    t = np.array([r[0] for r in rows])
    assert np.allclose(np.diff(t), 0.025) and t[-1] <= live[-1, 0] + 1e-9
    # the same past with a different future: identical rows up to the cut
    cut = 150
    changed = live.copy()
    changed[cut:, 1] += 0.3
    b = Reactor(behavior, TABLE, max_backlog=None)
    rows_b = [row for s in changed for row in b.advance(*s)]
    upto = sum(1 for r in rows if r[0] < live[cut, 0])
    assert rows[:upto] == rows_b[:upto]
    assert rows[upto + 1:] != rows_b[upto + 1:]


def test_live_input_glitches_are_ignored(behavior):
    r = Reactor(behavior, TABLE)
    r.start(0.0, 0.8, 0.5, 0.0)
    assert r.advance(0.1, 0.81, 0.5, 0.0)
    before = r.pose
    assert r.advance(0.1, 5.0, 5.0, 0.0) == []        # same time again
    assert r.advance(0.05, 5.0, 5.0, 0.0) == []       # older
    assert r.advance(0.2, math.nan, 0.5, 0.0) == []   # not finite
    assert r.pose == before
    pose = r.update(0.23, 0.82, 0.5, 0.0)
    assert all(math.isfinite(v) for v in pose)


def test_a_long_gap_is_skipped_not_replayed(behavior):
    r = Reactor(behavior, TABLE, max_backlog=1.0)
    r.start(0.0, 0.8, 0.5, 0.0)
    rows = r.advance(60.0, 0.8, 0.5, 0.0)
    assert 40 <= len(rows) <= 41                        # one second of steps, not sixty
    assert abs(rows[-1][0] - 60.0) < 1e-9


def test_the_reactor_stays_on_a_small_table(behavior):
    table = (0.3, 0.2, 0.9, 0.6)
    live = pm_demos.main_path(33, 20, rate_hz=30)
    r = Reactor(behavior, table)
    for s in live:
        x, y, _ = r.update(*s)
        assert table[0] <= x <= table[2] and table[1] <= y <= table[3]


def test_several_reactors_share_one_behavior_independently(behavior):
    live = pm_demos.main_path(34, 5, rate_hz=40)
    a, b = Reactor(behavior, TABLE), Reactor(behavior, TABLE)
    for s in live:
        pa = a.update(*s)
        pb = b.update(*s)
        assert pa == pb
    solo = Reactor(behavior, TABLE)
    for s in live:
        ps = solo.update(*s)
    assert ps == pa
