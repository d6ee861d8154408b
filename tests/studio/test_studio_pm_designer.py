"""Puppet Master's designer tools in the studio: training in a worker thread swapped in between
ticks, and sequential training (the main puck alone, then the reactor against its playback)."""

import json

import numpy as np

from behaviors.puppet_master import designers
from tabletop import library
from tabletop.frames import Frame, Puck
from tabletop.studio.machine import SWAP_S

from tests.studio.test_studio_keys import Bench, demo_frames, designer


def test_background_training_swaps_the_take_in_between_ticks(tmp_path):
    (e,) = designer(tmp_path, background_training=True)
    bench = Bench([e], tmp_path)
    target = bench.studio.target
    demo = designers.demonstrate("lover", seed=8, seconds=12)
    cmds = {5: ("designer.record",), 300: ("designer.record",), 301: ("designer.discard",),
            310: ("designer.record",), 400: ("designer.record",)}
    frames = list(demo_frames(demo, cmds))
    for f in frames[:301]:
        _, studio = bench.step(f)
    # the tick that stopped the recording did not train: the take trains in a worker thread
    # and plays from the first tick SWAP_S of frame time after the stop (so replays are exact)
    assert studio.action == "training" and "training" in studio.label
    assert e.behavior is None and e.hold is None
    # discarded while (or just after) training: the worker's take never plays
    _, studio = bench.step(frames[301])
    target.trainer.wait(30.0)
    assert studio.action == "idle" and "take discarded" in studio.label
    for f in frames[302:401]:
        chars, studio = bench.step(f)
        assert e.behavior is None
    assert studio.action == "training"
    target.trainer.wait(30.0)           # done long before: still swapped in at a fixed time
    swap = next(f for f in frames[401:] if f.t >= frames[400].t + SWAP_S)
    for f in frames[401:swap.seq]:
        chars, studio = bench.step(f)
        assert studio.action == "training" and e.behavior is None
    chars, studio = bench.step(swap)
    assert studio.action == "trying" and "trained" in studio.label
    assert e.behavior is target.pending and e.behavior.samples == 90     # 90 rows at 40 Hz
    assert e.reactor.behavior is e.behavior          # the reactor built in the worker plays it
    for f in frames[swap.seq + 1:]:
        chars, _ = bench.step(f)
        assert chars["pet"].valid
    _, studio = bench.step(Frame(seq=1000, t=200.0, commands=("designer.keep",)))
    assert "kept as pet" in studio.label
    saved = library.load_behavior(tmp_path / "lib" / "pet").demonstration
    assert np.allclose(saved[:, 1:], demo[310:400, 1:])
    log = [json.loads(x) for x in bench.session.path.read_text().splitlines()]
    assert [x["outcome"] for x in log] == ["discarded", "kept"] and log[1]["training_s"] > 0


def sequential_takes(bench, demo, t, seq0, part):
    """Play one part of a sequential take: ``part`` "main" moves puck 1 along the demo's main,
    "react" puck 2 along its reactor; R at the first row (and at the last, for the main).
    Returns the ghost characters and the studio's actions seen."""
    ghosts, actions = [], []
    for i, row in enumerate(demo):
        puck = Puck(1, *row[1:4]) if part == "main" else Puck(2, *row[4:7])
        cmds = ("designer.record",) if i == 0 or (part == "main" and i == len(demo) - 1) else ()
        chars, studio = bench.step(Frame(seq=seq0 + i, t=t + row[0], pucks=(puck,),
                                         commands=cmds))
        ghosts += [c for name, c in chars.items() if name == "pet.main"]
        actions.append(studio)
    return ghosts, actions


def test_sequential_training_at_the_table(tmp_path):
    # one hand: the main puck alone, then the reactor puck against the main's playback
    (e,) = designer(tmp_path, sequential=True, background_training=True)
    bench = Bench([e], tmp_path)
    target = bench.studio.target
    demo = designers.demonstrate("stalker", seed=4, seconds=12)
    # a main part that is too short is refused, and says so
    _, studios = sequential_takes(bench, demo[:40], 100.0, 0, "main")
    assert studios[-1].action == "idle" and "too short" in studios[-1].label
    assert "of the main puck" in studios[-1].label
    ghosts, studios = sequential_takes(bench, demo, 200.0, 100, "main")
    assert {s.action for s in studios[:-1]} == {"recording"}
    assert len(ghosts) == 1         # from the stop on, the playback's first pose waits
    assert not any("no puck 2" in s.label for s in studios)   # the reactor puck is not needed
    _, studio = bench.step(Frame(seq=1000, t=220.0))
    assert studio.action == "ready" and "R records the reaction" in studio.label
    ghosts, studios = sequential_takes(bench, demo, 230.0, 2000, "react")
    # the playback's end (the main take was recorded up to the row before the stop) stopped
    # the take by itself
    n = len(demo) - 2
    assert {s.action for s in studios[:n]} == {"recording"} and studios[n].action == "training"
    assert len(ghosts) == n and all(g.kind == "playback" for g in ghosts)
    # the ghost replays the main take where it was recorded
    g = np.array([(c.x, c.y) for c in ghosts])
    assert np.max(np.hypot(*(g - demo[:n, 1:3]).T)) < 1e-6
    target.trainer.wait(30.0)
    chars, studio = bench.step(Frame(seq=3000, t=250.0, pucks=(Puck(1, 0.6, 0.4, 0.0),)))
    assert studio.action == "trying" and "pet.main" not in chars and chars["pet"].valid
    # the paired demonstration is the two takes: main and reactor at matching times
    d = target.demo
    assert len(d) >= len(demo) - 2
    assert np.allclose(d[:, 4:6], demo[:len(d), 4:6], atol=1e-9)
    assert np.max(np.hypot(*(d[:, 1:3] - demo[:len(d), 1:3]).T)) < 1e-6
    _, studio = bench.step(Frame(seq=3001, t=251.0, commands=("designer.keep",)))
    assert "kept as pet" in studio.label
    saved = library.load_behavior(tmp_path / "lib" / "pet").demonstration
    assert np.allclose(saved, d)
    log = [json.loads(x)["outcome"] for x in bench.session.path.read_text().splitlines()]
    assert log == ["too short", "kept"]


def test_a_reaction_part_without_its_puck_says_which_puck_was_missing(tmp_path):
    # the main part recorded, then the playback runs to its end with no reactor puck on the
    # table: the line said "both takes need at least two samples", naming neither take nor puck
    (e,) = designer(tmp_path, sequential=True)
    bench = Bench([e], tmp_path)
    demo = designers.demonstrate("stalker", seed=4, seconds=6)
    sequential_takes(bench, demo, 200.0, 0, "main")
    bench.step(Frame(seq=1000, t=210.0))
    studios = [bench.step(Frame(seq=2000 + i, t=220.0 + row[0],
                                commands=("designer.record",) if i == 0 else ()))[1]
               for i, row in enumerate(demo)]
    assert studios[0].action == "recording" and "no puck 2" in studios[0].label
    # the main take is kept: only the reaction is recorded again (it was redone with the main)
    assert studios[-1].action == "ready"
    assert "no reaction recorded: puck 2 was not seen during the main's playback: R records " \
        "the reaction against the main's playback (5.9 s) again, X cancels" in \
        studios[-1].label, studios[-1].label
    chars, _ = bench.step(Frame(seq=2900, t=229.0))
    assert np.allclose([chars["pet.main"].x, chars["pet.main"].y], demo[0, 1:3])  # the ghost
    _, studios = sequential_takes(bench, demo, 240.0, 3000, "react")
    said = next(s.label for s in studios if "trained" in s.label)
    assert "unseen" not in said, said          # the refused part's missing puck is not counted
    bench.step(Frame(seq=4000, t=250.0, commands=("designer.keep",)))
    assert library.list_behaviors(tmp_path / "lib") == ["pet"]
    log = [json.loads(x)["outcome"] for x in bench.session.path.read_text().splitlines()]
    assert log == ["refused", "kept"], log


def test_a_new_take_keeps_the_character_s_parameters_and_is_kept_as_tried(tmp_path):
    # redoing the shipped afraid character at the table: its take trained with the defaults
    # but the rate and window (edge_percentile 50 lost), and the kept behaviour was reloaded
    # with the table it was saved with, where the tried one had the take's own bounds
    from dataclasses import asdict

    from behaviors.puppet_master.engine import Behavior
    from tests.studio.test_studio_keys import build
    (e,) = build([{"kind": "puppet_master", "name": "pet", "behavior": "behaviors/library/afraid",
                   "designer": {"enabled": True, "library": str(tmp_path / "lib"),
                                "background_training": False}}])
    assert e.behavior.params.edge_percentile == 50.0
    bench = Bench([e], tmp_path)
    demo = designers.demonstrate("afraid", seed=8, seconds=12)
    frames = list(demo_frames(demo, {5: ("designer.record",), 400: ("designer.record",)}))
    for f in frames[:401]:
        _, studio = bench.step(f)
    assert studio.action == "trying"
    tried = e.behavior.params
    assert tried.edge_percentile == 50.0 and (tried.table_width, tried.table_height) == (1.2, 0.8)
    _, studio = bench.step(Frame(seq=1000, t=200.0, commands=("designer.keep",)))
    assert "kept as pet" in studio.label
    stored = library.load_behavior(tmp_path / "lib" / "pet")
    assert stored.parameters["edge_percentile"] == 50.0
    kept = Behavior.train(stored.demonstration, **stored.parameters)
    assert asdict(kept.params) == asdict(tried)
    assert kept.edge_margin == e.behavior.edge_margin > 0.0


def test_keep_between_the_parts_tells_the_designer_to_record_the_reaction(tmp_path):
    """K with the main recorded and the reaction not yet said "nothing to keep: R records a
    take", as if nothing had been recorded; the take is half done, and R records its reaction
    against the main's playback."""
    (e,) = designer(tmp_path, sequential=True)
    bench = Bench([e], tmp_path)
    demo = designers.demonstrate("stalker", seed=4, seconds=6)
    sequential_takes(bench, demo, 200.0, 0, "main")
    _, studio = bench.step(Frame(seq=1000, t=210.0, commands=("designer.keep",)))
    assert studio.action == "ready"
    assert "nothing to keep yet: R records the reaction against the main's playback" in \
        studio.label, studio.label
    assert "R records a take" not in studio.label
    _, studio = bench.step(Frame(seq=1001, t=211.0, commands=("designer.record",)))
    assert studio.action == "recording"                  # the reaction part, as told


def test_the_main_takes_ghost_waits_at_its_first_pose_before_the_reaction_is_recorded(tmp_path):
    """Between the parts (and through the reaction's countdown) nothing showed where the main's
    playback would begin: its ghost appeared only as it started, maybe far from the reactor
    puck (seen in an Xvfb snapshot). It waits, still, at the main take's first pose."""
    import pygame
    from tabletop.renderer import Renderer
    (e,) = designer(tmp_path, sequential=True)
    bench = Bench([e], tmp_path)
    demo = designers.demonstrate("stalker", seed=4, seconds=6)
    sequential_takes(bench, demo, 200.0, 100, "main")
    first = bench.studio.target.session.main[0]
    renderer, surface = Renderer((1.2, 0.8), (640, 360), margin=24), pygame.Surface((640, 360))
    x, y = renderer.map.point(first[1], first[2])
    lit = []
    for k in range(30):                     # the designer gets puck 2 ready: 1 s
        chars, studio = bench.step(Frame(seq=1000 + k, t=220.0 + k / 30,
                                         pucks=(Puck(2, 0.9, 0.6, 0.0),)))
        assert studio.action == "ready"
        ghost = chars.get("pet.main")
        assert ghost is not None and ghost.kind == "playback"
        assert (ghost.x, ghost.y, ghost.heading) == tuple(first[1:])
        renderer.draw(surface, Frame(seq=k, t=220.0 + k / 30, characters=tuple(chars.values())))
        img = pygame.surfarray.array3d(surface).astype(int).sum(axis=2)
        lit.append(int((img[int(x) - 30:int(x) + 30, int(y) - 30:int(y) + 30] > 150).sum()))
    assert min(lit[15:]) > 250, lit   # its ring lights its place (measured: 386 of 3600 px)
