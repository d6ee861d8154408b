"""The compiled generation step (behaviors/puppet_master/step_kernel.py) is the Python step
(engine.Reactor._step) to the last bit: every pose, choice and source, on every kind of
demonstration, with other characters to keep apart from, input gaps and a change of main;
and the displayed pose between two steps (Reactor.update) with them."""

import math

import numpy as np
import pytest

from behaviors.puppet_master.engine import Behavior, Reactor
from behaviors.puppet_master.step_kernel import hypot, remainder, wrap_angle
from tabletop.frames import wrap_angle as wrap_angle_py
from tabletop import examples, library
from tests.puppet_master import demos

TABLE = (0.0, 0.0, 1.6, 1.0)


def _run(behavior: Behavior, main: np.ndarray, compiled: bool, crowd: int = 0):
    r = Reactor(behavior, TABLE)
    r.compiled = compiled
    rows, trace, shown = [], [], []
    for k, sample in enumerate(main):
        if k % 97 in (5, 6, 7):          # input gaps: several steps from one sample
            continue
        if k == len(main) // 2:          # another main from here (one of several mains)
            r.rebind(sample[0], sample[1] + 0.2, sample[2], sample[3] + 1.0)
            continue
        # a character to keep apart from, wandering over the reactor's ground
        r.obstacles = [(0.8 + 0.5 * math.sin(k / 40), 0.5 + 0.3 * math.cos(k / 55), 0.1)] \
            if k % 300 < 200 else []
        if crowd and r.started and k % 300 >= 250:   # a crowd round the reactor: more rows
            r.obstacles = [(r.pose[0] + 0.1 * math.cos(i + k / 30),   # than its first buffer
                            r.pose[1] + 0.1 * math.sin(i + k / 30), 0.08 + 0.02 * (i % 3))
                           for i in range(crowd)]
        if k % 3 == 0:   # the display's call: the pose moved on between steps, kept apart
            before = r.i if r.started else -1
            if r.started and k % 300 < 200:     # one right beside the reactor
                r.obstacles = r.obstacles + [(r.pose[0] + 0.02, r.pose[1] - 0.01, 0.05)]
            shown.append(r.update(*sample))
            out = [] if r.i == before else [r.pose]
        else:
            out = r.advance(*sample)
            rows.extend(out)
        if out:
            trace.append((r.source, r.last_choice, r.coherence_share, r.k, *r.pose))
    # compiled: the searches and the step as one call (match_step_kernel), not the four
    # calls kept for searches of another kind (tests/puppet_master/test_pm_fast_search.py)
    assert r._fused or not compiled
    return np.asarray(rows, dtype=float), trace, np.asarray(shown, dtype=float)


@pytest.mark.parametrize("kind,rate,params,duration", [
    ("follow", 40.0, {}, 20.0),
    ("circling", 30.0, {"half_life": 10.0}, 20.0),
    ("keep_away", 55.0, {"relative_motion": 0.0}, 20.0),
    # with the room on the table among the situation features (features.room_at)
    ("keep_away", 40.0, {"w_room": 2.0, "table_width": 1.2, "table_height": 0.8}, 20.0),
    # the main's still/moving state and the room both among the situation features
    ("follow", 40.0, {"w_room": 2.0, "table_width": 1.2, "table_height": 0.8}, 20.0),
    # with targets fitted off the edges (Params.edge_percentile, Reactor.target_table)
    ("keep_away", 40.0, {"edge_percentile": 50.0, "table_width": 1.2, "table_height": 0.8},
     20.0),
    ("follow", 40.0, {}, 1.5),      # shorter than look.train_place's span
    ("playful_friend", 45.0, {}, 0.0),  # shipped; touches its main: no personal space
    ("bully", 30.0, {}, 0.0),           # shipped; charges held in the world
    ("stalker", 40.0, {}, 0.0),         # shipped; its drift corrected at the moment's pace
    ("lover", 30.0, {}, 0.0),           # shipped; the mean of its raw steps capped
])
def test_the_compiled_step_equals_the_python_step_bit_for_bit(kind, rate, params, duration):
    shipped = kind in ("playful_friend", "bully", "stalker", "lover")
    if shipped:
        stored = library.load_behavior(examples.DEFAULT_OUT / kind)
        demo, params = stored.demonstration, stored.parameters
    elif kind == "keep_away":
        demo = demos.keep_away(3, duration, rate_hz=40.0)
    else:
        m = demos.main_path(3, duration, rate_hz=40.0, reversals=kind == "circling")
        demo = demos.circling(m) if kind == "circling" else demos.follow_behind(m)
    b = Behavior.train(demo, **params)
    # the main's still/moving state among the situation features where the reactor stops
    # with its main (the follower, the stalker) or keeps away from it (a personal space, not
    # walking with its main: the keep-away and circling characters), then the room
    still = kind in ("follow", "stalker", "keep_away", "circling")
    assert (b.scales.still > 0.0) == still
    # the steps since the last push where the demonstration charges again and again, or
    # circles its main and darts into it (the synthetic circler never touches its main)
    since = kind in ("bully", "playful_friend")
    assert (b.scales.since > 0.0) == since and b.charging == (kind == "bully")
    assert b.situation_vectors.shape[1] == 6 + still + since + (
        2 if params.get("w_room") else 0)
    assert (b.personal_space == 0.0) == (shipped and kind != "lover")   # share_around
    assert b.keeps_pace == (kind == "stalker")
    assert b.walks_with_main == (kind in ("follow", "lover"))   # generation.mean_capped
    # a main on which the charging kinds enter charges here (with the obstacles below)
    main = demos.main_path(12, 60.0, rate_hz=rate, reversals=True)
    fast, fast_trace, fast_shown = _run(b, main, True)
    slow, slow_trace, slow_shown = _run(b, main, False)
    assert len(fast) == len(slow) > 1000 and len(fast_trace) > 1500
    assert np.array_equal(fast.view(np.uint64), slow.view(np.uint64))
    assert np.array_equal(fast_shown.view(np.uint64), slow_shown.view(np.uint64))
    assert fast_trace == slow_trace
    if duration > 10 or shipped:
        choices = {t[1] for t in fast_trace}
        assert {"situation", "coherence"} <= choices <= {"situation", "coherence", "charge",
                                                            "dart"}
        # darts kept whole where the demonstration circles its main and darts into it
        assert ("dart" in choices) == (kind == "playful_friend")
        # charges kept whole, both ways, where the demonstration charges again and again
        # (Behavior.charging: the bully; the follower's one pass, the playful friend's one
        # dart and the stalker's one pass are not kept)
        assert ("charge" in choices) == (kind == "bully") == b.charging


def test_the_compiled_step_equals_the_python_step_in_a_crowd():
    """Twelve characters to keep apart from, and a main's personal space after them (the rows
    kept between calls, Reactor._obstacle_array, grow for them)."""
    m = demos.main_path(3, 20.0, rate_hz=40.0)
    b = Behavior.train(demos.follow_behind(m))
    assert b.personal_space > 0.0
    main = demos.main_path(12, 30.0, rate_hz=40.0, reversals=True)
    fast, fast_trace, fast_shown = _run(b, main, True, crowd=12)
    slow, slow_trace, slow_shown = _run(b, main, False, crowd=12)
    assert len(fast) == len(slow) > 500
    assert np.array_equal(fast.view(np.uint64), slow.view(np.uint64))
    assert np.array_equal(fast_shown.view(np.uint64), slow_shown.view(np.uint64))
    assert fast_trace == slow_trace


def test_the_compiled_remainder_is_pythons():
    rng = np.random.default_rng(3)
    values = list(rng.normal(size=5000) * 20) + [k * math.pi for k in range(-7, 8)] + [
        -0.0, 1e-300, -1e-300, math.tau, -math.tau, 0.5 * math.tau, 2.5 * math.tau]
    for x in values:
        for y in (math.tau, 1.0, 0.3):
            got, want = remainder(x, y), math.remainder(x, y)
            assert got == want and math.copysign(1.0, got) == math.copysign(1.0, want), (x, y)
        assert wrap_angle(x) == wrap_angle_py(x)


def test_the_compiled_hypot_is_pythons():
    """libm's hypot differs from CPython's in the last bit now and then (measured: the
    first difference of a compiled step from the Python one came from there)."""
    rng = np.random.default_rng(4)
    for scale in (1e-4, 1e-2, 1.0, 30.0):
        a = rng.normal(size=20000) * scale
        b = rng.normal(size=20000) * scale * rng.uniform(0.01, 1.0, 20000)
        for x, y in zip(a.tolist(), b.tolist()):
            assert hypot(x, y) == math.hypot(x, y), (x, y)
    assert hypot(0.010740750473444659, -0.02628584784220118) == math.hypot(
        0.010740750473444659, -0.02628584784220118)
    for x, y in ((0.0, 0.0), (-0.0, 3.0), (math.inf, 1.0), (1.0, -math.inf)):
        assert hypot(x, y) == math.hypot(x, y)
    assert math.isnan(hypot(math.nan, 1.0))
