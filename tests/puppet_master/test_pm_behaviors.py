"""Behaviour tests: demonstrated personalities carried onto new main paths (measured)."""

import numpy as np
from tests.puppet_master import demos as pm_demos

from behaviors.puppet_master.engine import Behavior, Reactor

TABLE = (0.0, 0.0, pm_demos.TABLE[0], pm_demos.TABLE[1])


def run(behavior: Behavior, main: np.ndarray, table=TABLE):
    """Feed a main path sample by sample; returns (rows (m, 4), choices, reactor)."""
    reactor = Reactor(behavior, table, max_backlog=None)
    rows, choices = [], []
    for sample in main:
        new = reactor.advance(*sample)
        rows += new
        choices += [reactor.last_choice] * len(new)
    return np.array(rows), choices[1:], reactor


def main_at(main: np.ndarray, t: np.ndarray) -> np.ndarray:
    """The main pose (x, y, unwrapped dir) interpolated at times t."""
    return np.column_stack([np.interp(t, main[:, 0], main[:, 1]),
                            np.interp(t, main[:, 0], main[:, 2]),
                            np.interp(t, main[:, 0], np.unwrap(main[:, 3]))])


def direction_jitter(xy: np.ndarray, rate_hz: float = 40.0, min_speed: float = 0.05) -> float:
    """RMS change of movement direction between consecutive steps while moving (rad)."""
    step = np.diff(xy, axis=0)
    speed = np.hypot(step[:, 0], step[:, 1]) * rate_hz
    ang = np.arctan2(step[:, 1], step[:, 0])
    turn = np.angle(np.exp(1j * np.diff(ang)))
    ok = (speed[1:] > min_speed) & (speed[:-1] > min_speed)
    return float(np.sqrt(np.mean(turn[ok] ** 2)))


def test_follow_behind_keeps_its_distance_behind_the_main():
    demo = pm_demos.follow_behind(pm_demos.main_path(1, 90), distance=0.3)
    live = pm_demos.main_path(2, 60, rate_hz=30)        # a new path, at another input rate
    out, _, _ = run(Behavior.train(demo), live)
    m = main_at(live, out[:, 0])
    d = out[:, 1:3] - m[:, :2]
    dist = np.hypot(d[:, 0], d[:, 1])
    ahead = np.cos(m[:, 2]) * d[:, 0] + np.sin(m[:, 2]) * d[:, 1]
    assert 0.2 <= np.median(dist) <= 0.4                 # measured 0.32
    assert np.mean(ahead < 0) >= 0.7                     # measured 1.0


def test_keep_away_never_lets_the_main_close_and_stays_on_the_table():
    demo = pm_demos.keep_away(3, 120)
    demo_min = float(np.min(np.hypot(demo[:, 4] - demo[:, 1], demo[:, 5] - demo[:, 2])))
    live = pm_demos.main_path(4, 60, rate_hz=30, reversals=True)   # stops and sudden reversals
    assert np.any(np.abs(np.diff(np.unwrap(live[:, 3]))) > 3.0)   # it does reverse
    out, _, _ = run(Behavior.train(demo), live)
    m = main_at(live, out[:, 0])
    dist = np.hypot(out[:, 1] - m[:, 0], out[:, 2] - m[:, 1])
    assert np.mean(dist < demo_min) < 0.05               # measured 0.023
    x0, y0, x1, y1 = TABLE
    assert np.all((out[:, 1] >= x0) & (out[:, 1] <= x1) & (out[:, 2] >= y0) & (out[:, 2] <= y1))


def test_circling_goes_counter_clockwise():
    demo = pm_demos.circling(pm_demos.main_path(5, 90), radius=0.25, omega=2.0)
    live = pm_demos.main_path(6, 60, rate_hz=30)
    out, _, _ = run(Behavior.train(demo), live)
    m = main_at(live, out[:, 0])
    bearing = np.arctan2(out[:, 2] - m[:, 1], out[:, 1] - m[:, 0])
    turn = np.angle(np.exp(1j * np.diff(bearing)))
    assert np.mean(turn > 0) >= 0.7                      # measured 0.97
    # mirrored demonstration: the same test fails for clockwise circling
    mirrored = demo.copy()
    mirrored[:, [2, 5]] = 1.0 - mirrored[:, [2, 5]]
    mirrored[:, [3, 6]] = -mirrored[:, [3, 6]]
    out, _, _ = run(Behavior.train(mirrored), live)
    bearing = np.arctan2(out[:, 2] - m[:, 1], out[:, 1] - m[:, 0])
    assert np.mean(np.angle(np.exp(1j * np.diff(bearing))) > 0) < 0.3   # measured 0.06


def test_balancing_holds_the_target_ratio_without_coherence_loops():
    demo = pm_demos.follow_behind(pm_demos.main_path(21, 90))
    live = pm_demos.main_path(22, 180, rate_hz=30)       # three minutes
    _, choices, reactor = run(Behavior.train(demo), live)
    coherent = np.array(choices) == "coherence"
    assert abs(coherent.mean() - 0.5) < 0.05             # measured 0.499
    blocks = coherent[:coherent.size // 400 * 400].reshape(-1, 400).mean(axis=1)
    assert np.all((blocks > 0.25) & (blocks < 0.75))     # every 10 s stays balanced
    runs, n = [], 0
    for c in coherent:
        n = n + 1 if c else 0
        runs.append(n)
    assert max(runs) < 160                               # no 4-second coherence loop (measured 107)
    assert 0.3 < reactor.coherence_share < 0.7
    # a target of 3:1 situation to coherence is followed as well
    _, choices, _ = run(Behavior.train(demo, ratio=3.0), live[:live.shape[0] // 2])
    assert abs(np.mean(np.array(choices) == "coherence") - 0.25) < 0.05   # measured 0.24


def test_a_static_weight_does_not_balance():
    demo = pm_demos.follow_behind(pm_demos.main_path(21, 90))
    live = pm_demos.main_path(22, 60, rate_hz=30)
    _, choices, _ = run(Behavior.train(demo, balance_gain=1e-12), live)
    assert abs(np.mean(np.array(choices) == "coherence") - 0.5) > 0.2   # measured 0.0


def test_texture_shaky_demonstration_gives_shaky_output_smooth_gives_smooth():
    main = pm_demos.main_path(7, 90)
    live = pm_demos.main_path(8, 60, rate_hz=30)
    smooth = Behavior.train(pm_demos.follow_behind(main))
    shaky = Behavior.train(pm_demos.follow_behind(main, wobble=0.6, wobble_hz=6.0))
    j_demo_smooth = direction_jitter(smooth.react[:, :2])
    j_demo_shaky = direction_jitter(shaky.react[:, :2])
    assert j_demo_shaky > 3 * j_demo_smooth              # the demonstrations differ (0.39 vs 0.07)
    out_smooth, _, _ = run(smooth, live)
    out_shaky, _, _ = run(shaky, live)
    j_smooth = direction_jitter(out_smooth[:, 1:3])
    j_shaky = direction_jitter(out_shaky[:, 1:3])
    assert j_shaky > 1.5 * j_smooth                      # measured 0.39 vs 0.12
    assert j_smooth < 0.6 * j_demo_shaky
    # with the paper's step toward the target, the detail is what carries it: without detail
    # the shaky output loses texture (the relative step carries the demonstrated wobble itself)
    flat = Behavior.train(pm_demos.follow_behind(main, wobble=0.6), detail_clip=1e-9,
                          relative_motion=0.0)
    out_flat, _, _ = run(flat, live)
    # measured 0.29 vs 0.39; 0.32 with the main's still/moving state among the features of
    # a follower that stops with its main (features.main_still)
    assert direction_jitter(out_flat[:, 1:3]) < 0.85 * j_shaky


def test_runs_are_reproducible_to_the_last_digit():
    demo = pm_demos.circling(pm_demos.main_path(5, 30))
    live = pm_demos.main_path(6, 15, rate_hz=30)
    a, _, _ = run(Behavior.train(demo), live)
    b, _, _ = run(Behavior.train(demo), live)
    assert np.array_equal(a, b)
