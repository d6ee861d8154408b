"""The scripted designers: each personality shows in the demonstration, measured."""

import numpy as np
import pytest

from behaviors.puppet_master import designers as D

RATE = 40.0


def _speed(xy: np.ndarray, k: int = 10) -> np.ndarray:
    """Speed (m/s) over a 0.5 s span, which averages the hand's shake out."""
    v = np.empty(len(xy))
    v[k:-k] = np.hypot(*(xy[2 * k:] - xy[:-2 * k]).T) * RATE / (2 * k)
    v[:k], v[-k:] = v[k], v[-k - 1]
    return v


def _held(mask: np.ndarray, samples: int) -> np.ndarray:
    """True where ``mask`` has held for more than ``samples`` samples in a row."""
    run = np.zeros(len(mask), dtype=int)
    c = 0
    for i, m in enumerate(mask):
        c = c + 1 if m else 0
        run[i] = c
    return run > samples


def _dist(d: np.ndarray) -> np.ndarray:
    return np.hypot(d[:, 4] - d[:, 1], d[:, 5] - d[:, 2])


@pytest.fixture(scope="module")
def demos() -> dict[str, np.ndarray]:
    return {p: D.demonstrate(p) for p in D.PERSONALITIES}


@pytest.mark.parametrize("name", D.PERSONALITIES)
def test_shape_time_grid_and_table(demos, name):
    d = demos[name]
    assert d.shape == (round(D.DURATION_S.get(name, 60.0) * RATE), 7)    # afraid: 80 s
    assert np.isfinite(d).all()
    assert np.allclose(np.diff(d[:, 0]), 1 / RATE) and d[0, 0] == 0.0
    for col in (3, 6):
        assert (d[:, col] > -np.pi).all() and (d[:, col] <= np.pi).all()
    assert (d[:, (1, 4)] >= 0).all() and (d[:, (1, 4)] <= 1.2).all()
    assert (d[:, (2, 5)] >= 0).all() and (d[:, (2, 5)] <= 0.8).all()
    # two pucks never overlap (centres at least about a puck apart)
    assert _dist(d).min() >= 0.04


def test_deterministic_and_seeded():
    a = D.demonstrate("bully", seed=3, seconds=10)
    b = D.demonstrate("bully", seed=3, seconds=10)
    c = D.demonstrate("bully", seed=4, seconds=10)
    assert a.tobytes() == b.tobytes()
    assert np.abs(a - c).max() > 0.05
    assert np.array_equal(D.lover(), D.demonstrate("lover"))


def test_main_path_pauses_moves_and_reverses():
    m = D.designer_main_path(7, seconds=120)
    v = _speed(m[:, 1:3])
    assert 0.03 < _held(v < 0.02, 20).mean() < 0.5        # pauses of over half a second
    assert 0.1 < np.percentile(v, 90) < 0.4                  # hand speeds, m/s
    step = np.diff(m[:, 1:3], axis=0)
    heading = np.arctan2(step[:, 1], step[:, 0])
    moving = np.hypot(*step.T) * RATE > 0.06
    later = np.roll(heading, -20)                            # 0.5 s later
    turned = np.abs(np.angle(np.exp(1j * (later - heading))))
    assert ((turned > 2.5) & moving & np.roll(moving, -20)).any()   # a sudden reversal


def test_lover_stays_close_facing_the_main(demos):
    d = demos["lover"]
    dist = _dist(d)
    assert np.median(dist) < 0.16 and np.percentile(dist, 95) < 0.25
    to_main = np.arctan2(d[:, 2] - d[:, 5], d[:, 1] - d[:, 4])
    off = np.abs(np.angle(np.exp(1j * (d[:, 6] - to_main))))
    assert np.median(off) < 0.3


def test_bully_charges_pushes_and_backs_off(demos):
    d = demos["bully"]
    dist = _dist(d)
    charges, armed = 0, True
    for x in dist:                       # contact after being at least 0.2 m away
        if armed and x < 0.08:
            charges, armed = charges + 1, False
        if x > 0.2:
            armed = True
    assert charges >= 8
    assert np.percentile(_speed(d[:, 4:6], 4), 95) > 0.35   # charges are fast
    assert np.median(dist) > 0.2                             # and it backs off between them


def test_playful_friend_circles_counter_clockwise(demos):
    d = demos["playful_friend"]
    bearing = np.unwrap(np.arctan2(d[:, 5] - d[:, 2], d[:, 4] - d[:, 1]))
    assert (np.diff(bearing) > 0).mean() > 0.85
    dist = _dist(d)
    assert 0.1 < np.median(dist) < 0.25
    assert np.percentile(dist, 5) < 0.1                      # darts in close


def test_stalker_follows_behind_and_stops_when_it_stops(demos):
    d = demos["stalker"]
    dist = _dist(d)
    assert 0.25 < np.median(dist) < 0.4
    mv, rv = _speed(d[:, 1:3]), _speed(d[:, 4:6])
    c, s = np.cos(d[:, 3]), np.sin(d[:, 3])
    ahead = c * (d[:, 4] - d[:, 1]) + s * (d[:, 5] - d[:, 2])
    assert (ahead < 0)[mv > 0.05].mean() > 0.7
    still = _held(mv < 0.02, 20)
    assert still.sum() > 40
    assert np.median(rv[still]) < 0.02 < 0.1 < np.median(rv[mv > 0.08])


def test_afraid_keeps_away_and_flees_when_chased(demos):
    d = demos["afraid"]
    dist = _dist(d)
    assert np.median(dist) > 0.33 and np.percentile(dist, 5) > 0.1     # measured 0.38, 0.13
    assert np.median(dist) > 3 * np.median(_dist(demos["lover"]))
    # the designer's main goes after it, so the demonstration shows fleeing: close often,
    # and fast while close (measured 55% within 0.4 m, speeds 0.39 vs 0.04 m/s)
    assert np.mean(dist < 0.4) > 0.3
    rv = _speed(d[:, 4:6], 4)
    assert np.median(rv[dist < 0.3]) > 2.5 * np.median(rv[dist > 0.5])


@pytest.mark.parametrize("name", D.PERSONALITIES)
def test_hands_shake_a_little(demos, name):
    d = demos[name]
    k = np.ones(9) / 9
    for col in (1, 4):
        smooth = np.convolve(d[:, col], k, mode="same")
        resid = (d[:, col] - smooth)[10:-10]
        assert 0.0004 < np.sqrt(np.mean(resid ** 2)) < 0.005     # metres


def test_the_designers_own_character_on_another_path_is_the_fidelity_reference(demos):
    # reaction_on_grid plays a personality against a main path it was not made on, on the
    # generation grid: the reference bench/fidelity.py sets beside each generated reactor
    from behaviors.puppet_master import fidelity
    from tests.puppet_master.demos import unseen_main_paths
    paths = unseen_main_paths(0, 40.0, (1.2, 0.8))
    for path in ("slow_pauses_30hz", "fast_reversals_60hz"):
        main = paths[path]
        rows = {}
        for name in ("stalker", "afraid"):
            d = demos[name]
            demo = fidelity.figures(d[:, 1:4], d[:, 4:7], RATE, 2 * np.pi)
            t, react = D.reaction_on_grid(name, main, RATE)
            assert np.allclose(np.diff(t), 1 / RATE) and t[0] == main[0, 0]
            assert main[-1, 0] - 1 / RATE <= t[-1] <= main[-1, 0]
            grid = fidelity.main_on_grid(main, t)
            rows[name] = fidelity.compare(demo, fidelity.figures(grid, react, RATE, 2 * np.pi))
        # the stalker's own character keeps its demonstrated figures there (measured speed W1
        # 0.026 and 0.021 m/s against 0.044 allowed, facing 1.0 and 0.99)
        assert rows["stalker"]["ok_facing"] and rows["stalker"]["ok_speed"], rows["stalker"]
        # the afraid one's facing share depends on its main: the demonstration's main goes for
        # it about half of the time and it faced the main 24% of it; these mains never chase
        # it (measured 0.74 and 0.77)
        assert rows["afraid"]["gen_facing"] > rows["afraid"]["demo_facing"] + 0.3, rows["afraid"]
