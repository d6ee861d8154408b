"""The ``puppet_master`` engine on the bus: config, bindings, several reactors, designer mode."""

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

from behaviors.puppet_master import designers
from tabletop import library
from tabletop.config import validate_config
from tabletop.frames import Frame, Puck, Touch
from tabletop.plugins import puppet_master as pm
from tabletop.registry import BuildContext
from tabletop.schema import ConfigError
from tracking.visitor import ScriptedVisitor

ROOT = Path(__file__).resolve().parents[2]
SHIPPED = ROOT / "behaviors" / "library"
TABLE = (1.2, 0.8)


def build(engines: list[dict], base: Path = ROOT) -> list[pm.PuppetMasterEngine]:
    cfg = validate_config({"sources": [{"kind": "scripted"}], "engines": engines}, "test.yaml",
                          base)
    ctx = BuildContext(table=TABLE, rate_hz=60.0, config=cfg, base=base)
    return [pm.build(e, ctx) for e in cfg["engines"]]


def run(engines, frames):
    """Step every engine with every frame; returns {name: (n, 4) x, y, heading, valid}."""
    out = {e.name: [] for e in engines}
    for f in frames:
        for e in engines:
            produced = e.step(f)
            f = f.with_characters(produced)
            for c in produced:
                out[c.name].append((c.x, c.y, c.heading, float(c.valid)))
    return {k: np.array(v) for k, v in out.items()}


def visitor_frames(seconds: float, rate: float = 60.0, seed: int = 3, t0: float = 50.0):
    v = ScriptedVisitor(TABLE, [1, 2], seed=seed)
    for i in range(int(seconds * rate)):
        t = i / rate
        yield Frame(seq=i, t=t0 + t, pucks=tuple(Puck(pid, x, y, a) for pid, x, y, a in v.poses(t)))


def main_track(seconds, rate=60.0, seed=3):
    v = ScriptedVisitor(TABLE, [1], seed=seed)
    return np.array([v.poses(i / rate)[0][1:] for i in range(int(seconds * rate))])


# -- configuration ------------------------------------------------------------------------------

def test_defaults_and_paths_relative_to_the_config():
    cfg = validate_config({"sources": [{"kind": "scripted"}], "engines": [
        {"kind": "puppet_master", "name": "lover", "behavior": "behaviors/library/lover"}]},
        "c.yaml", ROOT)
    e = cfg["engines"][0]
    assert e["behavior"] == SHIPPED / "lover"
    assert e["main"] == {"kind": "puck", "puck": 1}
    assert e["size"] == 0.08 and e["designer"]["enabled"] is False


@pytest.mark.parametrize("entry, words", [
    ({"main": {"puck": 1, "touch": 2}}, ["engines[0].main", "exactly one"]),
    ({"main": {"stream": "arm"}}, ["engines[0].main.columns", "missing"]),
    ({"main": {"stream": "arm", "columns": [0]}}, ["engines[0].main.columns", "1 items"]),
    ({"main": {"puck": "one"}}, ["engines[0].main.puck", "integer"]),
    ({"main": {"puck": 1, "colour": 3}}, ["engines[0].main.colour", "unknown key"]),
    ({"behavior": None}, ["engines[0].behavior", "designer.enabled"]),
    ({"behavior": "behaviors/library/nobody"}, ["engines[0].behavior", "does not exist"]),
    ({"color": [1, 2]}, ["engines[0].color"]),
    ({"designer": {"enabled": True, "bogus": 1}}, ["engines[0].designer.bogus", "unknown key"]),
    ({"designer": {"react_puck": -1}}, ["engines[0].designer.react_puck"]),
])
def test_bad_options_name_their_key(entry, words):
    e = {"kind": "puppet_master", "behavior": "behaviors/library/lover", **entry}
    with pytest.raises(ConfigError) as err:
        build([e])
    for w in words:
        assert w in str(err.value)


def test_corrupt_behaviour_is_refused_at_load_and_left_alone(tmp_path):
    folder = library.save_behavior(tmp_path, "x", designers.demonstrate("lover", seconds=5), {})
    (folder / "behavior.yaml").write_text("format: tabletop-behavior\nkind: [\n")
    before = (folder / "behavior.yaml").read_bytes()
    with pytest.raises(ConfigError) as err:
        build([{"kind": "puppet_master", "behavior": str(folder)}])
    assert "engines[0].behavior" in str(err.value) and "corrupt YAML" in str(err.value)
    assert (folder / "behavior.yaml").read_bytes() == before


def test_character_binding_must_name_a_known_engine():
    with pytest.raises(pm.PuppetMasterError, match=r"engines\[0\]\.main.*'nobody'"):
        build([{"kind": "puppet_master", "name": "a", "behavior": "behaviors/library/stalker",
                "main": {"character": "nobody"}}])
    # a puppet_master engine listed later is read one tick old
    a, b = build([{"kind": "puppet_master", "name": "a", "behavior": "behaviors/library/stalker",
                   "main": {"character": "b"}},
                  {"kind": "puppet_master", "name": "b", "behavior": "behaviors/library/lover"}])
    assert a.mains.delayed == {"b"} and b.mains.delayed == set()


# -- reacting on the bus ------------------------------------------------------------------------

def test_shipped_afraid_keeps_further_away_than_lover():
    engines = build([
        {"kind": "puppet_master", "name": "lover", "behavior": "behaviors/library/lover"},
        {"kind": "puppet_master", "name": "afraid", "behavior": "behaviors/library/afraid"}])
    out = run(engines, visitor_frames(40))
    main = main_track(40)
    d = {k: np.hypot(*(v[:, :2] - main[:, :2]).T)[120:] for k, v in out.items()}
    assert np.median(d["lover"]) < 0.22
    assert np.median(d["afraid"]) > 0.3
    assert np.median(d["afraid"]) > 2.0 * np.median(d["lover"])
    for v in out.values():
        assert v[:, 3].all()
        assert (v[:, 0] >= 0).all() and (v[:, 0] <= 1.2).all()
        assert (v[:, 1] >= 0).all() and (v[:, 1] <= 0.8).all()


def test_a_reactor_reacts_to_another_reactor():
    engines = build([
        {"kind": "puppet_master", "name": "lead", "behavior": "behaviors/library/playful_friend"},
        {"kind": "puppet_master", "name": "tail", "behavior": "behaviors/library/stalker",
         "main": {"character": "lead"}}])
    out = run(engines, visitor_frames(30))
    tail, lead = out["tail"], out["lead"]
    assert tail[:, 3].all()
    path = np.hypot(*np.diff(tail[:, :2], axis=0).T).sum()
    assert path > 1.0                                        # it moves (metres travelled)
    gap = np.hypot(*(tail[:, :2] - lead[:, :2]).T)[120:]
    assert 0.12 < np.median(gap) < 0.5                       # following its lead at a distance


def test_absent_main_waits_then_keeps_reacting_to_its_last_pose():
    (e,) = build([{"kind": "puppet_master", "name": "lover",
                   "behavior": "behaviors/library/lover"}])
    first = e.step(Frame(seq=0, t=1.0))[0]
    assert not first.valid and "waiting for puck 1" in first.label
    broken = e.step(Frame(seq=1, t=1.5, pucks=(Puck(1, math.nan, 0.2, 0.0),)))[0]
    assert not broken.valid and math.isfinite(broken.x)
    frames = list(visitor_frames(10, t0=2.0))
    cut = [Frame(seq=f.seq, t=f.t, pucks=() if 300 <= f.seq < 420 else f.pucks) for f in frames]
    out = run([e], cut)["lover"]
    assert out[:, 3].all() and np.isfinite(out).all()
    last = np.array([frames[299].pucks[0].x, frames[299].pucks[0].y])
    d = np.hypot(*(out[300:420, :2] - last).T)
    assert np.median(d[60:]) < 0.2                           # stays near where the main was left


def test_touch_and_stream_bindings_drive_the_reactor():
    engines = build([
        {"kind": "puppet_master", "name": "t", "behavior": "behaviors/library/stalker",
         "main": {"touch": 4}},
        {"kind": "puppet_master", "name": "s", "behavior": "behaviors/library/stalker",
         "main": {"stream": "hand", "columns": [1, 2]}}])
    main = main_track(20)
    frames = []
    for i, (x, y, a) in enumerate(main):
        vx, vy = (main[i] - main[i - 1])[:2] * 60 if i else (0.0, 0.0)
        frames.append(Frame(seq=i, t=10 + i / 60, touches=(Touch(4, x, y, vx, vy),),
                            streams={"hand": np.array([0.0, x, y])}))
    out = run(engines, frames)
    for name in ("t", "s"):
        v = out[name]
        assert v[:, 3].all()
        assert np.hypot(*np.diff(v[:, :2], axis=0).T).sum() > 1.0
        d = np.hypot(*(v[:, :2] - main[:, :2]).T)[120:]
        assert 0.15 < np.median(d) < 0.5


# -- designer mode ------------------------------------------------------------------------------

def designer_frames(demo: np.ndarray, commands: dict[int, tuple[str, ...]], t0: float = 100.0,
                    extra: dict[int, tuple[Puck, ...]] | None = None):
    for i, row in enumerate(demo):
        pucks = (Puck(1, row[1], row[2], row[3]), Puck(2, row[4], row[5], row[6]))
        pucks += (extra or {}).get(i, ())
        yield Frame(seq=i, t=t0 + row[0], pucks=pucks, commands=commands.get(i, ()))


def designer_engine(tmp_path, **designer):
    # trained within the tick: these tests follow the designer's steps frame by frame
    designer = {"background_training": False, **designer}
    return build([{"kind": "puppet_master", "name": "pet",
                   "designer": {"enabled": True, "library": str(tmp_path / "lib"), **designer}}])


def test_designer_records_trains_tries_and_keeps(tmp_path):
    (e,) = designer_engine(tmp_path)
    demo = designers.demonstrate("lover", seed=8, seconds=30)
    assert "R to record" in e.step(Frame(seq=0, t=99.0)).__getitem__(0).label
    start, stop = 10, 10 + 800
    frames = list(designer_frames(demo, {start: ("designer.record",), stop: ("designer.record",)}))
    labels = []
    for f in frames[:stop + 1]:
        (c,) = e.step(f)
        labels.append(c.label)
        if start <= f.seq < stop:       # the character is drawn under the reactor puck
            assert (c.x, c.y) == (f.pucks[1].x, f.pucks[1].y) and c.valid
    assert "recording 20.0 s" in labels[stop - 1]
    assert e.mode == "trying" and "trained" in labels[stop] and "K keep" in labels[stop]
    # try it: the main puck alone drives the new behaviour, which keeps close like the take
    main = designers.designer_main_path(77, seconds=20)
    tries = [Frame(seq=1000 + i, t=200 + r[0], pucks=(Puck(1, r[1], r[2], r[3]),))
             for i, r in enumerate(main)]
    out = run([e], tries)["pet"]
    assert np.median(np.hypot(*(out[:, :2] - main[:, 1:3]).T)[80:]) < 0.22
    (c,) = e.step(Frame(seq=5000, t=300.0, commands=("designer.keep",)))
    assert "kept as pet" in c.label
    saved = library.load_behavior(tmp_path / "lib" / "pet")
    take = saved.demonstration
    assert len(take) == stop - start
    assert (np.diff(take[:, 0]) > 0).all() and take[0, 0] == 0.0
    assert np.allclose(take[:, 1:], demo[start:stop, 1:]) and np.allclose(
        take[:, 0], demo[start:stop, 0] - demo[start, 0])
    header = (tmp_path / "lib" / "pet" / "demonstration.csv").read_text().splitlines()[0]
    assert header == "t,main_x,main_y,main_dir,react_x,react_y,react_dir"
    assert e.mode == "idle" and e.behavior is not None


def test_designer_discard_and_keep_never_overwrite(tmp_path):
    (e,) = designer_engine(tmp_path)
    demo = designers.demonstrate("afraid", seed=2, seconds=12)
    corrupt = tmp_path / "lib" / "pet"
    corrupt.mkdir(parents=True)
    (corrupt / "behavior.yaml").write_text("kind: [\n")
    before = (corrupt / "behavior.yaml").read_bytes()
    cmds = {5: ("designer.record",), 200: ("designer.record",), 201: ("designer.discard",),
            210: ("designer.record",), 400: ("designer.record",), 401: ("designer.keep",),
            402: ("designer.keep",)}
    labels = [e.step(f)[0].label for f in designer_frames(demo, cmds)]
    assert "take discarded" in labels[201]
    assert "kept as pet-2" in labels[401]
    assert "nothing to keep" in labels[402]
    assert (corrupt / "behavior.yaml").read_bytes() == before
    assert library.list_behaviors(tmp_path / "lib") == ["pet", "pet-2"]
    assert len(library.load_behavior(tmp_path / "lib" / "pet-2").demonstration) == 190


def test_recording_again_redoes_the_take(tmp_path):
    (e,) = build([{"kind": "puppet_master", "name": "pet", "behavior": "behaviors/library/afraid",
                   "designer": {"enabled": True, "library": str(tmp_path),
                                "background_training": False}}])
    original = e.behavior
    demo = designers.demonstrate("lover", seed=2, seconds=12)
    cmds = {5: ("designer.record",), 150: ("designer.record",), 160: ("designer.record",),
            300: ("designer.record",)}
    takes = []
    for f in designer_frames(demo, cmds):
        e.step(f)
        if f.seq in (151, 301):
            takes.append(e.behavior)
    assert takes[0] is not takes[1] and original not in takes and e.mode == "trying"
    assert takes[1].samples == 140
    (c,) = e.step(Frame(seq=999, t=500.0, commands=("designer.discard",)))
    assert e.behavior is original and e.mode == "idle"
    assert "take discarded" in c.label
    assert list(tmp_path.iterdir()) == []


def test_too_short_a_take_is_not_trained(tmp_path):
    (e,) = designer_engine(tmp_path, min_seconds=3.0)
    demo = designers.demonstrate("bully", seed=2, seconds=5)
    cmds = {0: ("designer.record",), 40: ("designer.record",)}
    labels = [e.step(f)[0].label for f in designer_frames(demo, cmds)]
    assert "too short" in labels[40] and e.mode == "idle" and e.behavior is None
    assert not (tmp_path / "lib").exists()


def test_record_marker_starts_and_stops_recording(tmp_path):
    (e,) = designer_engine(tmp_path, record_marker=9)
    demo = designers.demonstrate("stalker", seed=4, seconds=15)
    marker = {i: (Puck(9, 0.1, 0.1, 0.0),) for i in range(40, 400)}
    modes = []
    for f in designer_frames(demo, {}, extra=marker):
        e.step(f)
        modes.append(e.mode)
    # on the table for 0.3 s (12 frames at 40 Hz) starts; lifted off for 0.3 s stops
    assert modes[51] == "idle" and modes[53] == "recording"
    assert modes[411] == "recording" and modes[413] == "trying"
    assert 355 <= len(e.take) <= 365


def test_tab_selects_which_designer_engine_records(tmp_path):
    a, b = build([
        {"kind": "puppet_master", "name": n,
         "designer": {"enabled": True, "library": str(tmp_path),
                                "background_training": False}} for n in ("a", "b")])
    demo = designers.demonstrate("lover", seed=1, seconds=3)
    assert a.designer_targets() == ("a",) and b.designer_targets() == ("b",)
    cmds = {4: ("designer.record",)}
    for f in designer_frames(demo, cmds):
        f = dataclasses.replace(f, focus="b")  # what the main loop sets after one Tab
        f = f.with_characters(a.step(f))
        (cb,) = b.step(f)
    assert a.mode == "idle" and b.mode == "recording"
    assert "[selected]" in cb.label


DEFAULT_ENTRY = """
engines:
  - kind: puppet_master
    name: lover
    behavior: behaviors/library/lover
    main: {puck: 1}
    color: [240, 110, 150]
    size: 0.08
"""


def test_the_default_config_entry_reacts_to_the_scripted_visitor():
    import yaml
    (e,) = build(yaml.safe_load(DEFAULT_ENTRY)["engines"])
    out = run([e], visitor_frames(10, seed=0))["lover"]
    assert out[:, 3].all() and np.hypot(*np.diff(out[:, :2], axis=0).T).sum() > 0.5
    assert np.median(np.hypot(*(out[:, :2] - main_track(10, seed=0)[:, :2]).T)[60:]) < 0.25


def test_background_training_swaps_the_take_in_between_ticks(tmp_path):
    (e,) = designer_engine(tmp_path, background_training=True)
    demo = designers.demonstrate("lover", seed=8, seconds=12)
    frames = list(designer_frames(demo, {5: ("designer.record",), 300: ("designer.record",)}))
    for f in frames[:301]:
        e.step(f)
    # the tick that stopped the recording did not train: the take trains in a worker thread
    assert e.mode == "idle" and e.pending is None and "training" in e.step(frames[301])[0].label
    e.trainer.wait(30.0)
    c = e.step(frames[302])[0]
    assert e.mode == "trying" and e.pending is not None and e.pending.samples > 200
    assert "trained" in c.label and c.valid
    for f in frames[303:]:
        assert e.step(f)[0].valid


def test_sequential_training_at_the_table(tmp_path):
    # one hand: the main puck alone, then the reactor puck against the main's playback
    (e,) = designer_engine(tmp_path, sequential=True)
    demo = designers.demonstrate("stalker", seed=4, seconds=12)
    t = 200.0
    for i, row in enumerate(demo):          # R, the main take (puck 1 only), R
        f = Frame(seq=i, t=t + row[0], pucks=(Puck(1, row[1], row[2], row[3]),),
                  commands={0: ("designer.record",), len(demo) - 1: ("designer.record",)}
                  .get(i, ()))
        e.step(f)
    assert e.mode == "recording" and "R plays it back" in e.step(
        Frame(seq=len(demo), t=t + 20.0))[0].label
    t2, seq0, ghosts = t + 30.0, len(demo) + 1, []
    for i, row in enumerate(demo):          # R: playback; puck 2 reacts; ends with the take
        f = Frame(seq=seq0 + i, t=t2 + row[0], pucks=(Puck(2, row[4], row[5], row[6]),),
                  commands=("designer.record",) if i == 0 else ())
        out = e.step(f)
        ghosts += [c for c in out if c.name == "pet.main"]
    assert len(ghosts) > len(demo) - 5
    # the ghost replays the main take where it was recorded
    g = np.array([(c.x, c.y) for c in ghosts[5:]])
    assert np.max(np.hypot(*(g - demo[5:5 + len(g), 1:3]).T)) < 0.01
    assert e.mode == "trying" and e.pending is not None
    # the paired demonstration is the two takes: main and reactor at matching times
    d = e.pending_demo
    assert len(d) >= len(demo) - 2
    assert np.allclose(d[:, 4:6], demo[:len(d), 4:6], atol=1e-9)
    assert np.max(np.hypot(*(d[:, 1:3] - demo[:len(d), 1:3]).T)) < 1e-6
