"""Bad MOP library files and entries behind the studio: reported once and skipped, the others
kept working, a fix followed at once, and no take named as a skipped file."""

import numpy as np
import pytest
import yaml

from tabletop.frames import InputError
from tabletop.plugins.mop_table import EXAMPLES, G, build, designer_config
from tabletop.studio.mop_table import StudioTable
from tests.studio.mop_table import kept_line


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
    assert set(engine.puppets["face"].actions) == {"circle"} \
        and not engine.puppets["lizard"].actions
    table = StudioTable(engine, lib, focus="mop/lizard")
    for t in table.targets:
        t._poller.every_s = 0.0
    table.tick()
    table.studio.poll()
    table.tick()
    assert "2 bad library file(s)" in table.status
    table.rest(1.0)
    run = table.perform("circle")                        # the face's own action still plays
    assert np.mean([c["face"].valid and c["face"].action == "circle"
                    for u, c in run if u > 0.4]) > 0.9
    # fixed on disk: followed without a restart
    (lib / "lizard" / "actions.yaml").write_text(good)
    table.studio.poll()
    assert table.studio.problems == [table.studio.problems[0]] \
        and "face" in table.studio.problems[0]
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
    table.stop_take()
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

@pytest.mark.parametrize("text, said", [
    # a key misspelt in one entry said only "expected 'actions:' followed by a list of
    # {name, template, motion}", the designer left to find which entry and key
    ("- {name: a, template: a.csv, motion: laugh}\n- {name: b, template: a.csv, motoin: wink}\n",
     "actions.yaml: actions[1] (b): no 'motion' ('motoin' misspelt?); each action is {name, "
     "template, motion}"),
    ("- {name: a, template: a.csv, motion: 3}\n",
     "actions.yaml: actions[0] (a): 'motion' must be text, got 3"),
    ("- a.csv\n", "actions.yaml: actions[0]: expected a mapping, got 'a.csv'"),
    # PyYAML's four lines (its message, the line quoted, a caret) in one line with its place
    ("- name: a\n  template: a.csv\n  motion laugh: x: y\n",
     "actions.yaml: cannot read the action library: YAML syntax error at line 4, column 18: "
     "mapping values "),
    ("- name: a\n  template: a.csv\n  motion: laugh\n  motion: wink\n",
     "YAML syntax error at line 5, column 3: key 'motion' is given twice"),
])
def test_a_library_file_edited_by_hand_names_the_entry_and_key(tmp_path, text, said):
    lib = tmp_path / "lib"
    (lib / "face").mkdir(parents=True)
    (lib / "face" / "a.csv").write_text((EXAMPLES / "mop/gestures/line.csv").read_text())
    (lib / "face" / "actions.yaml").write_text("actions:\n" + text)
    engine = build(designer_config(tmp_path), tmp_path)
    (problem,) = engine.library_problems["face"]
    assert said in problem and "\n" not in problem, problem
    assert set(engine.puppets["face"].actions) == {"circle"}     # the config's, started


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
    assert "face/actions.yaml: action 'a'" in problem \
        and "no channel named after a blendshape" in problem
    assert set(engine.puppets["face"].actions) == {"circle"}

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


def test_a_library_entry_on_the_samples_of_another_action_is_skipped_naming_both(tmp_path):
    """An entry edited by hand onto the config's circle.csv (or a copy of another entry's
    template) is reported and skipped, at start and when the studio reloads: loaded, the
    follower took it and the configured circle as one and it never played, without a word
    (measured: a circle performed, 121 ticks: the configured circle drove 86, 'round' none),
    as the config's own twins are refused (mop_files.twin_of)."""
    lib = tmp_path / "lib"
    (lib / "face").mkdir(parents=True)
    circle = EXAMPLES / "mop/gestures/circle.csv"
    (lib / "face" / "mine.csv").write_text((EXAMPLES / "mop/gestures/line.csv").read_text())
    (lib / "face" / "copy.csv").write_text((EXAMPLES / "mop/gestures/line.csv").read_text())
    (lib / "face" / "actions.yaml").write_text(
        f"actions:\n- {{name: round, template: {circle}, motion: laugh}}\n"
        "- {name: mine, template: mine.csv, motion: wink}\n"
        "- {name: again, template: copy.csv, motion: angry}\n")
    engine = build(designer_config(tmp_path), tmp_path)
    problems = engine.library_problems["face"]
    assert len(problems) == 2, problems
    assert "action 'round': the same template as action 'circle'" in problems[0] \
        and str(circle) in problems[0]
    assert "action 'again'" in problems[1] and "copy.csv holds the same samples as the " \
        "template of action 'mine'" in problems[1]
    assert set(engine.puppets["face"].actions) == {"circle", "mine"}
    table = StudioTable(engine, lib, focus="mop/face")
    table.rest(1.0)
    driven = [ch["face"].valid and ch["face"].action == "circle"
              for _, ch in table.perform("circle")]
    assert sum(driven) >= 60, sum(driven)         # (86 measured, as with the entry loaded)
    kept, again = engine.library_actions("face")           # as the studio reloads it
    assert [a.name for a, _ in kept] == ["mine"] and again == problems
