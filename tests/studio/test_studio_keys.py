"""The designer studio driven by key commands: record, train, try, keep or redo, and the
library (switch, rename, delete, undo) for Puppet Master behaviours and MOP actions."""

import json
from pathlib import Path

import numpy as np
import pytest
import yaml

from behaviors.puppet_master import designers
from tabletop import library
from tabletop.config import validate_config
from tabletop.frames import Frame, Puck
from tabletop.plugins import mop
from tabletop.plugins import puppet_master as pm
from tabletop.registry import BuildContext
from tabletop.studio.machine import Studio
from tabletop.studio.session import SessionLog
from tabletop.studio.mop_target import MopTarget
from tabletop.studio.targets import PuppetMasterTarget

ROOT = Path(__file__).resolve().parents[2]
TABLE = (1.2, 0.8)


def build(engines: list[dict], base: Path = ROOT):
    cfg = validate_config({"sources": [{"kind": "scripted"}], "engines": engines}, "test.yaml",
                          base)
    ctx = BuildContext(table=TABLE, rate_hz=60.0, config=cfg, base=base)
    return [pm.build(e, ctx) for e in cfg["engines"]]


class Bench:
    """Engines behind a studio, stepped frame by frame as the loop does (studio filter first)."""

    def __init__(self, engines, tmp_path, review=False, targets=None):
        self.engines = engines
        self.session = SessionLog(tmp_path / "studio", review=review)
        self.studio = Studio(targets or [PuppetMasterTarget(e) for e in engines], countdown_s=0.0,
                             log_try=self.session.log_try)
        self.studio.save_take = self.session.save_take     # as tabletop.studio.build does

    def step(self, frame):
        f = self.studio(frame)
        out = {}
        for e in self.engines:
            produced = e.step(f)
            f = f.with_characters(produced)
            out.update({c.name: c for c in produced})
        return out, f.character("studio")


def demo_frames(demo, commands, t0=100.0, focus=None):
    for i, row in enumerate(demo):
        pucks = (Puck(1, row[1], row[2], row[3]), Puck(2, row[4], row[5], row[6]))
        yield Frame(seq=i, t=t0 + row[0], pucks=pucks, commands=commands.get(i, ()), focus=focus)


def designer(tmp_path, **extra):
    """A designer engine that trains within the tick (the take plays on the stop's tick), so
    these tests follow every command exactly; background training has its own test."""
    extra = {"background_training": False, **extra}
    return build([{"kind": "puppet_master", "name": "pet",
                   "designer": {"enabled": True, "library": str(tmp_path / "lib"), **extra}}])


def test_the_status_line_and_the_session_log_count_the_same_samples(tmp_path):
    # a take recorded at 60 fps: the status line said the behaviour's own count, resampled at
    # 40 Hz (2/3 of the samples), where the session log and its review said the recorded ones
    (e,) = designer(tmp_path)
    bench = Bench([e], tmp_path)
    demo = designers.demonstrate("lover", seed=8, seconds=16)[:640]
    demo[:, 0] *= 40.0 / 60.0                        # the same take, seen by a 60 fps loop
    labels = [bench.step(f)[1].label for f in demo_frames(
        demo, {10: ("designer.record",), 610: ("designer.record",), 611: ("designer.keep",)})]
    logged = [json.loads(ln) for ln in bench.session.path.read_text().splitlines()]
    assert logged[-1]["outcome"] == "kept" and 595 <= logged[-1]["samples"] <= 605
    assert f"trained {logged[-1]['samples']} samples" in labels[610], labels[610]


def test_record_train_try_keep_and_it_is_in_the_library_after_a_restart(tmp_path):
    (e,) = designer(tmp_path)
    bench = Bench([e], tmp_path)
    demo = designers.demonstrate("lover", seed=8, seconds=30)
    start, stop = 10, 810
    labels = []
    frames = demo_frames(demo, {start: ("designer.record",), stop: ("designer.record",)})
    for f in list(frames)[:stop + 1]:
        chars, studio = bench.step(f)
        labels.append(studio.label)
        if start <= f.seq < stop:     # drawn under the reactor puck while recording
            assert (chars["pet"].x, chars["pet"].y) == (f.pucks[1].x, f.pucks[1].y)
            assert studio.action == "recording"
    assert bench.studio.state == "trying" and "trained 800 samples" in labels[stop]
    # try it: the main puck alone drives the new behaviour, which keeps close like the take
    main = designers.designer_main_path(77, seconds=20)
    xy = []
    for i, r in enumerate(main):
        chars, _ = bench.step(Frame(seq=1000 + i, t=200 + r[0], pucks=(Puck(1, r[1], r[2], r[3]),)))
        xy.append((chars["pet"].x, chars["pet"].y))
    assert np.median(np.hypot(*(np.array(xy) - main[:, 1:3]).T)[80:]) < 0.22
    _, studio = bench.step(Frame(seq=5000, t=300.0, commands=("designer.keep",)))
    assert "kept as pet" in studio.label and bench.studio.state == "idle"
    stored = library.load_behavior(tmp_path / "lib" / "pet")
    take = stored.demonstration
    assert len(take) == stop - start and take[0, 0] == 0.0
    # with the table it was made on (an edge margin set later measured the take's own bounds)
    assert (stored.parameters["table_width"], stored.parameters["table_height"]) == TABLE
    assert np.allclose(take[:, 1:], demo[start:stop, 1:])
    # a restart: a new engine and studio list it and play it
    (e2,) = designer(tmp_path)
    t2 = PuppetMasterTarget(e2)
    assert t2.items() == ["pet"]
    t2.use("pet")
    assert e2.behavior is not None and e2.behavior_name == "pet" and e2.behavior.samples == 800
    # the session log has the try, kept, with its figures
    (line,) = [json.loads(x) for x in bench.session.path.read_text().splitlines()]
    assert line["outcome"] == "kept" and line["name"] == "pet" and line["samples"] == 800
    assert line["duration_s"] == pytest.approx(demo[stop - 1, 0] - demo[start, 0], abs=1e-6)
    assert line["training_s"] > 0


def test_discard_redo_too_short_and_keep_never_overwrites(tmp_path):
    (e,) = designer(tmp_path, min_seconds=3.0)
    corrupt = tmp_path / "lib" / "pet"
    corrupt.mkdir(parents=True)
    (corrupt / "behavior.yaml").write_text("kind: [\n")
    before = (corrupt / "behavior.yaml").read_bytes()
    bench = Bench([e], tmp_path)
    demo = designers.demonstrate("afraid", seed=2, seconds=20)
    cmds = {5: ("designer.record",), 60: ("designer.record",),            # 1.4 s: too short
            70: ("designer.record",), 270: ("designer.record",), 271: ("designer.discard",),
            280: ("designer.record",), 480: ("designer.stop",), 490: ("designer.redo",),
            690: ("designer.stop",), 691: ("designer.keep",), 692: ("designer.keep",)}
    labels = {}
    for f in demo_frames(demo, cmds):
        _, studio = bench.step(f)
        labels[f.seq] = studio.label
    assert "too short" in labels[60] and "take discarded" in labels[271]
    assert "kept as pet-2" in labels[691] and "nothing to keep" in labels[692]
    assert (corrupt / "behavior.yaml").read_bytes() == before
    assert library.list_behaviors(tmp_path / "lib") == ["pet", "pet-2"]
    assert len(library.load_behavior(tmp_path / "lib" / "pet-2").demonstration) == 200
    outcomes = [json.loads(x)["outcome"] for x in bench.session.path.read_text().splitlines()]
    assert outcomes == ["too short", "discarded", "redone", "kept"]


def test_switch_rename_delete_and_undo(tmp_path):
    lib = tmp_path / "lib"
    for n, who in (("a", "lover"), ("b", "afraid")):
        library.save_behavior(lib, n, designers.demonstrate(who, seconds=4), {})
    (e,) = designer(tmp_path)
    s = Bench([e], tmp_path).studio
    s.command("designer.item_next")
    assert e.behavior_name == "a"
    s.command("designer.item_next")
    assert e.behavior_name == "b"
    (lib / "b" / "behavior.yaml").write_text("# made at the table\n"
                                             + (lib / "b" / "behavior.yaml").read_text())
    s.command("designer.rename:brave")
    assert library.list_behaviors(lib) == ["a", "brave"] and e.behavior_name == "brave"
    saved = (lib / "brave" / "behavior.yaml").read_text()   # the file says the new name too
    assert library.read_description(lib / "brave")["name"] == "brave"
    assert saved.startswith("# made at the table\n") and "name: brave\n" in saved
    s.command("designer.rename:a")                 # taken: refused, nothing changes
    assert "already exists" in s.message and library.list_behaviors(lib) == ["a", "brave"]
    s.command("designer.delete")
    assert library.list_behaviors(lib) == ["a"]
    s.command("designer.undo")                     # the delete
    assert library.list_behaviors(lib) == ["a", "brave"]
    s.command("designer.undo")                     # the rename
    assert library.list_behaviors(lib) == ["a", "b"]
    assert library.load_behavior(lib / "b").name == "b"
    assert library.read_description(lib / "b")["name"] == "b"
    s.command("designer.undo")
    assert "nothing to undo" in s.message


def test_tab_focus_selects_which_engine_records(tmp_path):
    a, b = build([{"kind": "puppet_master", "name": n,
                   "designer": {"enabled": True, "library": str(tmp_path)}} for n in ("a", "b")])
    bench = Bench([a, b], tmp_path)
    assert bench.studio.designer_targets() == ("a", "b")
    demo = designers.demonstrate("lover", seed=1, seconds=3)
    for f in demo_frames(demo, {4: ("designer.record",)}, focus="b"):
        _, studio = bench.step(f)
    assert bench.studio.selected == "b" and bench.studio.state == "recording"
    assert a.hold is None and b.hold is not None and studio.label.startswith("[b]")


GESTURES = ROOT / "examples" / "mop" / "gestures"


def test_a_mop_action_slot_is_recorded_trained_and_kept_through_the_same_studio(tmp_path):
    cfg = validate_config({"sources": [{"kind": "scripted"}], "engines": [{
        "kind": "mop", "library": "lib",
        "performers": [{"name": "hand", "inputs": [{"kind": "puck", "id": 1}]}],
        "characters": [{"name": "lizard", "kind": "creature", "performer": "hand",
                        "motions": ["strike", "curl"]}]}]}, str(tmp_path / "t.yaml"), tmp_path)
    ctx = BuildContext(table=TABLE, rate_hz=60.0, config=cfg, base=tmp_path)
    stage = mop.build(cfg["engines"][0], ctx)
    target = MopTarget(stage, "lizard", tmp_path / "lib")
    bench = Bench([stage], tmp_path, targets=[target])
    from tabletop.files import read_csv
    _, g = read_csv(GESTURES / "square.csv")
    t, seq = [100.0], [0]

    def tick(x, y, cmds=()):
        out = bench.step(Frame(seq=seq[0], t=t[0], pucks=(Puck(1, x, y, 0.0),),
                               commands=tuple(cmds), focus="mop/lizard"))
        t[0] += 1 / 60
        seq[0] += 1
        return out

    def perform(speed=1.0):
        tau, out = 0.0, []
        while tau < g[-1, 0]:
            out.append(tick(0.3 + np.interp(tau, g[:, 0], g[:, 1]),
                            0.3 + np.interp(tau, g[:, 0], g[:, 2])))
            tau += speed / 60
        return out

    for _ in range(60):
        tick(0.3, 0.3)
    tick(0.3, 0.3, ["designer.record"])
    perform()
    _, studio = tick(0.3, 0.3, ["designer.record"])
    # the followers are rebuilt in the stage's worker; the old ones play until the new swap in
    assert bench.studio.state == "training" and "take1" not in str(stage._routes)
    ticks = 0
    while bench.studio.state == "training":     # swapped in 0.15 s of frame time after the stop
        _, studio = tick(0.3, 0.3)
        ticks += 1
    assert 9 <= ticks <= 10 and "take1 -> strike" in studio.label
    assert bench.studio.state == "trying" and "take1" in str(stage._routes)
    tick(0.3, 0.3, ["designer.assign"])
    assert stage.puppets["lizard"].actions["take1"].clip.name == "curl"
    for _ in range(70):
        tick(0.3, 0.3)
    late = [c["lizard"] for c, _ in perform(1.3)[-30:]]
    assert np.mean([c.valid and c.action == "take1" for c in late]) > 0.9
    _, studio = tick(0.3, 0.3, ["designer.keep"])
    assert "kept as take1" in studio.label
    assert target.items() == ["take1"]
    saved = yaml.safe_load((tmp_path / "lib" / "lizard" / "actions.yaml").read_text())
    assert saved["actions"][0]["motion"] == "curl"
    bench.studio.command("designer.rename:square")
    assert target.items() == ["square"]
    bench.studio.command("designer.undo")
    assert target.items() == ["take1"]


def test_commands_for_a_target_the_studio_does_not_hold_pass_through(tmp_path):
    (e,) = designer(tmp_path)
    s = Bench([e], tmp_path).studio
    f = s(Frame(seq=0, t=1.0, commands=("designer.record",), focus="mop/face"))
    assert f.commands == ("designer.record",) and s.state == "idle"
    f = s(Frame(seq=1, t=1.1, commands=("designer.record",), focus="pet"))
    assert f.commands == () and s.state == "recording"     # no countdown in this bench


def test_a_corrupt_library_file_there_at_start_is_reported(tmp_path, caplog):
    """The library is read at start: a bad behaviour already there was skipped silently (only
    an edit made while running was reported), so the designer never learnt why it was gone."""
    (e,) = designer(tmp_path)
    bad = tmp_path / "lib" / "bully"
    bad.mkdir(parents=True)
    (bad / "behavior.yaml").write_text("kind: puppet_master\nparams: [1, 2\n")
    bench = Bench([e], tmp_path)
    with caplog.at_level("ERROR", logger="tabletop"):
        bench.studio.poll()
    assert len(bench.studio.problems) == 1 and str(bad / "behavior.yaml") in \
        bench.studio.problems[0]
    said = [r.getMessage() for r in caplog.records]
    assert len(said) == 1 and "corrupt YAML" in said[0], said
    _, studio = bench.step(Frame(seq=0, t=0.0, commands=("designer.record",)))
    assert "1 bad library file(s)" in studio.label


def test_the_status_line_names_a_behaviour_played_from_outside_the_library(tmp_path):
    """The engine's own ``behavior`` (not one of the studio's library) was shown as "(none)"."""
    (e,) = build([{"kind": "puppet_master", "name": "pet", "behavior": "behaviors/library/lover",
                   "designer": {"enabled": True, "library": str(tmp_path / "lib")}}])
    bench = Bench([e], tmp_path)
    _, studio = bench.step(Frame(seq=0, t=0.0, pucks=(Puck(1, 0.5, 0.4, 0.0),)))
    assert studio.label.startswith("[pet] behaviour lover (not in the library): R record")
    library.save_behavior(tmp_path / "lib", "shy", designers.demonstrate("afraid", seconds=4), {})
    bench.studio.command("designer.item_next")
    _, studio = bench.step(Frame(seq=1, t=30.0, pucks=(Puck(1, 0.5, 0.4, 0.0),)))  # said
    assert "shy" in studio.label and "R record" not in studio.label
    _, studio = bench.step(Frame(seq=2, t=36.0, pucks=(Puck(1, 0.5, 0.4, 0.0),)))  # then
    assert studio.label.startswith("[pet] behaviour shy: R record")


def kept_pet(tmp_path) -> Bench:
    """A designer engine's studio that has just kept a 6 s take as "pet" (session log on)."""
    (e,) = designer(tmp_path)
    bench = Bench([e], tmp_path)
    demo = designers.demonstrate("lover", seed=8, seconds=8)
    for f in demo_frames(demo, {10: ("designer.record",), 250: ("designer.record",),
                                251: ("designer.keep",)}):
        bench.step(f)
    return bench


def test_an_undo_of_another_targets_keep_names_that_target(tmp_path):
    """U undoes the last keep, rename or delete of any target, and pressed with another target
    selected it names the owner: "[b] undone: keep pet of a" (without it, "[b] undone: keep
    pet", read as b's)."""
    a, b = build([{"kind": "puppet_master", "name": n,
                   "designer": {"enabled": True, "library": str(tmp_path / n), "name": kept,
                                "background_training": False}}
                  for n, kept in (("a", "pet"), ("b", "shy"))])
    bench = Bench([a, b], tmp_path)
    demo = designers.demonstrate("lover", seed=8, seconds=8)
    for f in demo_frames(demo, {10: ("designer.record",), 250: ("designer.record",),
                                251: ("designer.keep",)}, focus="a"):
        bench.step(f)
    assert library.list_behaviors(tmp_path / "a") == ["pet"]
    _, studio = bench.step(Frame(seq=400, t=200.0, commands=("designer.undo",), focus="b"))
    assert library.list_behaviors(tmp_path / "a") == []
    assert studio.label.startswith("[b]") and "undone: keep pet of a" in studio.label, \
        studio.label
    bench.step(Frame(seq=401, t=200.1, commands=("designer.next",), focus="a"))
    bench.studio.command("designer.undo")
    assert bench.studio.message == "nothing to undo"


def test_the_status_line_names_a_behaviour_deleted_while_it_plays(tmp_path):
    """A behaviour that plays on from memory after U took its kept take out of the library (or
    Delete took it) is named on the idle status line "behaviour pet (deleted)" (without it,
    "behaviour (none)" while the character went on moving)."""
    bench = kept_pet(tmp_path)
    bench.studio.command("designer.undo")
    main = (Puck(1, 0.5, 0.4, 0.0),)
    bench.step(Frame(seq=899, t=160.0, pucks=main))          # the message, from its first frame
    out, studio = bench.step(Frame(seq=900, t=166.0, pucks=main))     # the message is over
    assert out["pet"].valid and "pet (deleted)" in out["pet"].label
    assert studio.label.startswith("[pet] behaviour pet (deleted): R record"), studio.label
    bench.studio.command("designer.undo")                 # nothing left to undo: it stays
    bench.step(Frame(seq=901, t=170.0, pucks=main))
    out, studio = bench.step(Frame(seq=902, t=176.0, pucks=main))
    assert "behaviour pet (deleted)" in studio.label, studio.label
