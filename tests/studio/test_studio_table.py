"""The studio on the table: control markers seen through the synthetic camera drive a take
(record, stop, keep); scripted keys through the view; the library is reloaded when it changes
on disk. (The ``review`` command's sheets: test_review_command.py.)"""

import json
import math
from pathlib import Path

import numpy as np
import pytest
import yaml

from behaviors.puppet_master import designers
from tabletop import library
from tabletop.cli import main as cli
from tabletop.config import load_config
from tabletop.kiosk.simulate import SimClock, simulated
from tabletop.studio.targets import PuppetMasterTarget

RATE = 20.0


def studio_config(tmp_path: Path) -> Path:
    path = tmp_path / "config.yaml"
    path.write_text(yaml.safe_dump({
        "loop": {"rate_hz": RATE},
        "sources": [{"kind": "synthetic_camera", "name": "camera", "pucks": [],
                     "resolution": [480, 270], "fps": RATE, "hands": {"every_s": 0}}],
        "engines": [{"kind": "puppet_master", "name": "pet", "main": {"puck": 1},
                     "designer": {"enabled": True, "library": "lib"}}],
        "view": {"size": [320, 180]},
        "studio": {"enabled": True, "countdown_s": 0.5},
    }))
    return path


def test_control_markers_through_the_camera_record_train_and_keep(tmp_path, capsys):
    demo = designers.demonstrate("lover", seed=3, seconds=12)

    def poses(s):
        i = min(int(np.searchsorted(demo[:, 0], s)), len(demo) - 1)
        r = demo[i]
        out = [(1, r[1], r[2], r[3]), (2, r[4], r[5], r[6])]
        if 0.5 <= s < 4.5:
            out.append((45, 0.06, 0.06, 0.0))        # the record marker, in a corner
        if 5.0 <= s < 6.0:
            out.append((47, 1.14, 0.06, 0.0))        # the keep marker
        return out

    path = studio_config(tmp_path)
    clock = SimClock()
    runner, inst = simulated(load_config(path), path, clock, kiosk=False, studio=True)
    runner.studio.session.wait()   # what the studio loads at start, before the clock runs
    inst.loop.inputs.sources[0].reader.poses = poses
    states = []
    for _ in range(int(6.5 * RATE)):
        frame = inst.loop.tick()
        states.append(frame.character("studio").action)
        assert 45 not in {p.id for p in frame.pucks}    # markers are controls, not inputs
        if states[-1] == "training":     # the worker trains; the take plays from the next tick
            runner.studio.target.trainer.wait(30.0)
        clock.advance(1 / RATE)
    inst.loop.close()
    runner.studio.session.wait()
    order = [s for i, s in enumerate(states) if i == 0 or s != states[i - 1]]
    assert order == ["idle", "countdown", "recording", "training", "trying", "idle"]
    assert states.count("training") == 3      # 0.15 s after the stop, at 20 Hz
    # started 0.3 s (debounce) + 0.5 s (countdown) after the marker was put down at 0.5 s and
    # confirmed by the tracker, stopped 0.3 s after it was lifted at 4.5 s
    rec = [i / RATE for i, s in enumerate(states) if s == "recording"]
    assert 1.3 <= rec[0] <= 1.55 and 4.8 <= rec[-1] <= 5.05
    saved = library.load_behavior(tmp_path / "lib" / "pet")
    take = saved.demonstration
    assert take[-1, 0] == pytest.approx(rec[-1] - rec[0], abs=0.05)
    # the take is the pucks as the camera saw them: within 1 cm of where they were
    i0 = np.searchsorted(demo[:, 0], rec[0])
    truth = demo[i0:i0 + len(take)]
    t_truth = np.interp(take[:, 0] + rec[0], demo[:, 0], demo[:, 1])
    assert np.median(np.abs(take[:, 1] - t_truth)) < 0.01
    assert len(truth) > 0
    log = [json.loads(x) for x in runner.studio.session.path.read_text().splitlines()]
    assert [x["outcome"] for x in log] == ["kept"] and log[0]["name"] == "pet"
    assert (runner.studio.session.folder / log[0]["review"]).stat().st_size > 10_000
    # after a restart the behaviour is in the library and plays
    runner2, inst2 = simulated(load_config(path), path, SimClock(), kiosk=False, studio=True)
    target = runner2.studio.target
    assert target.items() == ["pet"]
    target.use("pet")
    target.between_ticks(math.inf)           # (the loop: the first tick LOAD_S after the pick)
    assert abs(inst2.engines[0].behavior.samples - 40 * take[-1, 0]) <= 2   # at 40 Hz
    inst2.loop.close()
    # the session's contact sheet
    sheet = tmp_path / "sheet.png"
    assert cli(["review", str(runner.studio.session.path), "--out", str(sheet)]) == 0
    assert sheet.stat().st_size > 10_000
    assert "1 try, 1 kept (1.0 tries per kept take)" in capsys.readouterr().out


def test_a_corrupt_behaviour_is_reported_and_skipped_and_a_fix_is_picked_up(tmp_path):
    from tabletop.plugins import puppet_master as pm
    from tabletop.config import validate_config
    from tabletop.registry import BuildContext
    lib = tmp_path / "lib"
    good = library.save_behavior(lib, "good", designers.demonstrate("lover", seconds=4), {})
    bad = library.save_behavior(lib, "bad", designers.demonstrate("afraid", seconds=4), {})
    csv = bad / "demonstration.csv"
    text = csv.read_text()
    cfg = validate_config({"sources": [{"kind": "scripted"}], "engines": [
        {"kind": "puppet_master", "name": "pet", "behavior": str(good),
         "designer": {"enabled": True, "library": str(lib)}}]}, "t.yaml", tmp_path)
    engine = pm.build(cfg["engines"][0], BuildContext((1.2, 0.8), 60.0, cfg, tmp_path))
    target = PuppetMasterTarget(engine)
    target.lib_poller.every_s = target.play_poller.every_s = 0.0
    csv.write_text(text.replace("\n", "\nnot,a,number,row,at,all,x\n", 1))
    problems = target.poll()
    assert len(problems) == 1 and "bad/demonstration.csv" in problems[0] and "line 2" in problems[0]
    assert target.items() == ["bad", "good"]
    target.use("good")                       # the others keep working
    target.between_ticks(math.inf)           # (the loop: the first tick LOAD_S after the pick)
    assert engine.behavior_name == "good"
    csv.write_text(text)                     # fixed on disk: picked up, no restart
    assert target.poll() == []
    target.use("bad")
    target.between_ticks(math.inf)
    assert engine.behavior_name == "bad"
    # the behaviour in play is reloaded when its files change
    before = engine.behavior
    library.save_behavior(lib, "bad", designers.demonstrate("stalker", seconds=5), {},
                          replace=True)
    assert target.poll() == []
    target.between_ticks(math.inf)
    assert engine.behavior is not before
    assert engine.behavior.samples == len(designers.demonstrate("stalker", seconds=5))


def test_a_playing_behaviour_outside_the_studio_is_reloaded_or_kept(tmp_path):
    from tabletop.config import validate_config
    from tabletop.frames import Frame
    from tabletop.plugins import puppet_master as pm
    from tabletop.registry import BuildContext
    from tabletop.studio.reloader import BehaviorReloader
    folder = library.save_behavior(tmp_path, "x", designers.demonstrate("lover", seconds=4), {})
    good_yaml = (folder / "behavior.yaml").read_bytes()
    cfg = validate_config({"sources": [{"kind": "scripted"}], "engines": [
        {"kind": "puppet_master", "name": "pet", "behavior": str(folder)}]}, "t.yaml", tmp_path)
    engine = pm.build(cfg["engines"][0], BuildContext((1.2, 0.8), 60.0, cfg, tmp_path))
    hook = BehaviorReloader(engine)
    hook.poller.every_s = 0.0                   # looks at every call (the loop: once a second)
    first = engine.behavior
    (folder / "behavior.yaml").write_text("format: [\n")
    hook()
    hook.wait()
    assert engine.behavior is first and "behavior.yaml" in hook.problem
    assert "still playing" in engine.step(Frame(seq=0, t=1.0))[0].label
    (folder / "behavior.yaml").write_bytes(good_yaml)       # fixed: reloaded, label back
    hook()
    hook.wait()                                 # (the loop: the first tick after the worker)
    assert hook.problem == "" and engine.behavior is not first
    from tabletop.frames import Puck
    assert "playing x" in engine.step(Frame(seq=1, t=1.1, pucks=(Puck(1, 0.3, 0.3, 0.0),)))[0].label


def test_an_edit_saved_between_build_and_its_watchers_is_seen(tmp_path):
    """The behaviour folder's watchers (the reloader outside the studio, the studio's target)
    are made after the engine read the folder (seconds later at a cold start): their first
    look compares with the folder as it was read, so an edit saved in between is refused or
    reloaded (with the edited folder as their baseline, the edit would never be seen)."""
    from tabletop.config import validate_config
    from tabletop.plugins import puppet_master as pm
    from tabletop.registry import BuildContext
    from tabletop.studio.reloader import BehaviorReloader
    folder = library.save_behavior(tmp_path, "x", designers.demonstrate("lover", seconds=4), {})
    cfg = validate_config({"sources": [{"kind": "scripted"}], "engines": [
        {"kind": "puppet_master", "name": "pet", "behavior": str(folder), "main": {"puck": 1},
         "designer": {"enabled": True, "library": "lib"}}]}, "t.yaml", tmp_path)
    engine = pm.build(cfg["engines"][0], BuildContext((1.2, 0.8), 60.0, cfg, tmp_path))
    (folder / "behavior.yaml").write_text("format: [\n")     # saved while the rest starts
    hook = BehaviorReloader(engine)
    hook()
    hook.wait()
    assert "behavior.yaml" in (hook.problem or "")
    target = PuppetMasterTarget(engine)
    target.play_poller.every_s = 0.0
    target.poll()
    target.between_ticks(math.inf)              # (read in the loader: said at its swap)
    assert any("behavior.yaml" in p for p in target.poll())


def test_scripted_key_events_through_the_view_record_train_try_and_keep(tmp_path):
    """Key presses posted to pygame, read by the view, queued for the loop, handled by the
    studio: R (countdown, then record), R (stop: trained, trying), K (kept)."""
    import pygame
    path = tmp_path / "config.yaml"
    path.write_text(yaml.safe_dump({
        "loop": {"rate_hz": RATE},
        "sources": [{"kind": "scripted", "pucks": [1, 2]}],
        "engines": [{"kind": "puppet_master", "name": "pet", "main": {"puck": 1},
                     "designer": {"enabled": True, "library": "lib"}}],
        "view": {"size": [320, 180]},
        "studio": {"countdown_s": 1.0, "review": False},
    }))
    clock = SimClock()
    runner, inst = simulated(load_config(path), path, clock, kiosk=False, studio=False)
    keys = {int(1 * RATE): pygame.K_r, int(5 * RATE): pygame.K_r, int(7 * RATE): pygame.K_k}
    states = []
    for i in range(int(8 * RATE)):
        if i in keys:
            pygame.event.post(pygame.event.Event(pygame.KEYDOWN, key=keys[i], mod=0,
                                                 unicode="", scancode=0))
        states.append(inst.loop.tick().character("studio").action)
        if states[-1] == "training":     # the worker trains; the take plays from the next tick
            runner.studio.target.trainer.wait(30.0)
        clock.advance(1 / RATE)
    inst.loop.close()
    order = [s for i, s in enumerate(states) if i == 0 or s != states[i - 1]]
    assert order == ["idle", "countdown", "recording", "training", "trying", "idle"]
    take = library.load_behavior(tmp_path / "lib" / "pet").demonstration
    # pressed at 1 s (read by the view that tick, handled the next), 1 s countdown, stopped at 5 s
    assert take[-1, 0] == pytest.approx(3.0, abs=2.5 / RATE)


def test_studio_mode_gives_a_reactor_on_puck_2_another_puck_to_demonstrate_with(tmp_path):
    """``--studio`` makes every reactor a designer target; one whose main is puck 2 (the
    default reactor puck) demonstrates its reaction with puck 1, not with its main puck."""
    from tabletop.studio.build import studio_targets
    from tests.puppet_master.test_plugin import build

    entries = [{"kind": "puppet_master", "name": n, "behavior": "behaviors/library/lover",
                "main": {"puck": p}} for n, p in (("on_one", 1), ("on_two", 2))]
    cfg = {"engines": [dict(e, designer={"enabled": False}) for e in entries]}
    targets = studio_targets(build(entries), cfg, tmp_path, all_engines=True)
    pucks = {t.engine.name: (t.main_puck, t.react_puck) for t in targets}
    assert pucks == {"on_one": (1, 2), "on_two": (2, 1)}


MAINS = {"nearest_3_1": {"nearest": [{"puck": 3}, {"puck": 1}]},
         "first_2": {"first": [{"puck": 2}, {"touch": 4}]},
         "first_character": {"first": [{"character": "on_one"}, {"puck": 3}]}}


def test_studio_mode_takes_the_main_puck_of_several_mains_as_designer_mode_does(tmp_path):
    """A reactor bound to several mains is demonstrated in studio mode with the main puck its
    own designer mode takes (the first binding's puck, else puck 1), not always puck 1."""
    from tabletop.studio.build import studio_targets
    from tests.puppet_master.test_plugin import build

    entries = [{"kind": "puppet_master", "name": "on_one", "behavior": "behaviors/library/lover",
                "main": {"puck": 1}}]
    entries += [{"kind": "puppet_master", "name": n, "behavior": "behaviors/library/lover",
                 "main": m} for n, m in MAINS.items()]
    cfg = {"engines": [dict(e, designer={"enabled": False}) for e in entries]}
    studio = {t.engine.name: t.main_puck
              for t in studio_targets(build(entries), cfg, tmp_path, all_engines=True)}
    designed = [dict(e, designer={"enabled": True, "library": str(tmp_path / "lib"),
                                  "sequential": True}) for e in entries]
    own = {e.name: e.designer["main_puck"] for e in build(designed)}
    assert studio == own == {"on_one": 1, "nearest_3_1": 3, "first_2": 2, "first_character": 1}


def test_studio_mode_keeps_the_takes_of_a_reactor_whose_name_no_folder_may_have(tmp_path):
    """``--studio`` keeps a reactor's takes under its engine's name; for one named "mein
    Liebling" K refused every take (the name is no folder's), now they are "behaviour"."""
    from tabletop.studio.build import studio_targets
    from tabletop.studio.machine import Studio
    from tabletop.frames import Frame, Puck
    from tests.puppet_master.test_plugin import build

    entries = [{"kind": "puppet_master", "name": n, "behavior": "behaviors/library/lover"}
               for n in ("mein Liebling", "pet")]
    cfg = {"engines": [dict(e, designer={"enabled": False, "library": str(tmp_path / "lib")})
                       for e in entries]}
    targets = studio_targets(build(entries), cfg, tmp_path, all_engines=True)
    assert [t.engine.designer["name"] for t in targets] == ["behaviour", "pet"]
    studio = Studio(targets[:1], countdown_s=0.0)
    demo = designers.demonstrate("lover", seed=2, seconds=4)
    for i, row in enumerate(demo):
        studio(Frame(seq=i, t=100.0 + row[0], pucks=(Puck(1, *row[1:4]), Puck(2, *row[4:7])),
                     commands=("designer.record",) if i in (0, len(demo) - 1) else ()))
    studio(Frame(seq=len(demo), t=100.5 + demo[-1, 0]))     # trained in its worker: in play
    studio.command("designer.keep")
    assert studio.message == "kept as behaviour in library/"   # (the default, the config's)
    assert library.list_behaviors(targets[0].lib) == ["behaviour"]
