"""What a MOP take recorded in the studio keeps: the stills before and after the gesture left out
(also with tracking jitter, and rests longer than the puck's rest time), a hold within it kept."""

import numpy as np
import pytest

from tabletop.plugins.mop_table import G, RATE, build, designer_config
from tabletop.studio.mop_table import StudioTable


def test_the_stills_before_and_after_a_take_are_no_part_of_its_action(tmp_path):
    """A designer waits after the countdown and before stopping: the still samples at both ends
    are left out, so the action's progress reaches its end with the gesture's (it stopped at
    0.84 with 0.4 s still on each side of the zigzag) and the rest after it drives nothing (the
    held end kept it driven for 0.7 s of the rest); a take where nothing moved is refused."""
    engine = build(designer_config(tmp_path), tmp_path)
    table = StudioTable(engine, tmp_path / "lib", focus="mop/lizard")
    table.rest(1.0)
    table.tick(["designer.record"])
    table.rest(0.4)
    table.perform("zigzag")
    table.rest(0.4)
    table.stop_take()
    assert table.studio.state == "trying"
    n = len(engine.templates["lizard"]["take1"][1])
    gesture_samples = G.gesture("zigzag")[-1, 0] * engine.rate_hz
    # (its own slowest first and last samples are as still)
    assert 0.75 * gesture_samples <= n <= gesture_samples + 2, (n, gesture_samples)
    table.rest(1.2)
    run = table.perform("zigzag", speed=lambda u: 1.2)
    shown = [ch["lizard"].progress for _, ch in run
             if ch["lizard"].valid and ch["lizard"].action == "take1"]
    assert len(shown) > 0.6 * len(run) and max(shown) > 0.95
    after = table.rest(1.0)
    assert not any(ch["lizard"].valid for ch in after[int(0.3 * RATE):])
    # nothing moved: too short, and no action is made of it
    table.tick(["designer.discard"])
    table.tick(["designer.record"])
    table.rest(2.0)
    table.tick(["designer.record"])
    assert "too short" in table.status and "take2" not in engine.puppets["lizard"].actions


def _jittered_rest(table, seconds, rng, jitter):
    """The puck still where it is for ``seconds``, tracked with ``jitter`` metres of noise."""
    x0, y0 = table.pucks[1]
    for _ in range(int(seconds * RATE)):
        table.pucks[1] = (x0 + rng.normal(0, jitter), y0 + rng.normal(0, jitter))
        table.tick()
    table.pucks[1] = (x0, y0)


@pytest.mark.parametrize("jitter", [0.0, 0.0003])
def test_a_take_rested_longer_than_the_rest_time_and_tracked_with_jitter_is_trimmed(
        tmp_path, jitter):
    """A designer waits 1.5 s (longer than the puck's 0.8 s rest time) after the countdown and
    before stopping, tracked with 0.3 mm of jitter: the take keeps its gesture's samples and ends
    where the gesture ended (it kept the hold and a jump back to 0, 0 after the rest: 72 samples
    of the gesture's 54; with the jitter the stills at both ends too: 92)."""
    engine = build(designer_config(tmp_path), tmp_path)
    table = StudioTable(engine, tmp_path / "lib", focus="mop/lizard")
    rng = np.random.default_rng(3)
    table.rest(1.0)
    table.tick(["designer.record"])
    _jittered_rest(table, 1.5, rng, jitter)
    table.perform("zigzag", noise=jitter, seed=4)
    _jittered_rest(table, 1.5, rng, jitter)
    table.stop_take()
    assert table.studio.state == "trying"
    samples = engine.templates["lizard"]["take1"][1]
    g = G.gesture("zigzag")
    n = g[-1, 0] * engine.rate_hz     # 54 samples of a zigzag; up to 0.15 s more at each end
    assert 0.75 * n <= len(samples) <= n + 2 + 0.3 * engine.rate_hz, (len(samples), n)
    assert np.hypot(*(samples[-1, :2] - g[-1, 1:3])) < 0.003, (samples[-1], g[-1])


def test_a_take_paused_longer_than_the_rest_time_keeps_its_hold_and_goes_on_from_it(tmp_path):
    """A designer's raise, hold (1.5 s, longer than the puck's 0.8 s rest time), return: the
    take holds where the puck held and goes on from there, as the puck did. The rest moved the
    path features' origin to where the puck settled: the hold was left out and the return
    recorded from 0, 0 (a jump of half the gesture's extent)."""
    engine = build(designer_config(tmp_path), tmp_path)
    table = StudioTable(engine, tmp_path / "lib", focus="mop/lizard")
    table.rest(1.0)
    table.tick(["designer.record"])
    table.rest(0.3)
    x0, y0 = table.pucks[1]
    table.perform("zigzag", upto=0.5)
    held = table.pucks[1]
    table.rest(1.5)
    g = G.gesture("zigzag")
    dur, tau = g[-1, 0], 0.5 * g[-1, 0]
    while tau < dur:
        table.pucks[1] = (x0 + np.interp(tau, g[:, 0], g[:, 1]),
                          y0 + np.interp(tau, g[:, 0], g[:, 2]))
        table.tick()
        tau += 1.0 / RATE
    table.rest(0.3)
    table.stop_take()
    assert table.studio.state == "trying"
    samples = engine.templates["lizard"]["take1"][1][:, :2]
    steps = np.hypot(*np.diff(samples, axis=0).T)
    assert steps.max() < 0.035, steps.max()   # the zigzag's own fastest step: 0.024 m
    at_hold = np.hypot(*(samples - (held[0] - x0, held[1] - y0)).T) < 0.001
    assert at_hold.sum() >= 1.2 * engine.rate_hz, at_hold.sum()
    assert np.hypot(*(samples[-1] - g[-1, 1:3])) < 0.003, (samples[-1], g[-1])
