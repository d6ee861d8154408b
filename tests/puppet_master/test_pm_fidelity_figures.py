"""The fidelity measure itself (behaviors/puppet_master/fidelity.py) on hand-made paths whose
figures are known, and its thresholds at the issue's limits, so a figure measured wrongly
cannot pass or fail the generation unnoticed."""

import math

import numpy as np
import pytest

from behaviors.puppet_master import fidelity, visitors
from tabletop.frames import wrap_angles

RATE = 40.0
T = np.arange(int(20 * RATE)) / RATE


def _circling(radius: float, rate: float, facing: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """A main still at (0.6, 0.4) and a reactor going round it at ``rate`` rad/s."""
    main = np.column_stack([np.full(T.size, 0.6), np.full(T.size, 0.4), np.zeros(T.size)])
    a = rate * T
    look = a + math.pi if facing else a + math.pi / 2          # at the main, or along the way
    react = np.column_stack([0.6 + radius * np.cos(a), 0.4 + radius * np.sin(a), look])
    return main, react


def test_a_reactor_circling_a_still_main():
    # two turns in 20 s at 0.3 m
    rate = 2 * math.pi * 2 / 20.0
    main, react = _circling(0.3, rate)
    f = fidelity.figures(main, react, RATE, 6.0)
    assert abs(f["distance_mean_m"] - 0.3) < 1e-9
    assert abs(f["orbit_radps"] - rate) < 1e-3                 # its own rate round the main
    assert f["facing"] == 1.0 and f["contact"] == 0.0
    assert abs(f["speed_still_mps"] - 0.3 * rate) < 1e-3 and math.isnan(f["speed_moving_mps"])
    assert abs(f["look_change_rad"] - rate / RATE) < 1e-9
    # the texture of a steady turn is its turn per step
    assert abs(f["texture_rad"] - rate / RATE) < 1e-6
    assert np.allclose(f["_sector"], 1 / 8, atol=0.005)       # all round it, evenly
    side = fidelity.figures(*_circling(0.3, rate, facing=False), RATE, 6.0)
    assert side["facing"] == 0.0                               # looking along its way


def test_a_main_spinning_walking_or_going_round_is_no_orbit():
    # the main turns on the spot (2 rad/s) beside a still reactor, walks straight ahead with
    # the reactor 0.2 m behind it, or walks round it: the reactor itself never goes round
    spin = np.column_stack([np.full(T.size, 0.6), np.full(T.size, 0.4), 2.0 * T])
    still = np.column_stack([np.full(T.size, 0.9), np.full(T.size, 0.4), np.full(T.size, math.pi)])
    f = fidelity.figures(spin, still, RATE, 6.0)
    assert f["orbit_radps"] == 0.0 and f["facing"] == 1.0
    assert f["_sector"].max() < 0.2                            # in every sector of its frame
    x = 0.2 + 0.1 * T
    walk = np.column_stack([x, np.full(T.size, 0.4), np.zeros(T.size)])
    behind = np.column_stack([x - 0.2, np.full(T.size, 0.4), np.zeros(T.size)])
    g = fidelity.figures(walk, behind, RATE, 6.0)
    assert g["orbit_radps"] == 0.0 and g["texture_rad"] == 0.0 and g["facing"] == 1.0
    assert abs(g["speed_moving_mps"] - 0.1) < 1e-9 and math.isnan(g["speed_still_mps"])
    assert g["_sector"].max() == 1.0                           # always straight behind it
    # the main walks round a still reactor (0.3 m, 1 rad/s): the bearing between them turns,
    # but the reactor's own orbit is none
    a = 1.0 * T
    round_ = np.column_stack([0.6 + 0.3 * np.cos(a), 0.4 + 0.3 * np.sin(a), a + math.pi / 2])
    centre = np.column_stack([np.full(T.size, 0.6), np.full(T.size, 0.4), np.zeros(T.size)])
    assert fidelity.figures(round_, centre, RATE, 6.0)["orbit_radps"] == 0.0


def test_look_change_saturation_texture_and_contact():
    limit = 4.0                                                # rad/s
    main = np.column_stack([np.full(T.size, 0.6), np.full(T.size, 0.4), np.zeros(T.size)])
    # the reactor walks a zigzag (turning +-0.3 rad each step) past the main, its look turning
    # at the limit on every other step
    heading = np.where(np.arange(T.size) % 2 == 0, 0.15, -0.15)
    step = 0.5 / RATE * np.column_stack([np.cos(heading), np.sin(heading)])
    xy = np.cumsum(step, axis=0) + [0.3, 0.4]
    look = np.cumsum(np.where(np.arange(T.size) % 2 == 0, limit / RATE, 0.0))
    react = np.column_stack([xy, look])
    f = fidelity.figures(main, react, RATE, limit)
    assert abs(f["saturation"] - 0.5) < 0.01
    assert abs(f["look_change_rad"] - 0.5 * limit / RATE) < 1e-3
    assert abs(f["texture_rad"] - 0.3) < 1e-6
    near = np.hypot(xy[:, 0] - 0.6, xy[:, 1] - 0.4) < fidelity.CONTACT_M
    assert abs(f["contact"] - near.mean()) < 1e-12 and 0 < f["contact"] < 0.2


def test_speed_while_the_main_stands_and_while_it_walks():
    # the main stands for 10 s and walks at 0.2 m/s for 10 s; the reactor moves at 0.05 m/s
    # beside it while it stands and at 0.25 m/s while it walks
    half = T.size // 2
    mx = np.concatenate([np.full(half, 0.2), 0.2 + 0.2 * (T[half:] - T[half])])
    main = np.column_stack([mx, np.full(T.size, 0.4), np.zeros(T.size)])
    v = np.where(np.arange(T.size) < half, 0.05, 0.25)
    rx = np.concatenate([[0.0], np.cumsum(v[1:] / RATE)])
    react = np.column_stack([0.1 + rx, np.full(T.size, 0.6), np.zeros(T.size)])
    f = fidelity.figures(main, react, RATE, 6.0)
    assert abs(f["speed_still_mps"] - 0.05) < 0.005
    assert abs(f["speed_moving_mps"] - 0.25) < 0.005
    assert abs(f["still_moving_ratio"] - 0.2) < 0.03


def test_w1_and_the_thresholds_at_the_issues_limits():
    rng = np.random.default_rng(0)
    a = rng.normal(0.3, 0.05, 4000)
    assert abs(fidelity.w1(a, a + 0.1) - 0.1) < 1e-9
    assert fidelity.w1(a, a) == 0.0
    demo = {"facing": 0.5, "look_change_rad": 0.02, "texture_rad": 0.3, "contact": 0.2,
            "still_moving_ratio": 0.5, "orbit_radps": 1.0, "saturation": 0.05,
            "speed_mean_mps": 0.25, "_dist": a, "_speed": a - 0.05, "_sector": np.full(8, 1 / 8)}

    def row(shown: dict | None = None, **gen) -> dict:
        d = {**demo, **(shown or {})}
        return fidelity.compare(d, {**d, **gen})

    assert row()["ok"]
    # facing within 0.1; look change and texture within 0.67-1.5x; speed W1 within 20% of
    # the demonstrated mean speed; events within 30%; saturation at most the demo's + 0.1
    for key, good, bad in (("facing", 0.59, 0.61), ("look_change_rad", 0.0299, 0.0301),
                           ("look_change_rad", 0.0135, 0.0133), ("texture_rad", 0.44, 0.46),
                           ("contact", 0.259, 0.261), ("still_moving_ratio", 0.36, 0.34),
                           ("orbit_radps", 1.29, 1.31), ("saturation", 0.149, 0.151)):
        assert row(**{key: good})["ok"], (key, good)
        assert not row(**{key: bad})["ok"], (key, bad)
    assert row(_speed=a - 0.05 + 0.049)["ok"] and not row(_speed=a + 0.001)["ok_speed"]
    # an event figure near zero in the demonstration keeps a floor: a character that never
    # touched its main may touch it 2% of the time
    assert row({"contact": 0.0}, contact=0.019)["ok"]
    assert not row({"contact": 0.0}, contact=0.021)["ok_contact"]


def _turning(m: np.ndarray, rate: float) -> tuple[np.ndarray, np.ndarray]:
    """Speed (m/s) over 0.1 s and the per-step turn of the heading (rad; 0 where slower than
    0.05 m/s) of a main path (n, 4)."""
    k = max(1, int(round(0.1 * rate)))
    d = m[k:, 1:3] - m[:-k, 1:3]
    v = np.hypot(*d.T) * rate / k
    turn = wrap_angles(np.diff(np.arctan2(d[:, 1], d[:, 0])))
    turn[~((v[1:] > 0.05) & (v[:-1] > 0.05))] = 0.0
    return v, turn


@pytest.mark.parametrize("seed", [0, 1])
def test_the_unseen_main_paths_are_the_issues_kinds_of_visitor(seed):
    # at least three paths: different speeds, stops, reversals, loops and spins in place, at
    # main sample rates 30-60 Hz (measured on seeds 0-5: median speed 0.06-0.08 / 0.20-0.21 /
    # 0.14-0.21 m/s, still 5-24% of the time, 8-18 reversals on the fast path, 2.6-14 rad
    # turned one way within 8 s, the loops' at least 9.6)
    paths = visitors.unseen_main_paths(seed, 40.0, (1.2, 0.8))
    rates = {"slow_pauses_30hz": 30.0, "fast_reversals_60hz": 60.0, "loops_spins_45hz": 45.0}
    assert set(paths) == set(rates)
    fig = {}
    for name, m in paths.items():
        rate = rates[name]
        assert np.allclose(np.diff(m[:, 0]), 1.0 / rate) and m[-1, 0] >= 39.9
        v, turn = _turning(m, rate)
        half = max(1, int(round(0.25 * rate)))
        pace = np.hypot(*(m[2 * half:, 1:3] - m[:-2 * half, 1:3]).T) * rate / (2 * half)
        still = pace < 0.02
        look = np.abs(wrap_angles(np.diff(m[:, 3]))) * rate
        n = min(still.size, look.size)
        # a reversal: the heading over half a second turned round (more than 2.5 rad)
        h = np.arctan2(*(m[half:, 1:3] - m[:-half, 1:3]).T[::-1])
        k = int(0.5 * rate)
        back = (np.abs(wrap_angles(h[k:] - h[:-k])) > 2.5) & (pace[:h.size - k] > 0.05)
        fig[name] = {
            "speed": float(np.median(pace)), "still": float(still.mean()),
            "reversals": int(np.sum(np.diff(back.astype(int)) == 1)),
            "spin": float(np.mean((look[:n] > 1.0) & still[:n])),
            "loop": float(np.abs(np.convolve(np.clip(turn, -0.3, 0.3),
                                             np.ones(int(8 * rate)), "valid")).max())}
    slow, fast, loops = (fig[k] for k in rates)
    assert slow["speed"] < 0.1 and fast["speed"] > 2 * slow["speed"], fig
    assert min(f["still"] for f in fig.values()) > 0.04, fig          # every one stops
    assert fast["reversals"] >= 8 and fast["reversals"] > max(slow["reversals"],
                                                              loops["reversals"]), fig
    assert loops["loop"] > 2 * math.pi and loops["loop"] > max(slow["loop"], fast["loop"]), fig
    assert loops["spin"] > 0.02 and loops["spin"] > slow["spin"], fig
    # and none is a demonstration's own main path (at the same times, 0.1 m apart or more on
    # average)
    from tabletop import examples
    for name in examples.designers.PERSONALITIES:
        demo = examples.example_demonstration(name)
        for m in paths.values():
            shown = np.column_stack([np.interp(m[:, 0], demo[:, 0], demo[:, c]) for c in (1, 2)])
            assert np.mean(np.hypot(*(m[:, 1:3] - shown).T)) > 0.1, name


def test_event_thresholds_met_only_through_their_floor_are_named():
    # an event figure off by more than 30% of the demonstration's but within the floor meets
    # its threshold and is named; one within 30%, or missed, is not (bench/fidelity.py counts
    # them: events_met_by_floor_only; the --check summary too)
    from tabletop.examples import summary
    a = np.linspace(0.1, 0.5, 200)
    demo = {"facing": 0.5, "look_change_rad": 0.02, "texture_rad": 0.3, "contact": 0.04,
            "still_moving_ratio": 0.2, "orbit_radps": 1.0, "saturation": 0.05,
            "speed_mean_mps": 0.25, "_dist": a, "_speed": a, "_sector": np.full(8, 1 / 8)}

    def row(**gen) -> dict:
        return fidelity.compare(demo, {**demo, **gen})

    floored = row(contact=0.025, still_moving_ratio=0.29, orbit_radps=1.2)
    assert floored["ok"] and fidelity.floor_only(floored) == ["contact", "still_moving"]
    assert fidelity.floor_only(row(contact=0.029, still_moving_ratio=0.25)) == []   # within 30%
    missed = row(contact=0.019, still_moving_ratio=0.31)
    assert not missed["ok_contact"] and fidelity.floor_only(missed) == []
    table = {"lover": {"slow": floored, "fast": row()}}
    assert fidelity.floor_only_table(table) == ["lover:slow:contact", "lover:slow:still_moving"]
    assert summary(table, table).endswith("; 2 event thresholds met only through their floor "
                                          "(missed at 30% of the demonstration's alone)")
