"""MOP action slots through the studio's one state machine: record, train, assign a motion, try,
keep (written to the library and loaded by a new engine), discard, redo, too short, focus
(what a take keeps of the gesture: test_studio_mop_trim.py)."""

from pathlib import Path

import numpy as np
import pytest
import yaml

from tabletop.frames import Frame, InputError, Puck
from tabletop.studio.machine import Studio
from tabletop.studio.mop_target import MopTarget
from tests.mop.helpers import EXAMPLES, G, RATE, Table, build, designer_config


class StudioTable(Table):
    """The stage behind a studio (no countdown, training within the tick), stepped as the loop
    does: studio filter, then the engine; ``status`` is the studio's status line."""

    def __init__(self, engine, lib: Path, focus: str = "mop/face") -> None:
        super().__init__(engine)
        self.targets = [MopTarget(engine, c, lib, background=False) for c in engine.order]
        self.studio = Studio(self.targets, countdown_s=0.0)
        self.focus, self.status = focus, ""

    def tick(self, commands=(), focus=None):
        pucks = tuple(Puck(i, x, y, 0.0) for i, (x, y) in self.pucks.items())
        frame = self.studio(Frame(self.seq, self.t, pucks=pucks, commands=tuple(commands),
                                  focus=focus or self.focus))
        self.status = frame.character("studio").label
        out = {c.name: c for c in self.engine.step(frame)}
        self.t += 1.0 / RATE
        self.seq += 1
        return out


def test_a_take_is_recorded_trained_assigned_kept_and_reloaded(tmp_path):
    engine = build(designer_config(tmp_path), tmp_path)
    table = StudioTable(engine, tmp_path / "lib", focus="mop/lizard")
    table.rest(1.0)
    table.tick(["designer.assign"])           # before a take: chosen for the next one
    assert "the next take plays curl" in table.status, table.status
    table.tick(["designer.assign"])
    assert "the next take plays strike" in table.status, table.status
    table.tick(["designer.record"])
    table.tick()
    assert "recording" in table.status and table.studio.state == "recording"
    table.perform("square")
    table.tick(["designer.record"])
    assert "take1 -> strike" in table.status and table.studio.state == "trying"
    assert engine.puppets["lizard"].actions["take1"].clip.name == "strike"
    table.tick(["designer.assign"])
    assert "take1 -> curl; try it: K keep" in table.status
    assert engine.puppets["lizard"].actions["take1"].clip.name == "curl"
    # trained at once: perform it (a little faster) and the lizard curls along
    table.rest(1.2)
    run = table.perform("square", speed=lambda u: 1.3)
    late = [ch["lizard"] for u, ch in run if u > 0.5]
    assert np.mean([x.valid and x.action == "take1" for x in late]) > 0.9
    assert late[-1].progress > 0.85
    # keep: written atomically to the library, and a new engine loads it
    table.tick(["designer.keep"])
    assert "kept as take1" in table.status and table.studio.state == "idle"
    saved = yaml.safe_load((tmp_path / "lib" / "lizard" / "actions.yaml").read_text())
    assert saved == {"actions": [{"name": "take1", "template": "take1.csv", "motion": "curl"}]}
    header = (tmp_path / "lib" / "lizard" / "take1.csv").read_text().splitlines()[0]
    assert header == "t,dx,dy"
    again = build(designer_config(tmp_path), tmp_path)
    assert "take1" in again.puppets["lizard"].actions
    assert again.templates["lizard"]["take1"][1].shape == engine.templates["lizard"]["take1"][1].shape


def test_discard_redo_and_a_take_too_short(tmp_path):
    engine = build(designer_config(tmp_path), tmp_path)
    table = StudioTable(engine, tmp_path / "lib")
    table.rest(1.0)
    table.tick(["designer.record"])
    table.perform("line")
    table.tick(["designer.record"])
    assert "take1" in engine.puppets["face"].actions
    n1 = len(engine.templates["face"]["take1"][1])
    table.rest(1.0)
    table.tick(["designer.record"])            # redo: the pending take is replaced
    assert "take1" not in engine.puppets["face"].actions
    assert table.studio.tries[-1].outcome == "redone"
    table.perform("zigzag")
    table.tick(["designer.record"])
    assert "take2" in engine.puppets["face"].actions
    assert n1 != len(engine.templates["face"]["take2"][1])
    table.tick(["designer.discard"])
    assert "discarded" in table.status and table.studio.tries[-1].outcome == "discarded"
    assert set(engine.puppets["face"].actions) == {"circle"}
    assert not (tmp_path / "lib").exists()
    # a take too short to learn from is refused
    table.tick(["designer.record"])
    table.tick(["designer.record"])
    assert "too short" in table.status and set(engine.puppets["face"].actions) == {"circle"}
    assert table.studio.tries[-1].outcome == "too short" and table.studio.state == "idle"


def test_the_focus_selects_the_character_and_other_targets_commands_pass(tmp_path):
    engine = build(designer_config(tmp_path), tmp_path)
    table = StudioTable(engine, tmp_path / "lib")
    assert table.studio.designer_targets() == ("mop/face", "mop/lizard")
    assert not hasattr(engine, "designer_targets")     # the studio lists the slots
    table.rest(0.5)
    table.focus = "mop/lizard"                         # Tab in the view
    table.tick(["designer.record"])
    assert engine.take.character == "lizard" and "[mop/lizard] recording" in table.status
    table.perform("square")
    table.tick(["designer.record"])
    assert "take1" in engine.puppets["lizard"].actions
    # commands addressed to another engine are not the studio's
    table.tick(["designer.discard"], focus="pm")
    assert "take1" in engine.puppets["lizard"].actions and table.studio.state == "trying"
    # moving the focus away from the take being tried discards it
    table.tick(focus="mop/face")
    assert "take1" not in engine.puppets["lizard"].actions
    assert table.studio.tries[-1].outcome == "discarded"


def test_a_bad_library_file_is_reported_and_skipped_and_a_fix_is_followed_at_once(tmp_path):
    # a kept square for the lizard, then its library damaged two ways
    engine = build(designer_config(tmp_path), tmp_path)
    table = StudioTable(engine, tmp_path / "lib", focus="mop/lizard")
    table.rest(1.0)
    table.tick(["designer.record"])
    table.perform("square")
    table.tick(["designer.record"])
    table.tick(["designer.keep"])
    lib = tmp_path / "lib"
    good = (lib / "lizard" / "actions.yaml").read_text()
    (lib / "lizard" / "actions.yaml").write_text("actions: [oops\n")
    (lib / "face").mkdir()
    (lib / "face" / "actions.yaml").write_text(
        "actions:\n- {name: wrong, template: nothere.csv, motion: talk}\n")
    # a restart: the engine starts, each bad file reported and skipped, the rest works
    engine = build(designer_config(tmp_path), tmp_path)
    assert "lizard/actions.yaml: cannot read the action library" in \
        engine.library_problems["lizard"][0]
    assert "face/actions.yaml: action 'wrong'" in engine.library_problems["face"][0]
    assert "nothere.csv" in engine.library_problems["face"][0]
    assert set(engine.puppets["face"].actions) == {"circle"} and not engine.puppets["lizard"].actions
    table = StudioTable(engine, lib, focus="mop/lizard")
    for t in table.targets:
        t._poller.every_s = 0.0
    table.tick()
    table.studio.poll()
    table.tick()
    assert "2 bad library file(s)" in table.status
    table.rest(1.0)
    run = table.perform("circle")                        # the face's own action still plays
    assert np.mean([c["face"].valid and c["face"].action == "circle" for u, c in run if u > 0.4]) > 0.9
    # fixed on disk: followed without a restart
    (lib / "lizard" / "actions.yaml").write_text(good)
    table.studio.poll()
    assert table.studio.problems == [table.studio.problems[0]] and "face" in table.studio.problems[0]
    assert "take1" in engine.puppets["lizard"].actions
    table.rest(1.2)
    run = table.perform("square", speed=lambda u: 1.3)
    assert np.mean([c["lizard"].valid and c["lizard"].action == "take1"
                    for u, c in run if u > 0.5]) > 0.9
    # deleted from the library (undo restores it): no longer followed
    table.studio.command("designer.item_next")
    table.studio.command("designer.delete")
    table.studio.poll()
    assert "take1" not in engine.puppets["lizard"].actions
    table.studio.command("designer.undo")
    table.studio.poll()
    assert "take1" in engine.puppets["lizard"].actions


def test_control_markers_through_the_camera_record_and_keep_an_action(tmp_path):
    from tabletop.config import load_config
    from tabletop.kiosk.simulate import SimClock, simulated
    from tests.mop.helpers import G

    rate = 20.0
    path = tmp_path / "config.yaml"
    path.write_text(yaml.safe_dump({
        "loop": {"rate_hz": rate},
        "sources": [{"kind": "synthetic_camera", "name": "camera", "pucks": [],
                     "resolution": [480, 270], "fps": rate, "hands": {"every_s": 0}}],
        "engines": [{"kind": "mop", "name": "mop", "library": "lib", "rate_hz": rate,
                     "performers": [{"name": "hand", "inputs": [{"kind": "puck", "id": 1}]}],
                     "characters": [{"name": "lizard", "kind": "creature", "performer": "hand",
                                     "motions": ["strike", "curl"]}]}],
        "view": {"size": [320, 180]},
        "studio": {"enabled": True, "countdown_s": 0.5, "review": False}}))
    square = G.gesture("square")

    def poses(s):
        u = float(np.clip(s - 1.3, 0.0, square[-1, 0]))      # the square from 1.3 s
        out = [(1, 0.5 + np.interp(u, square[:, 0], square[:, 1]),
                0.4 + np.interp(u, square[:, 0], square[:, 2]), 0.0)]
        if 0.3 <= s < 1.3 + square[-1, 0]:
            out.append((45, 0.06, 0.06, 0.0))                # record, in a corner
        if 5.0 <= s < 5.6:
            out.append((47, 1.14, 0.06, 0.0))                # keep
        return out

    clock = SimClock()
    runner, inst = simulated(load_config(path), path, clock, kiosk=False, studio=True)
    inst.loop.inputs.sources[0].reader.poses = poses
    states = []
    for _ in range(int(6.2 * rate)):
        frame = inst.loop.tick()
        states.append(frame.character("studio").action)
        clock.advance(1 / rate)
    inst.loop.close()
    order = [s for i, s in enumerate(states) if i == 0 or s != states[i - 1]]
    assert order == ["idle", "countdown", "recording", "training", "trying", "idle"]
    saved = yaml.safe_load((tmp_path / "lib" / "lizard" / "actions.yaml").read_text())
    assert saved["actions"][0]["name"] == "take1"
    rows = (tmp_path / "lib" / "lizard" / "take1.csv").read_text().splitlines()
    assert abs(len(rows) - 1 - rate * square[-1, 0]) < 0.5 * rate   # the square, recorded
    # after a restart the action is in the library and followed
    runner2, inst2 = simulated(load_config(path), path, SimClock(), kiosk=False, studio=True)
    assert runner2.studio.target.items() == ["take1"]
    assert "take1" in inst2.engines[0].puppets["lizard"].actions
    inst2.loop.close()


def face_take(tmp_path, gesture: str = "line"):
    """A run with the face's take of ``gesture`` being tried; (engine, table), the library
    read at once."""
    engine = build(designer_config(tmp_path), tmp_path)
    table = StudioTable(engine, tmp_path / "lib")
    for t in table.targets:
        t._poller.every_s = 0.0
    table.rest(1.0)
    table.tick(["designer.record"])
    table.perform(gesture)
    table.tick(["designer.record"])
    return engine, table


def kept_line(tmp_path):
    """The face's take of a line, kept as take1; (engine, table), the library read at once."""
    engine, table = face_take(tmp_path)
    table.tick(["designer.keep"])
    return engine, table


def test_a_kept_take_is_not_renamed_over_a_configured_action(tmp_path):
    """Renaming the face's kept take "circle" replaced its configured circle (talk) with the
    take on reload, and undo then took "circle" from the face altogether."""
    engine, table = kept_line(tmp_path)
    s = table.studio
    s.command("designer.item_next")
    s.command("designer.rename:circle")
    assert "already exists" in s.message
    s.poll()
    face = engine.puppets["face"].actions
    assert set(face) == {"circle", "take1"} and face["circle"].clip.name == "talk"
    s.command("designer.rename:  ")                    # a blank name is no name (the kept
    assert "rename needs a new name" in s.message      # action was skipped at reload)
    s.command("designer.rename:line")                  # a free name is still renamed to
    s.poll()
    assert set(face) == {"circle", "line"} and face["circle"].clip.name == "talk"
    s.command("designer.undo")
    s.poll()
    assert set(face) == {"circle", "take1"}


def deleted_take(tmp_path):
    """The kept take1 of a line, deleted in the studio: (engine, studio, the face's library
    folder, take1.csv's bytes before the delete)."""
    engine, table = kept_line(tmp_path)
    folder = tmp_path / "lib" / "face"
    kept = (folder / "take1.csv").read_bytes()
    s = table.studio
    s.command("designer.item_next")
    s.command("designer.delete")
    return engine, s, folder, kept


def test_a_deleted_action_goes_into_the_trash_and_undo_brings_it_back(tmp_path):
    """README: Delete moves the item into the library's .trash. A kept MOP take lost its entry
    only: its CSV stayed, and the next run's take1 wrote over it."""
    engine, s, folder, kept = deleted_take(tmp_path)
    s.poll()
    assert not (folder / "take1.csv").exists() and "take1" not in engine.puppets["face"].actions
    (trashed,) = (folder / ".trash").iterdir()
    assert trashed.name.startswith("take1.csv.") and trashed.read_bytes() == kept
    s.command("designer.undo")
    s.poll()
    assert (folder / "take1.csv").read_bytes() == kept and "take1" in engine.puppets["face"].actions


def test_an_undo_that_failed_half_way_is_done_on_the_next_try(tmp_path):
    """The undo of a delete put the template back, then could not write the entries (here
    actions.yaml stands as a folder): tried again, it said "take1.csv: exists again" forever
    and every older undo stayed out of reach."""
    engine, s, folder, kept = deleted_take(tmp_path)
    (folder / "actions.yaml").unlink()
    (folder / "actions.yaml").mkdir()
    s.command("designer.undo")
    assert s.message.startswith("cannot") and s.undo_stack[-1][0] == "delete take1", s.message
    assert (folder / "take1.csv").read_bytes() == kept    # half-way: the template is back
    (folder / "actions.yaml").rmdir()
    s.command("designer.undo")
    assert s.message == "undone: delete take1", s.message
    assert [what for what, _ in s.undo_stack] == ["keep take1"]     # the older undo next
    entries = yaml.safe_load((folder / "actions.yaml").read_text())["actions"]
    assert [a["name"] for a in entries] == ["take1"]
    assert (folder / "take1.csv").read_bytes() == kept and "take1" in engine.puppets["face"].actions


def test_delete_undo_and_rename_are_followed_on_their_own_tick(tmp_path):
    """They were followed when the library's watcher next looked (wall-clock time), so a
    replay changed the characters on other ticks than the live run (371 of 1147 frames
    differed); and after undoing a delete, F2 said "nothing to rename"."""
    engine, table = kept_line(tmp_path)
    s, target = table.studio, table.targets[0]
    target._poller.every_s = 1e9                 # the watcher does not look again
    s.command("designer.item_next")
    s.command("designer.delete")
    assert "take1" not in engine.puppets["face"].actions
    s.command("designer.undo")
    assert "take1" in engine.puppets["face"].actions and s.message == "undone: delete take1"
    s.command("designer.rename:wave")
    assert s.message == "renamed take1 to wave"
    assert set(engine.puppets["face"].actions) == {"circle", "wave"}
    target._poller.every_s = 0.0
    assert not target._poller.changed()          # nothing left for the watcher to apply


def test_a_new_take_never_takes_the_name_of_a_library_file_skipped_at_load(tmp_path):
    # a kept take1 whose template was damaged: skipped at load, a new take was named take1 and
    # its keep wrote over the file and the entry (take2.csv: a file no entry names)
    kept_line(tmp_path)
    folder = tmp_path / "lib" / "face"
    (folder / "take1.csv").write_text("t,dx,dy\n0,0,oops\n")
    (folder / "take2.csv").write_text("t,dx,dy\n0,0,0\n0.1,0.01,0\n")
    saved = {f.name: f.read_text() for f in folder.iterdir()}
    engine = build(designer_config(tmp_path), tmp_path)
    assert "action 'take1'" in engine.library_problems["face"][0]
    table = StudioTable(engine, tmp_path / "lib")
    table.rest(1.0)
    table.tick(["designer.record"])
    table.perform("line")
    table.tick(["designer.record"])
    assert "take3 -> " in table.status
    table.tick(["designer.keep"])
    assert "kept as take3" in table.status
    for name, text in saved.items():
        if name != "actions.yaml":
            assert (folder / name).read_text() == text
    entries = yaml.safe_load((folder / "actions.yaml").read_text())["actions"]
    assert [a["name"] for a in entries] == ["take1", "take3"]
    # and a save under a name the library holds is refused, the file left as it was
    with pytest.raises(InputError, match="in the library already"):
        engine.save("face", "take2", np.zeros((9, 2)), ("dx", "dy"), "talk")
    assert (folder / "take2.csv").read_text() == saved["take2.csv"]


def test_library_entries_without_a_name_named_twice_or_as_a_configured_action_are_skipped(tmp_path):
    """Each is reported naming the library file and skipped; the engine starts with the rest
    (an empty name stopped the start naming no file; a repeated name or a configured one
    silently replaced the earlier entry's or the configured action)."""
    lib = tmp_path / "lib"
    (lib / "face").mkdir(parents=True)
    line = (EXAMPLES / "mop/gestures/line.csv").read_text()
    for name in ("a", "b", "c"):
        (lib / "face" / f"{name}.csv").write_text(line)
    (lib / "face" / "d.csv").write_text("t,dx,dy\n0,0,0\n0.5,0,0.1\n1,0.1,0.1\n")
    (lib / "face" / "actions.yaml").write_text(
        "actions:\n- {name: '', template: d.csv, motion: laugh}\n"
        "- {name: line, template: a.csv, motion: laugh}\n"
        "- {name: line, template: b.csv, motion: wink}\n"
        "- {name: circle, template: c.csv, motion: angry}\n")
    engine = build(designer_config(tmp_path), tmp_path)
    problems = engine.library_problems["face"]
    assert len(problems) == 3 and all("face/actions.yaml: action " in p for p in problems)
    assert "'' needs a name" in problems[0] and "'line' is named twice" in problems[1]
    assert "'circle' has the name of an action the config gives" in problems[2]
    assert set(engine.puppets["face"].actions) == {"circle", "line"}
    assert engine.puppets["face"].actions["line"].clip.name == "laugh"
    circle = engine.templates["face"]["circle"][1]
    assert len(circle) == len(G.gesture("circle"))     # the configured template, not c.csv


def test_a_library_entry_that_fails_to_load_does_not_claim_its_name(tmp_path):
    """Two entries named wave, the first's template damaged and the second a fixed copy: the
    first is reported and the second loads (it was refused as "named twice; the first is
    kept", and neither was kept)."""
    lib = tmp_path / "lib"
    (lib / "face").mkdir(parents=True)
    (lib / "face" / "a.csv").write_text("t,dx,dy\n0,0,oops\n")
    (lib / "face" / "b.csv").write_text((EXAMPLES / "mop/gestures/line.csv").read_text())
    (lib / "face" / "actions.yaml").write_text(
        "actions:\n- {name: wave, template: a.csv, motion: laugh}\n"
        "- {name: wave, template: b.csv, motion: wink}\n")
    engine = build(designer_config(tmp_path), tmp_path)
    (problem,) = engine.library_problems["face"]
    assert "action 'wave'" in problem and "a.csv" in problem and "twice" not in problem, problem
    assert engine.puppets["face"].actions["wave"].clip.name == "wink"


def test_a_library_entry_whose_clip_the_character_cannot_play_is_skipped(tmp_path):
    """A kept action playing a creature's clip file on the face: reported and skipped (the clip
    was checked only when the face took the action, and that stopped the engine's start)."""
    import json

    from behaviors.mop.creatures import creature_clips
    from behaviors.motion.clips import clip_to_mapping
    lib = tmp_path / "lib"
    (lib / "face").mkdir(parents=True)
    (lib / "face" / "walk.json").write_text(json.dumps(clip_to_mapping(creature_clips()["walk"])))
    (lib / "face" / "a.csv").write_text((EXAMPLES / "mop/gestures/line.csv").read_text())
    (lib / "face" / "actions.yaml").write_text(
        f"actions:\n- {{name: a, template: a.csv, motion: {lib / 'face' / 'walk.json'}}}\n")
    engine = build(designer_config(tmp_path), tmp_path)
    (problem,) = engine.library_problems["face"]
    assert "face/actions.yaml: action 'a'" in problem and "no channel named after a blendshape" in problem
    assert set(engine.puppets["face"].actions) == {"circle"}


def kept_without_library(tmp_path, cfg: dict | None = None):
    """A face's take of a line kept "for this run only" by an engine without a library
    (``cfg``: the designer config by default, its library taken away). Returns (the engine,
    its studio table, the config)."""
    cfg = cfg or designer_config(tmp_path)
    cfg["engines"][0].pop("library", None)
    engine = build(cfg, tmp_path)
    table = StudioTable(engine, None)
    table.rest(1.0)
    table.tick(["designer.record"])
    table.perform("line")
    table.tick(["designer.record"])
    table.tick(["designer.keep"])
    assert "for this run only" in table.status
    return engine, table, cfg


def test_undo_delete_and_rename_of_a_take_kept_for_this_run_only(tmp_path):
    """Without a library, U, Del and F2 after a keep raised AssertionError out of the studio;
    the keep's undo entry stayed and every later U raised again, for every character."""
    engine, table, _ = kept_without_library(tmp_path)
    s, face = table.studio, engine.puppets["face"].actions
    table.tick(["designer.rename:wave"])
    assert "has no library" in table.status and set(face) == {"circle", "take1"}
    table.tick(["designer.delete"])
    assert "deleted take1" in table.status and "take1" not in face
    table.tick(["designer.undo"])
    assert table.status.endswith("undone: delete take1") and "take1" in face
    table.tick(["designer.undo"])
    assert table.status.endswith("undone: keep take1") and "take1" not in face
    assert s.undo_stack == []
    table.tick(["designer.undo"])
    assert table.status.endswith("nothing to undo")


def test_the_idle_line_names_the_actions_a_character_knows_when_none_is_selected(tmp_path):
    # "[mop/face] action (none)" of a face playing its configured actions read as a face
    # that knew nothing
    engine = build(designer_config(tmp_path), tmp_path)
    table = StudioTable(engine, tmp_path / "lib")
    table.tick()
    known = ", ".join(sorted(engine.templates["face"]))
    assert table.status.startswith(f"[mop/face] action (none selected; it knows {known}): R "
                                   "record"), table.status


def test_a_still_take_says_the_performer_hardly_moved(tmp_path):
    # 3 s recorded with the puck resting said "take too short (1 samples of motion)", as if R
    # had been pressed twice at once
    engine = build(designer_config(tmp_path), tmp_path)
    table = StudioTable(engine, tmp_path / "lib")
    table.rest(1.0)
    table.tick(["designer.record"])
    table.rest(3.0)
    table.tick(["designer.record"])
    assert ("take too short: hand hardly moved in the 3.0 s recorded (1 of 8 samples of "
            "motion)") in table.status, table.status
    assert table.studio.tries[-1].outcome == "too short"
    table.tick(["designer.record"])               # pressed twice at once: no word of stillness
    table.tick(["designer.record"])
    assert "take too short (1 of 8 samples of motion)" in table.status, table.status


def test_the_countdown_names_the_performer_and_its_puck(tmp_path):
    # the countdown of an action's take said only "get ready": which puck performs?
    engine = build(designer_config(tmp_path), tmp_path)
    table = StudioTable(engine, tmp_path / "lib")
    table.studio.countdown_s = 1.0
    table.tick(["designer.record"])
    assert table.studio.state == "countdown"
    assert table.status == "[mop/face] get ready: hand (puck 1) performs face's new action"


def test_a_bad_library_file_at_the_start_is_logged_once(tmp_path, caplog):
    """The engine logs a bad library file as it starts; the studio behind it logs only what
    changes after that, so the operator reads the file's problem once."""
    (tmp_path / "lib" / "lizard").mkdir(parents=True)
    (tmp_path / "lib" / "lizard" / "actions.yaml").write_text("actions: [oops\n")
    with caplog.at_level("ERROR", logger="tabletop"):
        engine = build(designer_config(tmp_path), tmp_path)
        table = StudioTable(engine, tmp_path / "lib", focus="mop/lizard")
        for t in table.targets:
            t._poller.every_s = 0.0
        for _ in range(2):
            table.tick()
            table.studio.poll()
        table.tick()
    said = [r.getMessage() for r in caplog.records if "lizard/actions.yaml" in r.getMessage()]
    assert len(said) == 1, said
    assert "1 bad library file(s)" in table.status
