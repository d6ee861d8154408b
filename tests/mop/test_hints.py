"""Early feedback (behaviors.mop.hints): the likeliest actions are shown faintly from the
sample a gesture leaves its rest radius, and never on a still puck."""

import numpy as np

from bench.hint_still import (JITTER_M, jittered_rest, lifted_puck, still_finger,
                               touch_config, validated_table)
from tabletop.drawing.life import hint_level
from tabletop.frames import Touch
from tabletop.plugins.mop_table import RATE, G, Table, build


def _left_rest(name, radius=0.003):
    """Progress at which gesture ``name`` first lies ``radius`` metres from its start."""
    g = G.gesture(name)
    d = np.hypot(g[:, 1] - g[0, 1], g[:, 2] - g[0, 2])
    return float(g[np.argmax(d > radius), 0] / g[-1, 0])


def test_a_gesture_is_hinted_from_the_sample_it_leaves_its_rest(example_cfg):
    """Counted in samples from the first one at or past the progress where the puck lies 3 mm
    from its start (0.100 / 0.111). Measured: the first hint 1 / 0 samples after it (at 0.117
    / 0.111); with the engagement onset gating them, the circle's 5 samples after (0.150)."""
    rng = np.random.default_rng(1)
    for name in ("circle", "line"):
        table = validated_table(example_cfg)
        jittered_rest(table, 0.9, rng)
        run = table.perform(name, noise=JITTER_M, seed=2, upto=0.4)
        first = next(k for k, (u, ch) in enumerate(run) if hint_level(ch["dancer"]) > 0.03)
        left = next(k for k, (u, _) in enumerate(run) if u >= _left_rest(name))
        driven = next(k for k, (u, ch) in enumerate(run) if ch["dancer"].valid)
        assert first - left <= 2, (name, first - left)
        assert first < driven
        hinted = [hint_level(ch["dancer"]) for _, ch in run[first:driven]]
        assert min(hinted) > 0.03 and max(hinted) <= 1.0    # shown all along, never driving


def test_a_still_puck_is_never_hinted(example_cfg):
    """A puck standing still from the first frame, 0.7 mm of jitter: this draw crosses the
    3 mm rest radius by jitter alone in its first samples (4 samples at 0.67-0.80 would be
    hinted if only a rest silenced the hints)."""
    table = validated_table(example_cfg)
    still = jittered_rest(table, 3.0, np.random.default_rng(13))
    assert max(hint_level(ch[c]) for ch in still for c in ("dancer", "bird")) == 0.0


def test_a_stream_without_stillness_is_hinted_by_its_follower_alone(tmp_path):
    """A stream's columns tell no stillness (no rest radius): its hints are its follower's
    (the engagement onset), as it never reports a stillness to wait for. Measured: first
    hint at 0.133 of the circle, driven from 0.267."""
    circle, wave = G.gesture("circle"), G.gesture("wave")
    for name, g in (("circle", circle), ("wave", wave)):
        np.savetxt(tmp_path / f"{name}.csv", g[:, :3], delimiter=",", header="t,arm_0,arm_1",
                   comments="")
    data = {"sources": [{"kind": "scripted"}], "engines": [{
        "kind": "mop",
        "performers": [{"name": "body", "inputs": [{"kind": "stream", "name": "arm",
                                                    "columns": [0, 1]}]}],
        "characters": [{"name": "face", "kind": "face", "performer": "body", "actions": [
            {"name": "circle", "template": "circle.csv", "motion": "laugh"},
            {"name": "wave", "template": "wave.csv", "motion": "talk"}]}]}]}
    table = Table(build(data, tmp_path))
    rng = np.random.default_rng(4)
    for _ in range(30):
        table.streams = {"arm": rng.normal(0, JITTER_M, 2)}
        table.tick()
    hinted, driven = [], []
    dur = circle[-1, 0]
    for k in range(int(dur * RATE)):
        u = k / (dur * RATE)
        row = [np.interp(u * dur, circle[:, 0], circle[:, j]) for j in (1, 2)]
        table.streams = {"arm": np.array(row) + rng.normal(0, JITTER_M, 2)}
        face = table.tick()["face"]
        hinted.append(hint_level(face) > 0.03)
        driven.append(face.valid)
    assert any(hinted) and hinted.index(True) < driven.index(True)


def test_a_puck_lifted_and_put_down_still_is_never_hinted(example_cfg):
    """A puck rests, is lifted for 1 s and put down elsewhere, still, with 0.7 mm of jitter.
    Measured: none of these 3 draws is hinted; each would be (4, 6, 10 frames within 0.45 s
    of the put-down) were the lift counted as a rest. bench/hint_still.py runs 8 draws (7
    would be hinted)."""
    for seed in range(3):
        assert lifted_puck(example_cfg, seed) == 0.0, seed


def test_a_finger_is_hinted_from_touch_down_but_not_held_still(example_cfg):
    """A finger's touch-down starts a stroke: a circle drawn straight from it is hinted
    (measured: from its sample 16 of 120, driven from sample 34), while a finger
    put down and held still is not (draw 3 would be hinted 12 frames were its touch-down
    counted as calm; bench/hint_still.py runs draws 0-5, the others hinted either way)."""
    g = G.gesture("circle")
    for seed in (3, 5):   # (the circle follows draw 5's)
        still, table, rng = still_finger(touch_config(example_cfg), seed)
        assert max(still) == 0.0, seed
    table.touches = ()
    for _ in range(30):
        table.tick()
    dur, hinted, driven = g[-1, 0], [], []
    for k in range(int(dur * RATE)):
        t = k / RATE
        x, y = (np.interp(t, g[:, 0], g[:, j]) - g[0, j] for j in (1, 2))
        table.touches = (Touch(2, 0.6 + x + rng.normal(0, JITTER_M),
                               0.4 + y + rng.normal(0, JITTER_M)),)
        chars = table.tick().values()
        hinted.append(max(hint_level(c) for c in chars) > 0.03)
        driven.append(any(c.valid for c in chars))
    assert any(hinted) and hinted.index(True) < driven.index(True)
