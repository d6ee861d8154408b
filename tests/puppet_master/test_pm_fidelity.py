"""Fidelity: every shipped behaviour generated on main paths it never saw keeps its
demonstration's figures (behaviors/puppet_master/fidelity.py), measured, not timed."""

import numpy as np
import pytest

from behaviors.puppet_master import designers, fidelity, look, visitors
from behaviors.puppet_master.engine import Behavior
from behaviors.puppet_master.look import train_look
from behaviors.puppet_master.sequential import pair_takes
from tabletop import examples, library
from tests.puppet_master.demos import unseen_main_paths

TABLE = (0.0, 0.0, *examples.TABLE)
PATHS = ("slow_pauses_30hz", "loops_spins_45hz")
# Thresholds the generation still misses on these paths (measured; see bench/fidelity.py):
# event figures of rare or slow events (contacts, the speed while the main is still, the
# orbit), speeds on the loops (the stalker's main spins in place faster than ever
# demonstrated) and the afraid character's share of looking at the main. Every other
# threshold must hold.
KNOWN_MISSES = {
    # (the lover's loops still/moving is met: 0.369 against 0.419, limits 0.293-0.545; on
    # the slow path too, its steps beside a still main held to its still pace in its main's
    # frame as well, step.py)
    "lover": {"slow_pauses_30hz": {"orbit"}, "loops_spins_45hz": set()},
    # the bully stopped against its main at its least demonstrated distance (Behavior.main_disc)
    # meets orbit on every path of seeds 0, 1, 2, 5 (0.21-0.34 rad/s against 0.275); which
    # seconds of a pause its charges fall in moved: seed 0's slow contact 0.157 -> 0.109
    # (limit 0.110; its fast path 0.110 -> 0.162), see test_pm_contact.py. Leaving its pushes
    # at once (step_detail.py, StepDetail._detail) moved them again: slow 0.109 -> 0.164, loops
    # 0.126 -> 0.089 (limits 0.110-0.204); loops 0.156 and slow 0.144 with the current step
    "bully": {"slow_pauses_30hz": set(), "loops_spins_45hz": set()},
    # the playful friend's targets reached round the main (share_around), its place held in
    # the world where it circles (look._circling): slow and loops contact 0.025 / 0.029
    # against 0.041 (0.019 / 0.020 before, missed). The stalker's drift corrected at the matched
    # moment's pace (step.py) meets its speed (loops W1 0.062 -> 0.010) and its slow-path
    # still/moving (0.45 -> 0.31 against 0.285); on the loops, where its main spins in place,
    # still/moving (0.150; 0.161 matched by its main's still/moving state too,
    # features.main_still) and contact (0.0 against 0.022) stay missed. The friend's darts
    # timed by the steps since its last touch (behavior.py, Behavior.circling): its contact
    # missed on 4 instead of 9 of the 54 paths of seeds 0-5, 8-13, 26-31, seed 0's loops
    # among the 4 (0.019, limits 0.021-0.061; 0.022 before, its designer 0.028); met since
    # its live push is counted where the pucks touch (Behavior.live_touch): 0.025
    "playful_friend": {"slow_pauses_30hz": set(), "loops_spins_45hz": set()},
    "stalker": {"slow_pauses_30hz": set(), "loops_spins_45hz": {"contact"}},
    # (the afraid demonstration with the chasing hand of chased.py). Its targets kept off the
    # edges (Params.edge_percentile), it leaves the walls on these paths, whose mains never
    # chase it, and watches its main as its own designer does there: the facing, orbit
    # (made at the walls in its demonstration) and speed its designer misses on the slow path
    # (facing 0.52 against 0.24, orbit 0.28 against 0.67 rad/s; its designer 0.74 and 0.22)
    # are missed; its still/moving ratio is kept (slow path 0.79, loops 0.75 against 0.87)
    "afraid": {"slow_pauses_30hz": {"facing", "orbit", "speed"},
               "loops_spins_45hz": set()},
}


@pytest.fixture(scope="module")
def paths():
    return unseen_main_paths(0, 40.0, examples.TABLE)


@pytest.fixture(scope="module")
def shipped():
    out = {}
    for name in designers.PERSONALITIES:
        stored = library.load_behavior(examples.DEFAULT_OUT / name)
        out[name] = Behavior.train(stored.demonstration, **stored.parameters)
    return out


@pytest.mark.parametrize("name", designers.PERSONALITIES)
def test_generation_keeps_the_demonstrated_character(shipped, paths, name):
    b = shipped[name]
    demo = fidelity.demonstration_figures(b)
    for path in PATHS:
        row = fidelity.evaluate(b, paths[path], TABLE, demo)
        missed = set(fidelity.failures(row))
        assert missed <= KNOWN_MISSES[name][path], (name, path, missed, row)
        # the turn limiter and the path's texture hold everywhere
        assert row["ok_saturation"] and row["ok_texture"]


def test_the_looks_that_were_lost_are_kept(shipped, paths):
    # the figures: demonstrated reactors faced the main 86-99% of the time and the
    # generated ones 0-36%; the limiter saturated on 64-94% of steps
    for name in ("lover", "bully", "stalker"):
        row = fidelity.evaluate(shipped[name], paths["slow_pauses_30hz"], TABLE)
        assert row["demo_facing"] > 0.95 and row["gen_facing"] > 0.9
        assert row["gen_saturation"] < 0.12
        ratio = row["gen_look_change_rad"] / row["demo_look_change_rad"]
        assert 0.67 <= ratio <= 1.5


def test_the_lovers_look_stays_on_its_main_on_fast_paths(shipped, paths, monkeypatch):
    # where the lover faced its main and its main's look frame was as steady (3% of its
    # samples), that frame turned its look off an unseen fast main: per-step look change
    # 1.56 and 1.76x the demonstration's on seeds 0 and 1 (look.GAZE_MARGIN: 1.31 and 1.36)
    fast1 = unseen_main_paths(1, 40.0, examples.TABLE)["fast_reversals_60hz"]
    b = shipped["lover"]
    demo = fidelity.demonstration_figures(b)
    for main in (paths["fast_reversals_60hz"], fast1):
        row = fidelity.evaluate(b, main, TABLE, demo)
        ratio = row["gen_look_change_rad"] / row["demo_look_change_rad"]
        assert 0.67 <= ratio <= 1.5, ratio
    # the margin re-chooses only a gazing character's moments (the lover 34 of 2400, the bully
    # 17): the playful friend (looks where it runs) and the afraid one keep every frame
    chosen = {n: shipped[n].look.frame for n in designers.PERSONALITIES}
    monkeypatch.setattr(look, "GAZE_MARGIN", 1.0)
    for name, frame in chosen.items():
        b = shipped[name]
        changed = int(np.sum(train_look(b.main, b.react, b.params.rate_hz).frame != frame))
        assert (changed > 0) == (name in ("lover", "bully")), (name, changed)


@pytest.mark.parametrize("name", designers.PERSONALITIES)
def test_never_leaves_the_table_never_jumps_and_is_reproducible(shipped, paths, name):
    # every shipped behaviour on 20 s of the fast reversing hand and 20 s of the loops with
    # a spin in place (the target swings round a spinning main)
    b = shipped[name]
    largest = float(np.max(np.hypot(*np.diff(b.react[:, :2], axis=0).T)))
    fast = paths["fast_reversals_60hz"]
    loops = paths["loops_spins_45hz"]
    runs = [fast[fast[:, 0] < 20.0], loops[loops[:, 0] >= 20.0]]
    x0, y0, x1, y1 = TABLE
    for i, main in enumerate(runs):
        a = fidelity.generate(b, main, TABLE)
        if i == 0:
            again = fidelity.generate(b, main, TABLE)
            assert a.tobytes() == again.tobytes()                       # to the last digit
        assert len(a) >= 0.95 * 20.0 * b.params.rate_hz                # every step generated
        assert ((a[:, 1] >= x0) & (a[:, 1] <= x1) & (a[:, 2] >= y0) & (a[:, 2] <= y1)).all()
        step = np.hypot(*np.diff(a[:, 1:3], axis=0).T)
        # measured: the largest generated step is 0.73-1.0 of the demonstration's largest
        # (a shoved lover is held at it: step.py, to its cap's rounding)
        assert step.max() <= largest * (1.0 + 1e-12), (name, i, step.max(), largest)


# Sequential training against the two-puck demonstration of the same hand on the same main
# (seeds 0-3, 20 s: 12 unseen paths a behaviour; the reference recorded on the reactor's camera
# phase; tabletop.examples.sequential_misses' rule with the per-character allowances measured on
# the tuning seeds, examples.SEQUENTIAL_ALLOWANCE). Measured here (sequential - two-puck, misses /
# mean generated distance mm, against the allowance): lover +2 / -2.3 (7 / 5.1), bully -2 / +10.2
# (13 / 25.7), playful friend -3 / -0.9 (6 / 4.8), stalker +2 / -1.1 (11 / 4.4), afraid +10 (not
# judged) / -15.8 (53.9): each passes by at least 5 misses and 2.8 mm. The mispaired takes fail
# by at least 3 mm or 6 misses: the lover 0.2 s late +13 misses (by 6; +13 to +22 in all four
# tuning sets), the stalker 0.1 s late +11.2 mm (by 6.8; 8.8-11.4 in the tuning sets) and 0.1 s
# early -7.5 mm (by 3.1; 7.5-9.2), against the stalker's largest distance change from hands,
# other main paths or a frame of reaction of 4.4 mm. The lover 0.1 s early (-12 misses) passes;
# the pairing's angles and interpolation are guarded by tests/puppet_master/test_pm_sequential.py.
SEQUENTIAL_SEEDS = (0, 1, 2, 3)
SEQUENTIAL_SECONDS = 20.0
# the negative control: these characters' reactor takes paired as if stamped ``late_s`` late
# must fail the rule (checked in the same test, so the references are computed once in any
# test worker)
MISPAIRED_S = {"lover": (0.2,), "stalker": (0.1, -0.1)}


@pytest.mark.parametrize("name", designers.PERSONALITIES)
def test_sequential_training_keeps_the_character_as_a_two_puck_demonstration(name):
    """The designer records the main at 60 Hz, then the reaction against its playback on the
    camera's frames (half a frame after the main's, the playback seen a frame late); paired
    by pair_takes, it misses no more thresholds than a two-puck demonstration of the same hand
    on the reactor's frames, and keeps its distance to the main, within the character's
    allowance measured on the tuning seeds (examples.sequential_misses). The same take paired
    with the wrong main moments fails."""
    # the second hand's reference is the bench's (bench/fidelity.py), sequential_misses reads
    # the designer's own: 12 of the 60 open-path runs of a character left out
    figures = examples.sequential_comparison(name, SEQUENTIAL_SEEDS, SEQUENTIAL_SECONDS,
                                             references=("two_puck",))
    assert not examples.sequential_misses(name, figures), figures
    for late_s in MISPAIRED_S.get(name, ()):
        def mispaired(main, react, late_s=late_s):
            return pair_takes(main, react + np.array([late_s, 0.0, 0.0, 0.0]))
        figures = examples.sequential_comparison(name, SEQUENTIAL_SEEDS, SEQUENTIAL_SECONDS,
                                                 pair=mispaired, references=("two_puck",))
        assert examples.sequential_misses(name, figures), (f"paired {late_s} s late", figures)


def test_the_bully_charges_into_contact_and_keeps_a_charge_whole(shipped, paths):
    from behaviors.puppet_master.engine import Reactor
    from behaviors.puppet_master.demonstrated import charges
    # the demonstrated bully charges from its lurking distance into contact again and again
    # (measured: 15 charges, most from 0.2-0.33 m, into 0.05 m); the lover and the afraid
    # never do
    b = shipped["bully"]
    ends, touch = charges(b.main[:, :2], b.react[:, :2], b.params.rate_hz)
    touches = sorted({t for t in touch if t >= 0})
    assert len(touches) >= 10
    assert max(float(b.distance[t]) for t in touches) < 0.06
    starts = [ends.index(e) for e in sorted({e for e in ends if e >= 0})]
    assert float(np.median(b.distance[starts])) > 0.2
    for name in ("lover", "afraid"):
        o = shipped[name]
        assert max(charges(o.main[:, :2], o.react[:, :2], o.params.rate_hz)[0]) == -1
    # live, a charge the match entered runs on to its end, sample after sample (the 60 Hz
    # hand: at most one generation step per main sample)
    r = Reactor(b, TABLE, max_backlog=None)
    kept, prev = 0, -1
    for t, x, y, d in paths["fast_reversals_60hz"][:1200]:
        if r.advance(float(t), float(x), float(y), float(d)):
            if r.last_choice == "charge":
                assert r.source == prev + 1
                kept += 1
            prev = r.source
    assert kept > 50
    # and arrives: the contact share within the 30% of the demonstration's on the
    # loops of seeds 0-5 (0.110-0.204 against 0.157): on 5 of 6, 0.089-0.180 (6 of 6 before
    # the bully left its pushes at once, step.py; seed 0 0.126 -> 0.089, seed 1 0.129 ->
    # 0.128; 0.053 on seed 0 before charges were kept whole, 0.124 on seed 1 while the detail
    # still turned a charge's steps)
    demo = fidelity.demonstration_figures(b)
    rows = [fidelity.evaluate(b, unseen_main_paths(seed, 40.0, examples.TABLE)[
        "loops_spins_45hz"], TABLE, demo) for seed in range(6)]
    assert sum(row["ok_contact"] for row in rows) >= 5, [row["gen_contact"] for row in rows]


def test_a_character_shown_chased_is_checked_against_a_visitor_chasing_it(shipped):
    # the afraid demonstration's main goes for it about half of the time (chased.ChasingHand);
    # the open unseen paths never do, and there the designer's own afraid character watches
    # its main (facing 0.66-0.77 on seed 0, against 0.24 demonstrated). A visitor going after
    # it (a closed loop) is the situation its demonstration shows.
    b = shipped["afraid"]
    main, rows = fidelity.pursue(b, visitors.pursuer(0, 10.0, examples.TABLE), TABLE)
    again = fidelity.pursue(b, visitors.pursuer(0, 10.0, examples.TABLE), TABLE)
    assert main.tobytes() == again[0].tobytes() and rows.tobytes() == again[1].tobytes()
    assert len(main) == 500 and np.allclose(np.diff(main[:, 0]), 1 / 50.0)
    # the visitor goes after the reactor: its velocity points toward it more than away
    grid = fidelity.main_on_grid(main, rows[:, 0])
    to = rows[:, 1:3] - grid[:, :2]
    toward = np.einsum("ij,ij->i", np.diff(grid[:, :2], axis=0), to[:-1]) / np.maximum(
        np.hypot(*to[:-1].T), 1e-9) * b.params.rate_hz
    assert np.mean(toward > 0.05) > 2 * np.mean(toward < -0.05), toward
    # on 40 s of it (seed 0) the generated afraid character keeps its demonstrated look change
    # and texture and its distance to the visitor within 0.15 m of the demonstration's (0.25
    # against 0.37); its facing share, within 0.15 over seeds 0-3 (0.04, 0.22, 0.10, 0.19:
    # mean 0.14 against 0.24; one seed's moves by 0.1 with the re-matching). The designer's own
    # character there misses only the still/moving ratio (0.57 against 0.87): its
    # demonstration's main pauses beside it more often than this visitor does
    demo = fidelity.demonstration_figures(b)
    row = fidelity.evaluate_pursuit(b, visitors.pursuer(0, 40.0, examples.TABLE), TABLE, demo)
    assert row["ok_look_change"] and row["ok_texture"], row
    facing = [fidelity.evaluate_pursuit(b, visitors.pursuer(s, 40.0, examples.TABLE), TABLE,
                                        demo)["gen_facing"] if s else row["gen_facing"]
              for s in range(4)]
    assert abs(float(np.mean(facing)) - row["demo_facing"]) < 0.15, facing
    assert abs(row["gen_distance_mean_m"] - row["demo_distance_mean_m"]) < 0.15, row
    t, m, react = designers.pursued_on_grid("afraid", visitors.pursuer(0, 40.0, examples.TABLE),
                                            b.params.rate_hz, examples.TABLE)
    own = fidelity.compare(demo, fidelity.figures(m, react, b.params.rate_hz, b.turn_limit))
    assert set(fidelity.failures(own)) <= {"still_moving"}, fidelity.failures(own)


def test_the_designers_afraid_character_escapes_the_edges_when_chased():
    # chased by the unseen visitor, the scripted afraid character slides along an edge and
    # escapes round the visitor instead of being pinned: at an edge 4.6% and 13.4% of the
    # time on seeds 0 and 1 (0.045-0.134 on seeds 0-5; fleeing straight away from the
    # visitor, as the former policy did: 0.18-0.59)
    for seed in (0, 1):
        t, m, react = designers.pursued_on_grid(
            "afraid", visitors.pursuer(seed, 40.0, examples.TABLE), 40.0, examples.TABLE)
        assert fidelity.figures(m, react, 40.0, 8.0, TABLE)["edge_share"] < 0.2, seed


def test_the_time_at_a_table_edge_is_reported(shipped):
    # edge_share: steps within 0.1 m of a table edge, where the table is known (reported, no
    # threshold). The afraid demonstration spends 6% of its time there (measured 0.062, its
    # character sliding along the edges and escaping round the chasing hand; one that stays at
    # the edge it was chased to: 0.372);
    # a reactor circling the table's centre none, one sliding along an edge all of it
    b = shipped["afraid"]
    demo = fidelity.demonstration_figures(b, TABLE)
    assert 0.03 < demo["edge_share"] < 0.1, demo["edge_share"]
    assert np.isnan(fidelity.demonstration_figures(b)["edge_share"])
    t = np.arange(400) / 40.0
    main = np.column_stack([0.6 + 0.1 * np.cos(t), 0.4 + 0.1 * np.sin(t), t + np.pi / 2])
    centre = np.column_stack([0.6 + 0.3 * np.cos(t), 0.4 + 0.2 * np.sin(t), t])
    along = np.column_stack([0.1 + 0.1 * t, np.full(t.size, 0.05), np.zeros(t.size)])
    assert fidelity.figures(main, centre, 40.0, 6.0, TABLE)["edge_share"] == 0.0
    assert fidelity.figures(main, along, 40.0, 6.0, TABLE)["edge_share"] == 1.0


def test_the_stalker_keeps_its_pace_behind_a_fast_or_spinning_main(shipped, paths):
    """A character that slows when its main stops corrects its drift at most at the matched
    moment's pace (step.py, GenerationStep._trajectory): without that cap the stalker runs at
    its top speed on 30% of the steps of the loops, chasing targets 10-15 cm off."""
    b = shipped["stalker"]
    demo = fidelity.demonstration_figures(b)
    fast = unseen_main_paths(1, 40.0, examples.TABLE)["fast_reversals_60hz"]
    for main, most_w1, most_moving in ((paths["loops_spins_45hz"], 0.03, 0.30),
                                       (fast, 0.03, 0.30)):
        row = fidelity.evaluate(b, main, TABLE, demo)
        # measured 0.010 and 0.014 m/s (0.062 and 0.052 without the cap; threshold 0.044)
        assert row["speed_w1_mps"] < most_w1, row
        # measured 0.270 and 0.270 m/s (0.337 and 0.319 without the cap; demonstrated 0.251)
        assert row["gen_speed_moving_mps"] < most_moving, row
        assert row["ok_speed"]


def test_a_character_circling_its_main_holds_its_place_in_the_world(shipped, paths):
    # the playful friend circles its main one way (2.4 rad/s in the world): placed in the
    # world on 71% of its samples (none without circling); the others turn either way
    # (bully 0.78, stalker 0.23, lover 0.86, afraid 0.40, the same without it)
    assert [n for n, b in shipped.items() if b.circling] == ["playful_friend"]
    world = {n: float(np.mean(np.asarray(b.place_frame) == look.PLACE_WORLD))
             for n, b in shipped.items()}
    assert world["playful_friend"] > 0.5, world
    # so a reversing main does not swing its target to the main's other side: speed W1 on
    # seed 0's fast path measured 0.038 m/s (0.064 without circling; threshold 0.081)
    b = shipped["playful_friend"]
    row = fidelity.evaluate(b, paths["fast_reversals_60hz"], (0.0, 0.0, *examples.TABLE))
    assert row["speed_w1_mps"] < 0.05, row["speed_w1_mps"]
