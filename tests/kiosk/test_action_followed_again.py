"""A kiosk follows its MOP actions' files for its whole run (tabletop.kiosk.actions): an action
it started without, followed once fixed, is followed again when its template is replaced later
(recorded, so the replay follows it from the same frame), and a template or clip broken while
its action plays is listed in the status's behavior_errors while the characters play the action
as read before, until it is fixed."""

import base64

import numpy as np

from tabletop.kiosk.simulate import SimClock
from tabletop.plugins.mop_files import load_template
from tests.kiosk.running import (Latest, Ticked, kiosk_built, replays_alike,
                                 ticked_with_edits)
from tests.kiosk.test_bad_action_start import _corrupt, drawing_config
from tests.kiosk.test_kiosk_lock import status
from tests.tabletop.test_replay_exact import frames


def _scaled(text: str, k: float) -> str:
    """The template ``text`` (``t,dx,dy``) drawn ``k`` times as large: another valid line."""
    rows = text.splitlines()
    out = [rows[0]] + [",".join([r.split(",")[0]] + [repr(float(v) * k) for v in r.split(",")[1:]])
                       for r in rows[1:] if r]
    return "\n".join(out) + "\n"


def test_a_fixed_action_is_followed_again_when_its_template_is_replaced_later(tmp_path):
    cfg_path, good = drawing_config(tmp_path)
    _corrupt(tmp_path)
    session = tmp_path / "session.jsonl"
    clock = SimClock()
    inst, _ = kiosk_built(cfg_path, clock=clock, record_path=session)
    stage = inst.engines[0]
    larger = _scaled(good["line.csv"], 1.5)
    ticked_with_edits(inst, clock, 200, {20: (tmp_path / "line.csv", good["line.csv"]),  # the fix
                                         100: (tmp_path / "line.csv", larger)})  # weeks later
    whole = load_template(tmp_path / "line.csv", ("dx", "dy"), stage.rate_hz)
    for name in ("walker", "lone"):
        assert np.array_equal(stage.templates[name]["line"][1], whole), name
    recorded = [(f["seq"], e) for f in frames(session)
                for e in f.get("consumed", {}).get("reload", {}).get("actions", {}).get("mop", [])]
    read = [(e["character"], e["action"], base64.b64decode(e["files"][0]).decode())
            for _, e in recorded]
    assert read == [("walker", "line", good["line.csv"]), ("lone", "line", good["line.csv"]),
                    ("walker", "line", larger), ("lone", "line", larger)]
    assert recorded[0][0] == recorded[1][0] < recorded[2][0] == recorded[3][0]
    assert stage.start_problems == [e for e in stage.start_problems if "square" in e]
    replays_alike(session, tmp_path / "replayed.jsonl", least=150, aside=())


def test_a_template_and_a_clip_broken_while_their_actions_play_are_listed_and_play_on(tmp_path):
    """The line template deleted and the wag clip made a folder while the characters play:
    both listed in behavior_errors (each with its file and why), the characters go on playing
    the line as read at the start, nothing stops; the template put back drops its entry. On
    simulated time (its waits are table seconds)."""
    cfg_path, good = drawing_config(tmp_path)
    session = tmp_path / "session.jsonl"
    clock = SimClock()
    inst, refused = kiosk_built(cfg_path, clock=clock, record_path=session)
    assert refused is None
    stage = inst.engines[0]
    latest = Latest()
    inst.loop.sinks.insert(0, latest)

    def playing_line() -> bool:
        return {"walker", "lone"} <= {c.name for c in latest.characters if c.action == "line"}

    def errors() -> list:
        return status(tmp_path).get("behavior_errors", [])
    with Ticked(inst, clock) as table:
        assert table.until(playing_line, 20.0)
        assert table.until(lambda: "behavior_errors" in status(tmp_path), 2.0)
        assert errors() == []
        (tmp_path / "line.csv").unlink()
        (tmp_path / "wag.json").unlink()
        (tmp_path / "wag.json").mkdir()
        assert table.until(lambda: len(errors()) == 3, 10.0), status(tmp_path)
        listed = errors()
        assert all("\n" not in e for e in listed)
        assert sum(e.startswith("mop: character") and "action 'line'" in e and "line.csv" in e
                   and "not found" in e for e in listed) == 2, listed
        assert any("'walker', action 'square'" in e and "wag.json" in e and "folder" in e
                   for e in listed), listed
        assert table.until(lambda: not playing_line(), 20.0)        # the gesture's end
        assert table.until(playing_line, 20.0)                       # and the next one, as read
        assert {n: set(t) for n, t in stage.templates.items()} == {
            "walker": {"circle", "line", "square"}, "lone": {"line"}}
        (tmp_path / "line.csv").write_text(good["line.csv"])
        assert table.until(lambda: len(errors()) == 1, 10.0), status(tmp_path)
        assert "wag.json" in errors()[0]
        (tmp_path / "wag.json").rmdir()
        (tmp_path / "wag.json").write_text(good["wag.json"])
        assert table.until(lambda: errors() == [], 10.0), status(tmp_path)
        assert table.until(playing_line, 20.0)
    assert not sum(inst.loop.stats.errors.values())
    replays_alike(session, tmp_path / "replayed.jsonl", least=30, aside=())


def test_a_part_header_carries_each_action_as_last_read():
    """A later part's ``reloaded`` holds each action's latest read once (a kiosk replacing a
    template every day for weeks would otherwise carry every copy in every part's header)."""
    from tabletop.parts import carried
    first = {"actions": {"mop": [{"character": "lone", "action": "line", "files": ["YQ=="]},
                                 {"character": "walker", "action": "line", "files": ["YQ=="]}]}}
    later = {"actions": {"mop": [{"character": "lone", "action": "line", "files": ["Yg=="]}]}}
    state = carried(carried({}, first), later)
    assert state["actions"]["mop"] == [
        {"character": "walker", "action": "line", "files": ["YQ=="]},
        {"character": "lone", "action": "line", "files": ["Yg=="]}]
