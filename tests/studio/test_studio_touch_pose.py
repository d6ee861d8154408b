"""Touch-pose actions designed in the studio: a take posed with a finger is recorded, trained,
tried (the drag along its path plays it), kept, known after a restart, renamed, deleted, undone,
redone; a take that hardly moves is refused; a bad library file is reported and skipped and a
fixed one picked up without a restart. By keys, and by control markers through the synthetic
camera (the names takes are kept under: test_studio_touch_pose_names.py)."""

import json
from pathlib import Path

import numpy as np
import pytest
import yaml

from behaviors.touch_pose.humanoid import PARTS
from tabletop.config import load_config, validate_config
from tabletop.frames import Frame, Observation, SourceHealth, Touch
from tabletop.kiosk.simulate import SimClock, simulated
from tabletop.plugins import touch_pose
from tabletop.registry import BuildContext
from tabletop.studio.machine import Studio
from tabletop.studio.pose_target import TouchPoseTarget
from tests.touch_pose.conftest import models  # noqa: F401  (the learned models, once)

TABLE = (1.2, 0.8)
RATE = 30.0
DRAG_S = 1.2


def arc(u: float) -> np.ndarray:
    """The designer's drag, table metres from where the finger went down (out and up)."""
    return np.array([0.06 * np.sin(np.pi / 2 * u), 0.10 * u])


def part_at(engine, part: str) -> np.ndarray:
    """Where ``part`` is drawn on the table now (metres)."""
    core = engine.core
    return core.camera.table(core._points(core.output)[core._np:])[PARTS.index(part)]


class Poser:
    """A touch-pose engine behind the studio (no countdown), stepped as the loop does."""

    def __init__(self, tmp_path: Path, models) -> None:
        self.cfg = validate_config({"sources": [{"kind": "scripted", "pucks": []}], "engines": [{
            "kind": "touch_pose", "name": "poser", "view": [90, 15], "physics": False,
            "mouse": False, "library": "actions"}]}, str(tmp_path / "c.yaml"), tmp_path)
        self.tmp = tmp_path
        self.engine = self.build()
        self.target = TouchPoseTarget(self.engine)
        self.target._poller.every_s = 0.0
        self.studio = Studio([self.target], countdown_s=0.0)
        self.t, self.seq, self.status = 10.0, 0, ""

    def build(self):
        return touch_pose.build(self.cfg["engines"][0],
                                BuildContext(TABLE, RATE, self.cfg, self.tmp))

    def tick(self, finger=None, cmds=()):
        touches = () if finger is None else (Touch(1, float(finger[0]), float(finger[1])),)
        f = self.studio(Frame(self.seq, self.t, touches=touches, commands=tuple(cmds)))
        self.shown = f.character("studio")           # what the view draws for the studio
        self.status = self.shown.label
        self.studio.poll()
        (c,) = self.engine.step(f)
        self.t += 1 / RATE
        self.seq += 1
        return c

    def drag(self, part="right_hand", pace=1.0, path=arc):
        """Drag ``part`` along ``path`` from where it is drawn; the characters, then lift."""
        start = part_at(self.engine, part)
        n = int(DRAG_S * pace * RATE)
        out = [self.tick(start + path(k / n)) for k in range(n + 1)]
        return out + [self.tick() for _ in range(int(2.5 * RATE))]

    def take(self, path=arc, stop=True, settle=12):
        """R, a drag of the right hand, R (``stop``), then ``settle`` ticks."""
        self.tick(cmds=["designer.record"])
        start = part_at(self.engine, "right_hand")
        n = int(DRAG_S * RATE)
        for k in range(n + 1):
            self.tick(start + path(k / n))
        if stop:
            self.tick(start + path(1.0), cmds=["designer.record"])
        for _ in range(settle):                       # learned, in play 0.3 s after the stop
            self.tick()


def played(chars, name) -> int:
    return sum(c.action == name for c in chars)


def test_a_posed_take_is_trained_tried_kept_and_known_after_a_restart(tmp_path, models):
    p = Poser(tmp_path, models)
    for _ in range(10):
        p.tick()
    p.take()
    assert p.studio.state == "trying" and "trained poser-action: its right hand" in p.status
    guide = p.shown.points                     # the path to drag is drawn from the hand
    assert p.shown.action == "trying" and len(guide) > 10
    assert np.linalg.norm(guide[0] - part_at(p.engine, "right_hand")) < 0.01
    assert np.linalg.norm(guide[-1] - guide[0]) > 0.05
    run = p.drag()
    assert played(run, "poser-action") > 0.5 * DRAG_S * RATE          # the drag plays it
    assert max(c.progress or 0.0 for c in run if c.action == "poser-action") > 0.9
    demo = p.target.demo                       # the session log's figures: t, the hand's path
    p.tick(cmds=["designer.keep"])
    assert f"kept as poser-action in {p.target.lib}/" in p.status and p.studio.state == "idle"
    assert demo.shape[1] == 4 and demo[-1, 0] == pytest.approx(DRAG_S, abs=0.1)
    assert np.linalg.norm(demo[-1, 1:] - demo[0, 1:]) > 0.2      # character metres
    from tabletop.studio.review import review_sheet
    review_sheet("pose action", demo, tmp_path / "try.png", title="poser: kept")
    assert (tmp_path / "try.png").stat().st_size > 10_000
    stored = json.loads((tmp_path / "actions" / "poser-action" / "action.json").read_text())
    assert stored["part"] == "right_hand" and len(stored["times"]) == len(stored["rots"]) > 30
    # a restart: the engine knows it from its library, and the same drag plays it
    again = Poser(tmp_path, models)
    assert "poser-action" in [a.name for a in again.engine.core.m.actions]
    assert again.target.items() == ["poser-action"]
    for _ in range(10):
        again.tick()
    assert played(again.drag(), "poser-action") > 0.5 * DRAG_S * RATE
    # another character's models are not changed by this one's actions
    assert "poser-action" not in [a.name for a in models.actions]
    # the drag only poses when it is 4 times slower, or once the take is discarded
    fresh = Poser(tmp_path / "other", models)
    fresh.take()
    assert played(fresh.drag(pace=4.0), "poser-action") == 0
    fresh.tick(cmds=["designer.discard"])
    assert played(fresh.drag(), "poser-action") == 0


def test_rename_delete_undo_redo_and_a_take_that_hardly_moves(tmp_path, models):
    p = Poser(tmp_path, models)
    p.take()
    p.tick(cmds=["designer.keep"])
    lib = tmp_path / "actions"
    # a built-in action's name is refused: renamed "punch", the take replaced the character's
    # own punch, and undo then took the punch away from it
    punch = next(a for a in p.engine.core.m.actions if a.name == "punch")
    p.studio.command("designer.rename:punch")
    assert "already exists" in p.studio.message and p.target.items() == ["poser-action"]
    assert punch in p.engine.core.m.actions
    p.studio.command("designer.rename:uppercut")
    assert p.target.items() == ["uppercut"] \
        and "renamed poser-action to uppercut" in p.studio.message
    names = [a.name for a in p.engine.core.m.actions]
    assert "uppercut" in names and "poser-action" not in names
    p.studio.command("designer.delete")
    assert p.target.items() == [] and "uppercut" not in [a.name for a in p.engine.core.m.actions]
    assert len(list((lib / ".trash").iterdir())) == 1
    p.studio.command("designer.undo")                 # the delete
    assert p.target.items() == ["uppercut"] \
        and "uppercut" in [a.name for a in p.engine.core.m.actions]
    assert p.target.current() == "uppercut"           # selected again: F2 said nothing to rename
    p.studio.command("designer.undo")                 # the rename
    assert p.target.items() == ["poser-action"]
    p.studio.command("designer.undo")                 # the keep
    assert p.target.items() == []
    # redo: R while trying drops the take being tried and records again
    p.take()
    assert "poser-action" in [a.name for a in p.engine.core.m.actions]
    p.tick(cmds=["designer.record"])
    assert p.studio.state == "recording" and p.studio.tries[-1].outcome == "redone"
    assert "poser-action" not in [a.name for a in p.engine.core.m.actions]
    p.tick(cmds=["designer.stop"])                    # a take without motion is refused
    assert p.studio.state == "training"               # (learned in the worker)
    for _ in range(12):                               # swapped in 0.3 s after the stop
        p.tick()
    assert p.studio.state == "idle" and p.studio.tries[-1].outcome == "too short"
    p.tick(cmds=["designer.record"])                  # a second of nobody posing it
    for _ in range(int(RATE)):
        p.tick()
    assert "hold a body part and move it" in p.status
    p.tick(cmds=["designer.stop"])
    for _ in range(12):
        p.tick()
    assert p.studio.state == "idle" and p.studio.tries[-1].outcome == "refused"
    assert "no body part was held" in p.studio.message   # said "the head hardly moves (0.00 m)"


def test_a_bad_action_file_is_reported_and_skipped_and_a_fix_is_picked_up(tmp_path, models):
    p = Poser(tmp_path, models)
    p.take()
    p.tick(cmds=["designer.keep"])
    p.take(path=lambda u: arc(u)[::-1])
    p.tick(cmds=["designer.keep"])
    lib = tmp_path / "actions"
    assert p.target.items() == ["poser-action", "poser-action-2"]
    good = (lib / "poser-action" / "action.json").read_text()
    (lib / "poser-action" / "action.json").write_text(good[: len(good) // 2])   # cut short
    p.tick()                                          # polled after the tick: shown on the next
    p.tick()
    assert "poser-action/action.json: cannot read the action" in p.status
    assert "bad library file" in p.status
    names = [a.name for a in p.engine.core.m.actions]
    assert "poser-action" not in names and "poser-action-2" in names      # the other works
    again = Poser(tmp_path, models)                   # a start skips it too, with its reason
    assert again.engine.problems and "poser-action" in again.engine.problems[0]
    assert "poser-action-2" in [a.name for a in again.engine.core.m.actions]
    (lib / "poser-action" / "action.json").write_text(good)              # fixed on disk
    p.tick()
    p.tick()
    assert "bad library file" not in p.status
    assert {"poser-action", "poser-action-2"} <= {a.name for a in p.engine.core.m.actions}


class Finger:
    """A touch source (as a TUIO table would give) on the simulated clock: ``where(t)``."""

    name = "finger"

    def __init__(self, clock, where) -> None:
        self.clock, self.where, self.seq = clock, where, 0

    def open(self) -> None:
        pass

    def close(self) -> None:
        pass

    def latest(self):
        t = self.clock()
        xy = self.where(t)
        self.seq += 1
        touches = () if xy is None else (Touch(7, float(xy[0]), float(xy[1])),)
        return Observation(self.name, t, self.seq, touches=touches)

    def health(self):
        return SourceHealth(self.name, True, "ok")


def test_control_markers_through_the_camera_record_and_keep_a_posed_action(tmp_path, models):
    rate = 20.0
    path = tmp_path / "config.yaml"
    path.write_text(yaml.safe_dump({
        "loop": {"rate_hz": rate},
        "sources": [{"kind": "synthetic_camera", "name": "camera", "pucks": [],
                     "resolution": [480, 270], "fps": rate, "hands": {"every_s": 0}}],
        "engines": [{"kind": "touch_pose", "name": "poser", "view": [90, 15], "physics": False,
                     "mouse": False, "library": "actions"}],
        "view": {"size": [320, 180]},
        "studio": {"enabled": True, "countdown_s": 0.5, "review": False}}))
    clock = SimClock()
    runner, inst = simulated(load_config(path), path, clock, kiosk=False, studio=True)
    engine = inst.engines[0]
    t0 = clock()
    starts: dict[str, np.ndarray] = {}

    def finger(t):
        s = t - t0
        for phase, (a, b) in {"take": (1.8, 1.8 + DRAG_S), "try": (4.5, 4.5 + DRAG_S)}.items():
            if a <= s <= b:
                if phase not in starts:
                    starts[phase] = part_at(engine, "right_hand")
                return starts[phase] + arc((s - a) / DRAG_S)
        return None

    def markers(s):
        out = []
        if 0.3 <= s < 3.4:
            out.append((45, 0.06, 0.06, 0.0))        # record, in a corner
        if 6.5 <= s < 7.2:
            out.append((47, 1.14, 0.06, 0.0))        # keep
        return out

    inst.loop.inputs.sources[0].reader.poses = markers
    inst.loop.inputs.sources.append(Finger(clock, finger))
    states, actions = [], []
    for _ in range(int(7.8 * rate)):
        frame = inst.loop.tick()
        states.append(frame.character("studio").action)
        actions.append(frame.character("poser").action)
        assert not {45, 47} & {p.id for p in frame.pucks}    # markers are controls, not inputs
        clock.advance(1 / rate)
    inst.loop.close()
    order = [s for i, s in enumerate(states) if i == 0 or s != states[i - 1]]
    assert order == ["idle", "countdown", "recording", "training", "trying", "idle"]
    assert states.count("training") == 6                  # 0.3 s after the stop, at 20 Hz
    rec = [i / rate for i, s in enumerate(states) if s == "recording"]
    assert 1.0 <= rec[0] <= 1.3 and 3.6 <= rec[-1] <= 3.9      # debounce 0.3 s, countdown 0.5 s
    tried = [i / rate for i, a in enumerate(actions) if a == "poser-action"]
    assert tried and 4.5 <= tried[0] <= 4.5 + DRAG_S             # the try's drag played it
    assert (tmp_path / "actions" / "poser-action" / "action.json").is_file()
    # after a restart the action is in the library and known to the character
    runner2, inst2 = simulated(load_config(path), path, SimClock(), kiosk=False, studio=True)
    assert runner2.studio.target.items() == ["poser-action"]
    assert "poser-action" in [a.name for a in inst2.engines[0].core.m.actions]
    inst2.loop.close()


def test_a_bad_action_file_at_the_start_is_logged_once(tmp_path, models, caplog):
    """The engine logs a bad library file as it starts; the studio behind it logs only what
    changes after that, so the operator reads the file's problem once."""
    bad = tmp_path / "actions" / "wave"
    bad.mkdir(parents=True)
    (bad / "action.json").write_text('{"name": "wave", "part": ')    # cut short
    with caplog.at_level("ERROR", logger="tabletop"):
        p = Poser(tmp_path, models)
        for _ in range(3):
            p.tick()
    said = [r.getMessage() for r in caplog.records if "wave/action.json" in r.getMessage()]
    assert len(said) == 1, said
    assert "bad library file" in p.status and "wave/action.json" in p.status


def test_a_posed_take_tried_at_quit_is_saved_as_its_action_file(tmp_path, models):
    """A posed take tried and not kept at quit is saved beside the session log as the
    action.json its keep writes (named in the log line); the library does not hold it."""
    from tabletop.studio.session import SessionLog
    p = Poser(tmp_path, models)
    session = SessionLog(tmp_path / "studio", review=False)
    p.studio.log_try, p.studio.save_take = session.log_try, session.save_take
    for _ in range(10):
        p.tick()
    p.take()
    assert p.studio.state == "trying"
    p.studio.close()
    (line,) = [json.loads(x) for x in session.path.read_text().splitlines()]
    saved = session.folder / line["take"]
    assert line["outcome"] == "quit" and saved.suffix == ".json", line
    stored = json.loads(saved.read_text())
    assert stored["name"] == "poser-action" and stored["part"] == "right_hand"
    assert len(stored["times"]) == len(stored["rots"]) > 30
    assert not (tmp_path / "actions" / "poser-action").exists()
    again = Poser(tmp_path, models)                 # nothing loads it
    assert again.target.items() == []


def test_a_posed_take_recorded_or_learned_at_quit_is_saved_as_its_action_file(tmp_path, models,
                                                                              caplog):
    """A posed take still recorded at quit, or still being learned, was not saved: it is, as
    the action.json its keep would write; a take of no part held says why nothing was."""
    from tabletop.studio.session import SessionLog

    def quit_after(sub, ticks):
        p = Poser(tmp_path / sub, models)
        session = SessionLog(tmp_path / sub / "studio", review=False)
        p.studio.log_try, p.studio.save_take = session.log_try, session.save_take
        ticks(p)
        state = p.studio.state
        with caplog.at_level("INFO", logger="tabletop"):
            p.studio.close()
        lines = session.path.read_text().splitlines() if session.path.exists() else []
        return state, [json.loads(x) for x in lines], session.folder

    for sub, ticks, state in (("rec", lambda p: p.take(stop=False, settle=0), "recording"),
                              ("learn", lambda p: p.take(settle=0), "training")):
        was, (line,), folder = quit_after(sub, ticks)
        assert was == state and line["outcome"] == "quit", (was, line)
        stored = json.loads((folder / line["take"]).read_text())
        assert stored["name"] == "poser-action" and stored["part"] == "right_hand"
        assert len(stored["times"]) == len(stored["rots"]) > 30
        assert not (tmp_path / sub / "actions" / "poser-action").exists()
    was, lines, folder = quit_after("none", lambda p: [p.tick(cmds=["designer.record"])] + [
        p.tick() for _ in range(int(RATE))])
    assert was == "recording" and lines == [] and list(folder.glob("*take*")) == []
    assert "take cancelled at quit; nothing saved: no body part was held" in caplog.text
