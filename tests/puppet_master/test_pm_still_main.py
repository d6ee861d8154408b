"""The lover (Behavior.walks_with_main) beside a main that stands keeps its demonstrated pace
at places held in its main's frame too: each step there is held to its typical speed beside
a still main (demonstrated.still_main_speed, step.py), as at moments whose main walked.
The stalker (a character that stops when its main stops) and the afraid character (one that
keeps away from its main) beside a standing main match moments where their demonstrated main
stood (features.main_still)."""

import numpy as np

from behaviors.puppet_master import fidelity
from behaviors.puppet_master.character import STILL_MPS, STILL_SPAN_S
from behaviors.puppet_master.engine import Reactor
from tabletop import examples
from tests.puppet_master.demos import unseen_main_paths
from tests.puppet_master.test_pm_fidelity import TABLE, shipped  # noqa: F401 (fixture)


def test_the_lover_keeps_its_pace_beside_a_still_main(shipped):
    # measured (seeds 0 and 2, slow path with pauses): speed beside the still main 0.057 and
    # 0.070 m/s, still/moving 0.56 and 0.77 (demonstrated 0.053 and 0.42, limits 0.29-0.55);
    # held, 0.049 and 0.054, still/moving 0.49 and 0.63
    b = shipped["lover"]
    demo = fidelity.demonstration_figures(b)
    rows = {seed: fidelity.evaluate(
        b, unseen_main_paths(seed, 40.0, examples.TABLE)["slow_pauses_30hz"], TABLE,
        demo) for seed in (0, 2)}
    assert rows[0]["ok_still_moving"], rows[0]["gen_still_moving_ratio"]
    assert rows[2]["gen_speed_still_mps"] < 0.062, rows[2]["gen_speed_still_mps"]


def _stood_share(b, main):
    """The share of the steps beside a standing main (within the still distance of where it
    was 0.5 s before) generated from moments whose demonstrated main stood."""
    r = Reactor(b, TABLE, max_backlog=None)
    span = int(round(STILL_SPAN_S * b.params.rate_hz))
    grid, sources = [], []
    for t, x, y, d in main:
        for row in r.advance(float(t), float(x), float(y), float(d)):
            grid.append(row[0])
            sources.append(r.source)
    m = fidelity.main_on_grid(main, np.array(grid))[1:, :2]
    src = np.array(sources[1:])
    back = np.maximum(np.arange(len(m)) - span + 1, 0)
    still = np.hypot(*(m - m[back]).T) < STILL_MPS * STILL_SPAN_S
    return float(np.mean(~np.array(b.walked)[src[still]])), int(still.sum())


def test_the_stalker_beside_a_standing_main_matches_moments_whose_main_stood(shipped):
    # the main's still/moving state among its situation and coherence features (it stops with
    # its main: Behavior.scales.still): measured on the loops of seeds 0, 2 and 30, the share
    # 0.29 / 0.54 / 0.69 (by the per-sample speeds alone 0.19 / 0.47 / 0.43)
    b = shipped["stalker"]
    assert b.scales.still > 0.0 and all(shipped[n].scales.still == 0.0
                                        for n in ("lover", "bully", "playful_friend"))
    shares = []
    for seed in (0, 2, 30):
        share, steps = _stood_share(
            b, unseen_main_paths(seed, 40.0, examples.TABLE)["loops_spins_45hz"])
        assert steps > 100
        shares.append(share)
    assert np.mean(shares) > 0.45, shares


def _first_still_speed(b, main, first_s=0.25):
    """The reactor's mean speed (over 0.1 s, m/s) in the first ``first_s`` of each window in
    which the fidelity bench reads its main as still (speed over 0.5 s under STILL_MPS)."""
    rows = fidelity.generate(b, main, TABLE)
    m = fidelity.main_on_grid(main, rows[:, 0])
    still = fidelity.span_speed(m[:, :2], b.params.rate_hz, 0.5) < fidelity.STILL_MPS
    speed = fidelity.span_speed(rows[:, 1:3], b.params.rate_hz, 0.1)
    start = np.flatnonzero(still & ~np.r_[False, still[:-1]])
    first = int(round(first_s * b.params.rate_hz))
    picked = np.concatenate([np.arange(s, s + first) for s in start])
    picked = picked[picked < still.size]
    return float(speed[picked[still[picked]]].mean())


def test_the_stalker_stops_soon_after_its_main(shipped):
    # its step held to its still pace once its main has kept within 0.004 m of its positions
    # over 0.2 s (character.STOP_SPAN_S): measured on the fast paths of seeds 10 and 27, in the
    # first 0.25 s of the bench's still windows, 0.311 / 0.339 m/s with the 0.5 s read, now
    # 0.122 / 0.140 (the demonstration 0.141; its designer on those paths 0.21 / 0.18)
    b = shipped["stalker"]
    assert b.keeps_pace and b.stop_span == 8
    for seed in (10, 27):
        v = _first_still_speed(
            b, unseen_main_paths(seed, 40.0, examples.TABLE)["fast_reversals_60hz"])
        assert v < 0.2, (seed, v)


def test_the_afraid_character_keeps_its_pace_beside_a_standing_main(shipped):
    # the main's still/moving state among its features (it keeps away from its main: a
    # personal space, its pace beside a still main 0.93 of its walking pace): measured on the
    # slow paths with pauses of seeds 0, 1, 13 and 31, the share of its steps beside the
    # standing main from moments whose main stood 0.39 / 0.32 / 0.23 / 0.04 -> 0.61 / 0.52 /
    # 0.49 / 0.39, its still/moving 0.517 / 0.575 / 0.596 / 0.471 -> 0.635 / 1.050 / 0.775 /
    # 0.930 (demonstrated 0.872, limits 0.61-1.13). Read over seeds 0-5, 13 and 31: a single
    # path's share moves with the re-matching (seed 1: 0.52 -> 0.25 when the steps near the
    # edges turned off them, table_boundary.turn_off_edges, while the mean went 0.451 -> 0.456
    # and the still/moving mean 0.83 -> 0.88)
    b = shipped["afraid"]
    assert b.scales.still > 0.0 and b.personal_space > 0.0 and not b.walks_with_main
    demo = fidelity.demonstration_figures(b)
    shares, ratios = [], []
    for seed in (0, 1, 2, 3, 4, 5, 13, 31):
        main = unseen_main_paths(seed, 40.0, examples.TABLE)["slow_pauses_30hz"]
        share, steps = _stood_share(b, main)
        assert steps > 50           # seed 5's main stands least: 75 steps, the others 100+
        shares.append(share)
        ratios.append(fidelity.evaluate(b, main, TABLE, demo)["gen_still_moving_ratio"])
    assert np.mean(shares) > 0.4, shares
    lo = demo["still_moving_ratio"] * (1.0 - fidelity.EVENT_SHARE)
    assert np.mean(ratios) > lo and min(ratios) > 0.6, ratios


def _orbit_beside_a_turning_main(b, look: float, turn_radps: float = 1.5,
                                 seconds: float = 20.0) -> float:
    """The reactor's mean rate round its main (rad/s, after the first 2 s) beside a main that
    stands at the table's centre (with a camera's 0.8 mm jitter, seeded) and turns in place
    from the look ``look`` (rad) at ``turn_radps``, sampled at 50 Hz."""
    r = Reactor(b, TABLE, max_backlog=None)
    rng = np.random.default_rng(int(look))
    cx, cy = 0.5 * (TABLE[0] + TABLE[2]), 0.5 * (TABLE[1] + TABLE[3])
    rows = []
    for i in range(int(seconds * 50)):
        t = i / 50.0
        mx, my = cx + 0.0008 * rng.standard_normal(), cy + 0.0008 * rng.standard_normal()
        rows.extend(r.advance(t, mx, my, look + turn_radps * t))
    a = np.array(rows)
    late = a[a[:, 0] > 2.0]
    bearing = np.unwrap(np.arctan2(late[:, 2] - cy, late[:, 1] - cx))
    return float(np.abs(np.diff(bearing)).sum() / (late[-1, 0] - late[0, 0]))


def test_the_afraid_character_is_not_turned_round_a_standing_main(shipped):
    # at a moment whose demonstrated main stood, beside a live main that stands, its place is
    # its distance on the live bearing (StepSenses._stood_place), not a place in the standing
    # main's frame, which swung round with a main turning in place. Measured from the looks 0,
    # 2 and 4 rad at 1.5 rad/s: 0.482 / 0.394 / 0.295 rad/s round it -> 0.258 / 0.265 / 0.271
    b = shipped["afraid"]
    rates = [_orbit_beside_a_turning_main(b, look) for look in (0.0, 2.0, 4.0)]
    assert np.mean(rates) < 0.33 and max(rates) < 0.3, rates
