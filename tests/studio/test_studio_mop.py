"""MOP action slots through the studio's one state machine: record, train, assign a motion, try,
keep (written to the library and loaded by a new engine), discard, redo, too short, focus, the
status line (what a take keeps of the gesture: test_studio_mop_trim.py; rename, delete and undo:
test_studio_mop_edits.py; bad library files: test_studio_mop_library_files.py)."""

import numpy as np
import yaml

from tabletop.plugins.mop_table import G, build, designer_config
from tabletop.studio.mop_table import StudioTable


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
    table.stop_take()
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
    assert [x.progress for x in late if x.valid][-1] > 0.85   # (the very last tick may
    # or may not see the puck at rest, by the tick's phase against the 30 Hz samples)
    # keep: written atomically to the library, and a new engine loads it
    table.tick(["designer.keep"])
    assert "kept as take1" in table.status and table.studio.state == "idle"
    saved = yaml.safe_load((tmp_path / "lib" / "lizard" / "actions.yaml").read_text())
    assert saved == {"actions": [{"name": "take1", "template": "take1.csv", "motion": "curl"}]}
    header = (tmp_path / "lib" / "lizard" / "take1.csv").read_text().splitlines()[0]
    assert header == "t,dx,dy"
    again = build(designer_config(tmp_path), tmp_path)
    assert "take1" in again.puppets["lizard"].actions
    assert again.templates["lizard"]["take1"][1].shape \
        == engine.templates["lizard"]["take1"][1].shape


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


def test_control_markers_through_the_camera_record_and_keep_an_action(tmp_path):
    from tabletop.config import load_config
    from tabletop.kiosk.simulate import SimClock, simulated

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


def test_the_idle_line_names_the_actions_a_character_knows_when_none_is_selected(tmp_path):
    # "[mop/face] action (none)" of a face playing its configured actions read as a face
    # that knew nothing
    engine = build(designer_config(tmp_path), tmp_path)
    table = StudioTable(engine, tmp_path / "lib")
    table.tick()
    known = ", ".join(sorted(engine.templates["face"]))
    assert table.status.startswith(f"[mop/face] action (none selected; it knows {known}), "
                                   "window 15 shared with lizard (+/-): R record"), table.status


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


def recording_after_circle(tmp_path, gesture: str = "circle"):
    """The face playing circle, then a take of the face started at once and ``gesture``
    performed while it records; (engine, table, the face while it recorded, from the take's
    first tick)."""
    engine = build(designer_config(tmp_path), tmp_path)
    table = StudioTable(engine, tmp_path / "lib")
    table.rest(1.0)
    idle = [ch["face"] for _, ch in table.perform("circle")]
    assert np.mean([c.valid and c.action == "circle" for c in idle]) > 0.5
    assert idle[-1].action == "circle"
    first = table.tick(["designer.record"])["face"]
    taking = [first] + [ch["face"] for _, ch in table.perform(gesture)]
    assert table.studio.state == "recording"
    return engine, table, taking


def not_driven(taking) -> None:
    """From the take's first tick the face plays and names none of its actions."""
    assert not any(c.valid for c in taking)
    assert {c.action for c in taking} == {None}
    assert {c.label for c in taking} == {"recording hand's new action"}


def plays(table, gesture: str = "circle", action: str = "circle") -> None:
    """Performed after a rest, ``gesture`` makes the face play ``action`` most of the time."""
    table.rest(1.0)
    again = [ch["face"] for _, ch in table.perform(gesture)]
    assert np.mean([c.valid and c.action == action for c in again]) > 0.5


def test_the_character_a_take_records_for_is_not_driven_while_it_records(tmp_path):
    """The face knows circle: performed idle, it plays it; performed while a take of the face
    records, the face plays and names none of its actions (not even the one it played a tick
    before) and its label says it records; the take discarded, it plays circle again."""
    engine, table, taking = recording_after_circle(tmp_path)
    not_driven(taking)
    table.tick(["designer.record"])                 # stopped, then discarded: circle plays
    table.tick(["designer.discard"])
    assert table.studio.state == "idle" and set(engine.puppets["face"].actions) == {"circle"}
    plays(table)


def test_a_kept_take_of_the_character_plays_after_it_recorded(tmp_path):
    engine, table, taking = recording_after_circle(tmp_path, "line")
    not_driven(taking)
    table.tick(["designer.record"])
    table.tick(["designer.keep"])
    assert table.studio.state == "idle"
    assert set(engine.puppets["face"].actions) == {"circle", "take1"}
    plays(table, "line", "take1")
    plays(table)


def test_the_studio_closed_mid_take_lets_the_character_play_again(tmp_path):
    engine, table, taking = recording_after_circle(tmp_path)
    not_driven(taking)
    table.studio.close()
    assert table.studio.state == "idle" and engine.take is None
    plays(table)


def test_a_take_whose_puck_is_not_seen_says_so(tmp_path):
    """A MOP take recorded with its performer's puck off the table (or hidden) says while it
    records that the puck is not seen, and when stopped for how long it was unseen, as a
    Puppet Master take does."""
    engine = build(designer_config(tmp_path), tmp_path)
    table = StudioTable(engine, tmp_path / "lib")
    table.rest(1.0)
    del table.pucks[1]                          # lifted: the camera sees no puck 1
    table.tick(["designer.record"])
    for _ in range(60):
        table.tick()
    assert "recording: no puck 1" in table.status, table.status
    table.tick(["designer.record"])
    assert "too short" in table.status and "puck 1 unseen 1.0 s of 1.0 s" in table.status, \
        table.status
    # lifted for part of a gesture: the trained line says how long, the frames left out
    table.pucks[1] = (0.3, 0.3)
    table.rest(1.0)
    table.tick(["designer.record"])
    table.perform("line")
    del table.pucks[1]
    for _ in range(30):
        table.tick()
    table.pucks[1] = (0.3, 0.3)
    table.perform("zigzag")
    table.stop_take()
    assert "take1 ->" in table.status and "puck 1 unseen 0.5 s of" in table.status, table.status


def test_a_on_a_character_of_one_motion_says_it_is_the_only_one(tmp_path):
    """A on a character that has one motion (the bird of examples/mop.yaml) cycled to that
    motion and said the same line again, the key looking broken: the line says it is the only
    one, before a take and while one is tried."""
    cfg = designer_config(tmp_path)
    cfg["engines"][0]["characters"][1]["motions"] = ["strike"]
    engine = build(cfg, tmp_path)
    table = StudioTable(engine, tmp_path / "lib", focus="mop/lizard")
    table.rest(1.0)
    table.tick(["designer.assign"])
    assert "the next take plays strike (strike is the only motion lizard has)" in table.status
    table.tick(["designer.record"])
    table.tick()
    table.perform("square")
    table.tick(["designer.record"])
    table.tick(["designer.assign"])
    assert "take1 -> strike (strike is the only motion lizard has); try it" in table.status
    table.focus = "mop/face"                             # several motions: as before
    table.tick(["designer.discard"])
    table.tick(["designer.assign"])
    assert "(A: another motion)" in table.status and "only motion" not in table.status


def test_an_action_take_tried_at_quit_is_saved_as_its_template(tmp_path):
    """A MOP take tried and not kept at quit is saved beside the session log as the template
    CSV its keep writes (t and the performer's features), named in the log line; the library
    does not list it, and ``tabletop follow`` follows the take along it."""
    import json

    from tabletop.cli import main as cli
    from tabletop.studio.session import SessionLog
    from tests.studio.mop_table import face_take
    engine, table = face_take(tmp_path)
    session = SessionLog(tmp_path / "studio", review=False)
    table.studio.log_try, table.studio.save_take = session.log_try, session.save_take
    assert table.studio.state == "trying"
    samples = np.asarray(engine.take.samples())
    table.studio.close()
    (line,) = [json.loads(x) for x in session.path.read_text().splitlines()]
    saved = session.folder / line["take"]
    assert line["outcome"] == "quit" and saved.suffix == ".csv", line
    assert "take tried, not kept; saved as" in table.studio.message
    header, *rows = saved.read_text().splitlines()
    got = np.array([[float(v) for v in r.split(",")] for r in rows])
    assert header.split(",")[0] == "t" and np.allclose(got[:, 1:], samples), header
    assert not (tmp_path / "lib" / "face").exists() or "take1" not in \
        (tmp_path / "lib" / "face" / "actions.yaml").read_text()
    assert cli(["follow", "--template", f"take={saved}", "--input", str(saved),
                "--out", str(tmp_path / "o.csv")]) == 0
    valid = [r.split(",")[-2] for r in (tmp_path / "o.csv").read_text().splitlines()[1:]]
    assert valid.count("1") >= len(valid) // 2, valid


def test_an_action_take_still_recorded_at_quit_is_saved_as_its_template(tmp_path, caplog):
    """A MOP take still recorded at quit was dropped ("take cancelled at quit"): it is saved
    as a tried one is (the template CSV, ``follow`` follows it); one of fewer samples than a
    take is learned from is not, and the log says so."""
    import json

    from tabletop.cli import main as cli
    from tabletop.plugins.mop_table import build, designer_config
    from tabletop.studio.mop_table import StudioTable
    from tabletop.studio.session import SessionLog
    for sub, gesture in (("a", "line"), ("b", None)):
        table = StudioTable(build(designer_config(tmp_path / sub), tmp_path / sub),
                            tmp_path / sub / "lib")
        session = SessionLog(tmp_path / sub / "studio", review=False)
        table.studio.log_try, table.studio.save_take = session.log_try, session.save_take
        table.rest(1.0)
        table.tick(["designer.record"])
        if gesture:
            table.perform(gesture)
        assert table.studio.state == "recording"
        if gesture:
            samples = np.asarray(table.engine.take.samples())
        with caplog.at_level("INFO", logger="tabletop"):
            table.studio.close()
    (line,) = [json.loads(x) for x in
               next((tmp_path / "a" / "studio").glob("*.jsonl")).read_text().splitlines()]
    saved = tmp_path / "a" / "studio" / line["take"]
    assert line["outcome"] == "quit" and saved.suffix == ".csv", line
    assert f"take recorded, not tried, at quit; saved as {saved}" in caplog.text
    got = np.loadtxt(saved, delimiter=",", skiprows=1)
    assert np.allclose(got[:, 1:], samples) and len(got) > 30
    assert cli(["follow", "--template", f"take={saved}", "--input", str(saved),
                "--out", str(tmp_path / "o.csv")]) == 0
    assert list((tmp_path / "b" / "studio").glob("*take*")) == []
    assert "take cancelled at quit; nothing saved: take too short (1 of 8 samples)" \
        in caplog.text, caplog.text
