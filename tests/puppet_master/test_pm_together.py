"""Reactors aware of each other on the bus: keeping apart, mutual pairs, several mains."""

import numpy as np
import pytest

from behaviors.puppet_master import designers, fidelity
from tabletop.frames import Frame, InputError, Puck
from tests.puppet_master.test_plugin import TABLE, build, main_track, run, visitor_frames
from tracking.visitor import ScriptedVisitor


def _engine(name, behavior, main, **extra):
    return {"kind": "puppet_master", "name": name, "behavior": f"behaviors/library/{behavior}",
            "main": main, **extra}


def test_two_reactors_on_one_main_keep_apart_and_keep_their_behaviour():
    size = 0.08
    together = build([_engine("a", "lover", {"puck": 1}, size=size),
                      _engine("b", "lover", {"puck": 1}, size=size)])
    out = run(together, visitor_frames(30))
    a, b = out["a"], out["b"]
    gap = np.hypot(*(a[:, :2] - b[:, :2]).T)
    # never overlapping by more than 10% of their sizes (discs of diameter ``size``), from
    # the first frame (both start from the same demonstrated pose) and on the frames between
    # two generation steps (the displayed pose lies between the last two)
    assert a[:, 3].all() and b[:, 3].all()
    assert gap.min() >= 0.9 * size                                   # measured 0.080
    # without keeping apart, two lovers of one main do overlap
    apart = build([_engine("a", "lover", {"puck": 1}, size=size, keep_apart=False),
                   _engine("b", "lover", {"puck": 1}, size=size, keep_apart=False)])
    free = run(apart, visitor_frames(30))
    assert np.hypot(*(free["a"][:, :2] - free["b"][:, :2]).T)[60:].min() < 0.5 * size   # 0.0
    # both still love: close to the main, as a lover alone is (median under 0.22 m)
    main = main_track(30)
    for v in (a, b):
        assert np.median(np.hypot(*(v[:, :2] - main[:, :2]).T)[120:]) < 0.22   # 0.13, 0.14


def test_mutual_pair_sees_each_other_one_tick_old_in_any_order():
    def pair(order):
        engines = {"s": _engine("s", "stalker", {"character": "l"}, keep_apart=False),
                   "l": _engine("l", "lover", {"character": "s"}, keep_apart=False)}
        return run(build([engines[k] for k in order]), visitor_frames(15))

    first, again, swapped = pair("sl"), pair("sl"), pair("ls")
    for k in ("s", "l"):
        assert np.array_equal(first[k], again[k])                    # reproducible
        assert np.array_equal(first[k], swapped[k])                  # order does not matter
    # they react to each other: neither waits after the first ticks, and the lover closes in
    s, lv = first["s"], first["l"]
    assert s[5:, 3].all() and lv[5:, 3].all()
    gap = np.hypot(*(s[:, :2] - lv[:, :2]).T)
    assert np.median(gap[-200:]) < 0.35                              # measured 0.12


def test_nearest_of_several_mains_and_first_present():
    engines = build([_engine("n", "lover", {"nearest": [{"puck": 1}, {"puck": 2}]}),
                     _engine("f", "lover", {"first": [{"puck": 7}, {"puck": 2}]})])
    n, f = engines
    chosen, nearest = [], []
    # seed 4: the visitors pass near the lover in turn (with seed 3 it stays by the first all
    # along, as a lover does: it never has a nearer main)
    for frame in visitor_frames(30, seed=4):
        x, y = (n.reactor.pose[:2] if n.reactor.started else (0.6, 0.4))
        n.step(frame)
        f.step(frame)
        ds = [np.hypot(p.x - x, p.y - y) for p in sorted(frame.pucks, key=lambda p: p.id)]
        chosen.append(n.mains.chosen)
        nearest.append(int(np.argmin(ds)))
        assert f.mains.chosen == 1                     # puck 7 never shows: the second main
    chosen, nearest = np.array(chosen[60:]), np.array(nearest[60:])
    assert len(set(chosen)) == 2                       # it turned to each puck in turn
    assert np.mean(chosen == nearest) > 0.9            # the nearest (hysteresis aside)


@pytest.mark.parametrize("name", designers.PERSONALITIES)
def test_every_character_beside_a_twin_on_one_main_keeps_its_figures(name):
    # each of the pair, measured against the same character alone on the same main (60 s at
    # 60 Hz, from the third second): the fidelity thresholds hold but for contacts, a rare
    # event (measured: misses contact on 2 of the 10, none else; distance W1 0.004-0.035 m,
    # speed W1 2-12% of the lone one's mean speed); and they never overlap by over 10%
    size = 0.08
    seconds = 60
    main = main_track(seconds)[120:]
    alone = run(build([_engine("a", name, {"puck": 1}, size=size)]), visitor_frames(seconds))
    pair = run(build([_engine("a", name, {"puck": 1}, size=size),
                      _engine("b", name, {"puck": 1}, size=size)]), visitor_frames(seconds))
    lone = fidelity.figures(main, alone["a"][120:, :3], 60.0, 1e9)
    for k in ("a", "b"):
        row = fidelity.compare(lone, fidelity.figures(main, pair[k][120:, :3], 60.0, 1e9))
        assert set(fidelity.failures(row)) <= {"contact"}, (k, fidelity.failures(row), row)
        assert row["distance_w1_m"] < 0.05, row["distance_w1_m"]
    assert np.hypot(*(pair["a"][:, :2] - pair["b"][:, :2]).T).min() >= 0.9 * size


def test_two_bullies_keep_apart_on_every_frame():
    # the bully charges into its main: two of them on one main, their displayed poses kept
    # apart between steps too (the steps' poses alone apart: 0 on the first frame, then 0.068
    # for 0.08 bodies)
    size = 0.08
    out = run(build([_engine("a", "bully", {"puck": 1}, size=size),
                     _engine("b", "bully", {"puck": 1}, size=size)]), visitor_frames(30, seed=4))
    gap = np.hypot(*(out["a"][:, :2] - out["b"][:, :2]).T)
    assert gap.min() >= 0.9 * size                                   # measured 0.080


@pytest.mark.parametrize("main, words", [
    ({"nearest": []}, ["engines[0].main.nearest", "got 0 items"]),
    ({"nearest": [{"puck": 1}], "first": [{"puck": 2}]}, ["engines[0].main", "one of nearest"]),
    ({"nearest": [{"bogus": 1}]}, ["engines[0].main.nearest[0]", "bogus"]),
    ({"first": {"puck": 1}}, ["engines[0].main.first", "a list"]),
    ({"first": [{"puck": 1}, {"character": "nobody"}]}, ["engines[0].main", "'nobody'"]),
    # itself: nearest of a puck and itself, it chased its own last pose (0.42 m from the
    # puck a lover keeps 0.13 m from, 8 s on the synthetic camera); alone, the same
    ({"nearest": [{"puck": 1}, {"character": "a"}]}, ["engines[0].main", "'a'", "itself"]),
    ({"character": "a"}, ["engines[0].main", "'a'", "itself"]),
])
def test_several_mains_badly_given_name_what_and_where(main, words):
    with pytest.raises(InputError) as err:
        build([_engine("a", "lover", main)])
    msg = str(err.value)
    assert len(msg.splitlines()) == 1
    for w in words:
        assert w in msg, msg


@pytest.mark.parametrize("order", ["wr", "rw"])
def test_a_reactor_of_a_waiting_reactor_waits_in_either_order(order):
    # w reacts to puck 7, which never comes: it waits, drawn at the table's centre. r, bound
    # to w, waits too; listed before w it played against that placeholder (valid on 99% of
    # the frames, 0.6, 0.4 its main), listed after w it waited
    engines = {"w": _engine("w", "stalker", {"puck": 7}),
               "r": _engine("r", "lover", {"character": "w"})}
    out = run(build([engines[k] for k in order]), visitor_frames(3))
    assert not out["w"][:, 3].any() and not out["r"][:, 3].any()


def test_a_cycle_of_three_reactors_starts_and_reacts():
    # a -> b -> c -> a: none has a puck; as a mutual pair, they start from each other's
    # waiting places instead of waiting for each other for ever
    engines = build([_engine("a", "lover", {"character": "b"}),
                     _engine("b", "stalker", {"character": "c"}),
                     _engine("c", "lover", {"character": "a"})])
    out = run(engines, visitor_frames(5))
    for v in out.values():
        assert v[5:, 3].all() and np.isfinite(v).all()


def test_three_and_four_reactors_of_any_size_on_one_main_never_overlap():
    # characters of one behaviour start on one spot: the second went a whole metre aside (to
    # the table's edge) and the third onto it, and one pass over the discs pushed a fourth out
    # of one into another (least gap over the pair's mean size 0.0 on the first frames)
    for names, sizes, seed in ((["lover"] * 3, [0.08] * 3, 4),
                               (["bully"] * 4, [0.04, 0.08, 0.15, 0.25], 3)):
        engines = [_engine(f"r{k}", n, {"puck": 1}, size=s)
                   for k, (n, s) in enumerate(zip(names, sizes))]
        out = run(build(engines), visitor_frames(2, seed=seed))
        for a in range(len(names)):
            for b in range(a + 1, len(names)):
                pa, pb = out[f"r{a}"], out[f"r{b}"]
                assert pa[:, 3].all() and pb[:, 3].all()
                gap = np.hypot(*(pa[:, :2] - pb[:, :2]).T) / (0.5 * (sizes[a] + sizes[b]))
                assert gap.min() >= 0.9, (names[a], a, b, gap.min())    # measured 1.0, 0.963
        # the second starts beside the first, not across the table
        assert np.hypot(*(out["r1"][0, :2] - out["r0"][0, :2])) < 0.2      # 0.08, 0.06


def test_a_chasing_ring_keeps_apart_in_a_corner():
    # the bully chases the afraid character, which flees the stalker, which stalks the bully
    # or the visitor's fast puck, whichever is nearer: the bully pushed into a corner, the
    # stalker pressed onto it along the edge came within 0.446 of their size (the push along
    # the line between them ran into the edge); it slides along the edge (measured 0.974)
    engines = [_engine("a", "bully", {"character": "b"}),
               _engine("b", "afraid", {"character": "c"}),
               _engine("c", "stalker", {"nearest": [{"character": "a"}, {"puck": 1}]})]
    v = ScriptedVisitor(TABLE, [1, 2], seed=5, speed=(0.5, 1.0))
    frames = [Frame(seq=i, t=50.0 + i / 60, pucks=tuple(Puck(p, x, y, a) for p, x, y, a in
                                                       v.poses(i / 60))) for i in range(900)]
    out = run(build(engines), frames)
    gap = np.hypot(*(out["a"][5:, :2] - out["c"][5:, :2]).T) / 0.08
    assert gap.min() >= 0.9, gap.min()


def test_reactors_on_one_main_step_together_whatever_their_order():
    # each plans against the others' poses of the previous tick, then their ends and shown
    # poses move apart together (behaviors.puppet_master.together): listed in another order,
    # every character moves the same to the last digit (stepped in engine order, the later of
    # two yielded to the earlier)
    def three(order):
        engines = {k: _engine(k, b, {"puck": 1})
                   for k, b in (("a", "lover"), ("b", "stalker"), ("c", "afraid"))}
        return run(build([engines[k] for k in order]), visitor_frames(3))

    first, swapped = three("abc"), three("cba")
    for k in "abc":
        assert np.array_equal(first[k], swapped[k]), k


def test_the_shipped_example_of_several_reactors_runs_as_its_comments_say():
    """examples/reactors.yaml: two reactors on one puck, a bully on the nearer of two pucks and
    a mutual pair, built from the config as the installation builds it (30 s of the visitor
    of its seed)."""
    import yaml

    from tests.puppet_master.test_plugin import ROOT
    data = yaml.safe_load((ROOT / "examples" / "reactors.yaml").read_text())
    assert [s["kind"] for s in data["sources"]] == ["scripted"]
    engines = build(data["engines"], base=ROOT / "examples")
    by_name = {e.name: e for e in engines}
    chosen = set()
    out = {e.name: [] for e in engines}
    for f in visitor_frames(30, seed=data["sources"][0]["seed"]):
        for e in engines:
            (c,) = e.step(f)
            f = f.with_characters((c,))
            out[c.name].append((c.x, c.y, float(c.valid)))
        chosen.add(by_name["bully"].mains.chosen)
    out = {k: np.array(v) for k, v in out.items()}
    # every character reacts from its first steps (the pair from each other's waiting places)
    assert all(v[3:, 2].all() for v in out.values())
    # none overlaps another: the sum of their body radii apart on every frame where both play
    # (the pair's first frame, waiting, is drawn dimmed at the table's centre), to a micrometre
    # (the issue asks within 10% of their sizes; measured: each pair's least gap is that sum,
    # at most 0.3 um short)
    names = list(out)
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            both = (out[a][:, 2] > 0) & (out[b][:, 2] > 0)
            gap = np.hypot(*(out[a][both, :2] - out[b][both, :2]).T)
            need = (by_name[a].size + by_name[b].size) / 2
            assert gap.min() >= need - 1e-6, (a, b, gap.min(), need)
    # each keeps its character beside the others: the lover close to its puck, the stalker
    # farther behind (measured medians 0.12 and 0.32 m)
    puck = main_track(30, seed=data["sources"][0]["seed"])
    lover, stalker = (np.median(np.hypot(*(out[k][120:, :2] - puck[120:, :2]).T))
                      for k in ("lover", "stalker"))
    assert lover < 0.22 and 0.22 < stalker < 0.45, (lover, stalker)
    assert chosen == {0, 1}     # the bully turned to each puck in turn (puck 2 half the time)
    pair = np.hypot(*(out["friend"][:, :2] - out["afraid"][:, :2]).T)
    assert np.median(pair[120:]) < 0.3             # they react to each other (measured 0.11)
