"""The follower window of a MOP character stepped in the studio (+/-): shown on the status line,
its followers rebuilt, saved with the character and read at the next start (the MOP paper's
Evaluation: the user "might need to adjust the window size")."""

import numpy as np
import yaml

from tabletop.plugins.mop_table import EXAMPLES, build, designer_config
from tabletop.studio.mop_table import StudioTable
from tests.studio.mop_table import kept_line


def _window(engine, performer: str = "hand") -> int:
    """The window the performer's follower runs with (its forward pass's half width)."""
    return engine._followers[performer].forward.half_window


def _two_performers() -> dict:
    """ann's puck 1 drives the face's circle, bob's puck 2 the lizard's line."""
    gestures = EXAMPLES / "mop" / "gestures"
    return {"sources": [{"kind": "scripted"}], "engines": [{
        "kind": "mop", "library": "lib",
        "performers": [{"name": "ann", "inputs": [{"kind": "puck", "id": 1}]},
                       {"name": "bob", "inputs": [{"kind": "puck", "id": 2}]}],
        "characters": [
            {"name": "face", "kind": "face", "performer": "ann", "actions": [
                {"name": "circle", "template": str(gestures / "circle.csv"), "motion": "talk"}]},
            {"name": "lizard", "kind": "creature", "performer": "bob", "actions": [
                {"name": "line", "template": str(gestures / "line.csv"), "motion": "curl"}]}]}]}


def test_plus_and_minus_step_the_window_rebuild_the_followers_and_save_it(tmp_path):
    engine = build(designer_config(tmp_path), tmp_path)
    table = StudioTable(engine, tmp_path / "lib")
    table.rest(0.2)
    assert "window 15 shared with lizard (+/-)" in table.status and _window(engine) == 15
    table.tick(["designer.window:+"])
    assert "face: window 20 states, shared with lizard, saved in" in table.status, table.status
    assert _window(engine) == 20
    saved = yaml.safe_load((tmp_path / "lib" / "face" / "actions.yaml").read_text())
    assert saved == {"actions": [], "window": 20}
    for _ in range(5):
        table.tick(["designer.window:-"])
    assert "window 1 states (its limit)" in table.status and _window(engine) == 1
    table.tick(["designer.window:+"])
    table.rest(6.0)                              # the message gone: the idle line shows it
    assert "window 6 shared with lizard (+/-)" in table.status, table.status
    # the next start reads it; a keep writes the entries and keeps the window
    again = build(designer_config(tmp_path), tmp_path)
    assert _window(again) == 6
    _, kept = kept_line(tmp_path)
    saved = yaml.safe_load((tmp_path / "lib" / "face" / "actions.yaml").read_text())
    assert saved["window"] == 6 and [a["name"] for a in saved["actions"]] == ["take1"]
    # the window decides what is followed: a circle played at twice its speed is never
    # valid with 1 state (0 of 60 ticks), with 15 states 41-48 of them
    for w, share in ((1, (0.0, 0.0)), (15, (0.5, 1.0))):
        engine.set_window("face", w)
        table.rest(1.0)
        run = table.perform("circle", speed=lambda u: 2.0)
        valid = np.mean([c["face"].valid and c["face"].action == "circle" for _, c in run])
        assert share[0] <= valid <= share[1], (w, valid)
    # the lizard steps from the window of the hand's follower it shares (15) and says so; with
    # no action yet it drives nothing, so the follower keeps the face's window
    table.tick(["designer.window:+"], focus="mop/lizard")
    assert ("lizard: window 15 states, shared with face (the largest of its characters' with "
            "actions is used; lizard's is 20), saved in") in table.status, table.status
    assert _window(engine) == 15
    engine.set_window("face", 25)
    assert _window(engine) == 25
    table.tick(["designer.window:-"], focus="mop/lizard")     # 25 - 5: the face's 25 stays
    assert ("lizard: window 25 states, shared with face (the largest of its characters' with "
            "actions is used; lizard's is 20)") in table.status, table.status
    assert _window(engine) == 25


def test_characters_of_two_performers_follow_with_their_own_windows(tmp_path):
    """The face's window changed, the lizard's not: their followers have other parameters and
    are stepped in two groups; each performer still drives its character."""
    engine = build(_two_performers(), tmp_path)
    table = StudioTable(engine, tmp_path / "lib")
    table.tick(["designer.window:+"])
    assert (_window(engine, "ann"), _window(engine, "bob")) == (20, 15)
    table.rest(1.0)
    for puck, name, who in ((1, "circle", "face"), (2, "line", "lizard")):
        run = table.perform(name, puck=puck)
        late = [c[who].valid and c[who].action == name for u, c in run if u > 0.4]
        assert np.mean(late) > 0.9, name
        table.rest(1.0)


def test_a_bad_saved_window_is_reported_and_the_configs_is_used(tmp_path):
    folder = tmp_path / "lib" / "face"
    folder.mkdir(parents=True)
    (folder / "actions.yaml").write_text("actions: []\nwindow: -3\n")
    engine = build(designer_config(tmp_path), tmp_path)
    assert _window(engine) == 15
    assert any("window: expected a whole number of states in 1..10000, got -3" in p
               for p in engine.library_problems["face"])


def test_a_window_step_rebuilds_only_the_followers_whose_window_changes(tmp_path):
    """The face's window stepped: only ann's follower is rebuilt, and once the two performers'
    followers step in groups of their own, bob's keeps following the line it is part way
    through. A window step that changes no follower's window rebuilds nothing."""
    engine = build(_two_performers(), tmp_path)
    table = StudioTable(engine, tmp_path / "lib")
    bob = engine._followers["bob"]
    table.tick(["designer.window:+"])
    assert engine._followers["bob"] is bob and _window(engine, "ann") == 20
    table.rest(1.0)
    run = table.perform("line", puck=2, upto=0.6)
    assert run[-1][1]["lizard"].valid and run[-1][1]["lizard"].progress > 0.4
    now = table.tick(["designer.window:+"])["lizard"]
    assert _window(engine, "ann") == 25 and engine._followers["bob"] is bob
    assert now.valid and now.action == "line" and now.progress > 0.4, now
    # the lizard's step rebuilds bob's follower, not ann's
    ann = engine._followers["ann"]
    table.tick(["designer.window:-"], focus="mop/lizard")
    assert engine._followers["ann"] is ann and engine._followers["bob"] is not bob
    assert _window(engine, "bob") == 10


def test_a_window_step_that_changes_no_followers_window_rebuilds_nothing(tmp_path):
    engine = build(designer_config(tmp_path), tmp_path)
    table = StudioTable(engine, tmp_path / "lib")
    hand, group = engine._followers["hand"], engine._group
    table.tick(["designer.window:+"], focus="mop/lizard")     # the lizard has no action
    assert engine._followers["hand"] is hand and engine._group is group


def test_the_start_says_which_window_it_reads_and_why_a_bad_one_is_ignored(tmp_path, caplog):
    """A saved window overrides the config's follower.window for its character: one line at
    start says so; a bad one is reported as a window (not as an action skipped)."""
    import logging
    folder = tmp_path / "lib" / "face"
    folder.mkdir(parents=True)
    (folder / "actions.yaml").write_text("actions: []\nwindow: 20\n")
    with caplog.at_level(logging.INFO, logger="tabletop"):
        build(designer_config(tmp_path), tmp_path)
    said = [r.getMessage() for r in caplog.records if "window" in r.getMessage()]
    assert said == ["MOP character 'face' follows with the window 20 saved in its actions.yaml "
                    "(the config's follower.window: 15)"], said
    caplog.clear()
    (folder / "actions.yaml").write_text("actions: []\nwindow: 0\n")
    with caplog.at_level(logging.INFO, logger="tabletop"):
        build(designer_config(tmp_path), tmp_path)
    said = [r.getMessage() for r in caplog.records if "window" in r.getMessage()]
    assert len(said) == 1 and said[0].startswith(
        "MOP saved window ignored, the config's follower.window 15 used: "), said
    assert said[0].endswith("window: expected a whole number of states in 1..10000, got 0")
