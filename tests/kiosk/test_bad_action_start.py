"""A kiosk started (a reboot, a restart) while a MOP gesture template or clip named in its config
is corrupt: the table runs, the character starts without the unreadable actions (each named in
the status's behavior_errors with its file and line) and plays the others; its recording replays
to the same characters. Outside a kiosk the same start is refused, naming the file. A corrupt
touch-pose action file is listed there too, while its library holds it."""

import json
import shutil
from pathlib import Path

import pytest
import yaml

from behaviors.mop.creatures import creature_clips
from behaviors.motion.clips import clip_to_mapping
from tabletop.frames import InputError
from tabletop.kiosk import last_good
from tabletop.kiosk.runner import Runner
from tabletop.kiosk.watch import ConfigWatcher
from tests.kiosk.running import (Latest, Ticked, kiosk_built, replay_cli, replays_alike,
                                 replays_without, running, started_without, ticked_with_edits)
from tests.kiosk.test_kiosk_lock import status
from tests.tabletop.test_replay_exact import frames
from tests.touch_pose.conftest import models  # noqa: F401  (the learned models, once)
from tracking.scenes import wait_for

GESTURES = Path(__file__).resolve().parents[2] / "examples" / "mop" / "gestures"


def _config(tmp_path: Path) -> Path:
    """A kiosk with two MOP creatures: 'walker' (a good action, a corrupt template, a corrupt
    clip) and 'lone' (its one action's template corrupt)."""
    for name in ("circle", "line", "square"):
        shutil.copy(GESTURES / f"{name}.csv", tmp_path / f"{name}.csv")
    (tmp_path / "wag.json").write_text(json.dumps(clip_to_mapping(creature_clips()["wag"]),
                                                  indent=1))
    cfg_path = tmp_path / "config.yaml"
    cfg_path.write_text(yaml.safe_dump({
        "loop": {"rate_hz": 30},
        "sources": [{"kind": "scripted", "name": "visitor", "pucks": [1]}],
        "engines": [{"kind": "mop", "name": "mop",
                     "performers": [{"name": "hand", "inputs": [{"kind": "puck", "id": 1}]}],
                     "characters": [
                         {"name": "walker", "kind": "creature", "performer": "hand",
                          "at": [0.3, 0.3], "actions": [
                              {"name": "circle", "template": "circle.csv", "motion": "walk"},
                              {"name": "line", "template": "line.csv", "motion": "curl"},
                              {"name": "square", "template": "square.csv",
                               "motion": "wag.json"}]},
                         {"name": "lone", "kind": "creature", "performer": "hand",
                          "at": [0.6, 0.3], "actions": [
                              {"name": "line", "template": "line.csv", "motion": "strike"}]}]}],
        "view": {"size": [320, 180], "headless": True},
        "kiosk": {"heartbeat": {"enabled": False}, "status_file": "status.json"},
    }))
    return cfg_path


def drawing_config(tmp_path: Path) -> tuple[Path, dict[str, str]]:
    """:func:`_config` with the visitor's puck drawing the line, and the good text of its line
    template and wag clip."""
    cfg_path = _config(tmp_path)
    shutil.copy(GESTURES / "line.csv", tmp_path / "drawn.csv")
    edited = yaml.safe_load(cfg_path.read_text())
    edited["sources"][0]["performers"] = [{"puck": 1, "home": [0.5, 0.4],
                                           "gestures": ["drawn.csv"], "speed": [1.0, 1.0]}]
    cfg_path.write_text(yaml.safe_dump(edited))
    return cfg_path, {name: (tmp_path / name).read_text() for name in ("line.csv", "wag.json")}


def _corrupt(tmp_path: Path) -> None:
    """A template with a short row (a copy cut short) and a clip cut in half."""
    with open(tmp_path / "line.csv", "a") as f:
        f.write("1e3,0.5\n")
    clip = (tmp_path / "wag.json").read_text()
    (tmp_path / "wag.json").write_text(clip[:len(clip) // 2])


def _circle_damaged(session: Path) -> Path:
    """A copy of the recording ``session`` whose carried circle template is damaged too."""
    lines = session.read_text().splitlines()
    header = json.loads(lines[0])
    key = next(k for k in header["files"] if k.endswith("circle.csv"))
    header["files"][key] = {"text": header["files"][key]["text"] + "1e3,0.5\n"}
    damaged = session.with_name("damaged.jsonl")
    damaged.write_text("\n".join([json.dumps(header)] + lines[1:]) + "\n")
    return damaged


def test_a_kiosk_starts_mop_characters_without_their_unreadable_actions(tmp_path, caplog):
    cfg_path = _config(tmp_path)
    _corrupt(tmp_path)
    session = tmp_path / "session.jsonl"
    cfg, refused = last_good.load(cfg_path, kiosk=True)    # the kiosk's start
    runner = Runner(cfg_path, cfg, headless=True, kiosk=True, record_path=session)
    inst = runner._build(runner.cfg)
    assert refused is None
    stage = inst.engines[0]
    errors = stage.start_problems
    assert len(errors) == 3
    assert any("'walker', action 'line'" in e and "line.csv: line" in e for e in errors)
    assert any("'walker', action 'square'" in e and "wag.json" in e and "line " in e
               for e in errors)
    assert any("'lone', action 'line'" in e and "line.csv: line" in e for e in errors)
    assert {n: set(t) for n, t in stage.templates.items()} == {"walker": {"circle"}, "lone": set()}
    assert sum("starts without the action" in r.getMessage() for r in caplog.records) == 3
    latest = Latest()
    inst.loop.sinks.insert(0, latest)
    with running(inst, 300, ticks=60, run_out=True):   # 2 s of a quiet machine's ticks
        assert wait_for(lambda: status(tmp_path).get("behavior_errors"), 10.0)
        listed = status(tmp_path)["behavior_errors"]
        assert listed == [f"mop: {e}" for e in errors]
        assert wait_for(lambda: {"walker", "lone"} <= {c.name for c in latest.characters}, 10.0)
    # the config watcher's first look finds the running config, not an edit to refuse; an
    # edit while the template is corrupt is refused naming it
    watcher = ConfigWatcher(cfg_path, runner.cfg, runner._load, runner._apply, every_s=0.0)
    watcher()
    assert watcher.error is None and watcher.refused == 0
    edited = yaml.safe_load(cfg_path.read_text())
    edited["loop"]["rate_hz"] = 25
    cfg_path.write_text(yaml.safe_dump(edited))
    watcher()
    assert watcher.refused == 1 and "line.csv: line" in watcher.error
    # the replay starts them without the same actions (the header's started_without)
    replays_without(session, tmp_path / "replayed.jsonl", {"mop"}, least=30, aside=())
    # a recording whose carried circle template is damaged too: refused, not replayed without
    # one more action than the run had
    done = replay_cli(_circle_damaged(session), tmp_path / "replayed-2.jsonl")
    assert done.returncode == 2, done.stderr
    last = done.stderr.strip().splitlines()[-1]
    assert last.startswith("tabletop replay: error: ") and "character 'walker': the " \
        "recording started without 'line', 'square', but this replay could not read " \
        "'circle', 'line', 'square'" in last, last


def _recorded_renamed(tmp_path: Path, names: dict[str, str]) -> Path:
    """The recording of 15 ticks (half a second quiet; ticks, not seconds: a loaded machine
    made 5 or fewer in 0.5 s) of a kiosk started on :func:`_config` corrupted, its characters and
    actions renamed (old name -> new)."""
    cfg_path = _config(tmp_path)
    text = cfg_path.read_text()
    for old, new in names.items():
        text = text.replace(f"name: {old}", f"name: {new}")
    cfg_path.write_text(text)
    _corrupt(tmp_path)
    session = tmp_path / "session.jsonl"
    kiosk_built(cfg_path, record_path=session)[0].loop.run(seconds=300, max_ticks=15)
    return session


def test_the_replay_of_a_start_without_actions_named_with_quotes_checks_them(tmp_path):
    """Names holding a quote (shown in double quotes in the start's messages) are checked as
    any: a recording whose carried circle template is damaged is refused."""
    session = _recorded_renamed(tmp_path, {"walker": "o'walker", "line": "it's line"})
    done = replay_cli(_circle_damaged(session), tmp_path / "replayed.jsonl")
    assert done.returncode == 2, done.stderr
    assert "character \"o'walker\": the recording started without \"it's line\", 'square', " \
        "but this replay could not read 'circle', \"it's line\", 'square'" in done.stderr, \
        done.stderr


def test_the_replay_of_a_start_without_actions_named_with_semicolons_reads_them(tmp_path):
    """Names holding "; " (the separator of the recorded started_without text): the replay
    starts without the same actions and replays to the same characters."""
    session = _recorded_renamed(tmp_path, {"walker": "a; walker", "square": "x; square"})
    replays_alike(session, tmp_path / "replayed.jsonl", least=5, aside=())


SEEN_S = 10.0
"""Seconds of table time a kiosk test waits for a fixed file to be followed and said in the
status: a bound, not a measure (on simulated time, the action reloader looking at every tick:
two ticks for the file to stay as it is, a status a second)."""


def test_a_kiosk_follows_a_mop_action_it_started_without_once_its_file_is_fixed(tmp_path):
    """The technician replaces the corrupt template, then the corrupt clip: within seconds,
    without a restart, each character follows the actions they complete (the lone creature
    one, the walker all three), the status's behavior_errors empty out, and the recording
    replays to the same characters, the actions followed from the same frame. On simulated
    time (in real time it waited 10 s for its looks and gestures)."""
    from tabletop.kiosk.simulate import SimClock
    cfg_path, good = drawing_config(tmp_path)
    _corrupt(tmp_path)
    session = tmp_path / "session.jsonl"
    clock = SimClock()
    inst, _ = kiosk_built(cfg_path, clock=clock, record_path=session)
    stage = inst.engines[0]
    latest = Latest()
    inst.loop.sinks.insert(0, latest)
    with Ticked(inst, clock) as table:
        assert table.until(lambda: len(status(tmp_path).get("behavior_errors", ())) == 3,
                           SEEN_S)
        # a copy still bad, otherwise: the entries say the new reason
        (tmp_path / "line.csv").write_text(good["line.csv"] + "0.5,x,0\n")
        assert table.until(lambda: sum("line.csv: line 48: " in e and "'x'" in e for e in status(
            tmp_path).get("behavior_errors", ())) == 2, SEEN_S), status(tmp_path)
        (tmp_path / "line.csv").write_text(good["line.csv"])
        assert table.until(lambda: len(status(tmp_path).get("behavior_errors", ())) == 1,
                           SEEN_S)
        (error,) = status(tmp_path)["behavior_errors"]
        assert "'walker', action 'square'" in error and "wag.json" in error
        assert {n: set(t) for n, t in stage.templates.items()} == {
            "walker": {"circle", "line"}, "lone": {"line"}}
        (tmp_path / "wag.json").write_text(good["wag.json"])
        assert table.until(lambda: status(tmp_path).get("behavior_errors") == [], SEEN_S)
        assert set(stage.templates["walker"]) == {"circle", "line", "square"}
        assert set(stage.puppets["walker"].actions) == {"circle", "line", "square"}
        # the line drawn drives both characters' line action
        assert table.until(lambda: {"walker", "lone"} <= {c.name for c in latest.characters
                                                          if c.action == "line"}, 20.0)
    assert started_without(session) == {"mop"}
    followed = [f["consumed"]["reload"]["actions"]["mop"] for f in frames(session)
                if "actions" in f.get("consumed", {}).get("reload", {})]
    assert [[(e["character"], e["action"]) for e in f] for f in followed] == [
        [("walker", "line"), ("lone", "line")], [("walker", "square")]]
    replays_alike(session, tmp_path / "replayed.jsonl", least=30, aside=())


def test_outside_a_kiosk_a_corrupt_mop_template_stops_the_start_naming_the_file(tmp_path):
    cfg_path = _config(tmp_path)
    _corrupt(tmp_path)
    with pytest.raises(InputError, match=r"actions\[1\].template: .*line.csv: line"):
        last_good.load(cfg_path, kiosk=False)


def _pose_kiosk(tmp_path: Path, name: str) -> tuple[Path, Path]:
    """A kiosk's config with one touch-pose character whose library's action ``name`` is a
    file cut short: (that file, the config)."""
    bad = tmp_path / "pose_actions" / name / "action.json"
    bad.parent.mkdir(parents=True)
    bad.write_text('{\n  "format": "tabletop.pose_action",\n  "part": ')
    cfg_path = tmp_path / "config.yaml"
    cfg_path.write_text(yaml.safe_dump({
        "loop": {"rate_hz": 30},
        "sources": [{"kind": "scripted", "name": "visitor", "pucks": []}],
        "engines": [{"kind": "touch_pose", "name": "poser", "physics": False,
                     "mouse": False}],
        "view": {"size": [320, 180], "headless": True},
        "kiosk": {"heartbeat": {"enabled": False}, "status_file": "status.json"},
    }))
    return bad, cfg_path


def test_a_kiosk_lists_a_corrupt_touch_pose_action_until_it_is_gone(tmp_path, models):
    """A touch-pose character starts without an action file cut short (in a kiosk or not, as
    the others load); the kiosk's status lists it with its file and line in behavior_errors, its
    recording's header in started_without, until the folder no longer holds it."""
    bad, cfg_path = _pose_kiosk(tmp_path, "wave")
    session = tmp_path / "session.jsonl"
    inst, _ = kiosk_built(cfg_path, record_path=session)
    with running(inst, 30):
        assert wait_for(lambda: status(tmp_path).get("behavior_errors"), 10.0)
        (error,) = status(tmp_path)["behavior_errors"]
        assert error.startswith(f"poser: {bad}: cannot read the action") and "line 3" in error
        shutil.rmtree(bad.parent)
        assert wait_for(lambda: status(tmp_path).get("behavior_errors") == [], 15.0)
    assert started_without(session) == {"poser"}


def test_a_kiosk_knows_a_touch_pose_action_once_its_file_is_fixed(tmp_path, models):
    """The corrupt touch-pose action file replaced by a good one: the character knows the
    action within seconds, without a restart, and the status no longer lists it."""
    import numpy as np

    from behaviors.touch_pose.designed import to_json
    from behaviors.touch_pose.humanoid import Pose
    bad, cfg_path = _pose_kiosk(tmp_path, "greet")
    inst, _ = kiosk_built(cfg_path)
    core = inst.engines[0].core
    with running(inst, 30):
        assert wait_for(lambda: status(tmp_path).get("behavior_errors"), 10.0)
        assert "greet" not in {a.name for a in core.m.actions}
        rots = np.tile([1.0, 0.0, 0.0, 0.0], (len(core.body.names), 1))
        poses = [Pose(np.array([0.3 * k / 40, 0.0, 0.9]), rots) for k in range(40)]
        bad.write_text(to_json("greet", "pelvis", np.linspace(0.0, 2.0, 40), poses))
        assert wait_for(lambda: status(tmp_path).get("behavior_errors") == [], 15.0)
        assert "greet" in {a.name for a in core.m.actions}


def test_a_part_that_starts_after_a_fix_replays_on_its_own_with_the_action(tmp_path):
    """A kiosk recording in parts (recorder.max_mb) that follows a fixed template mid-run: a
    later part's header carries what the session read by then (``reloaded``), so the part
    replayed alone follows the action, as the live run did (its header's files are the
    start's: without it the part's replay played no line at all)."""
    from tabletop.kiosk.simulate import SimClock
    cfg_path = _config(tmp_path)
    shutil.copy(GESTURES / "line.csv", tmp_path / "drawn.csv")
    edited = yaml.safe_load(cfg_path.read_text())     # the visitor's puck draws the line
    edited["sources"][0]["performers"] = [{"puck": 1, "home": [0.5, 0.4],
                                           "gestures": ["drawn.csv"], "speed": [1.0, 1.0]}]
    edited["recorder"] = {"enabled": True, "folder": "s", "max_mb": 0.1}
    cfg_path.write_text(yaml.safe_dump(edited))
    good = (tmp_path / "line.csv").read_text()
    _corrupt(tmp_path)
    clock = SimClock()
    inst, _ = kiosk_built(cfg_path, clock=clock)
    ticked_with_edits(inst, clock, 150, {20: (tmp_path / "line.csv", good)})
    parts = inst.recorder.paths
    assert len(parts) >= 3
    later = parts[1]           # (the first part holds the frame that followed the fix)
    assert "reloaded" not in json.loads(parts[0].read_text().splitlines()[0])
    reloaded = json.loads(later.read_text().splitlines()[0])["reloaded"]
    assert [(e["character"], e["action"]) for e in reloaded["actions"]["mop"]] == [
        ("walker", "line"), ("lone", "line")]
    live = frames(later)
    assert {"walker", "lone"} <= {c["name"] for f in live for c in f["characters"]
                                  if c.get("action") == "line"}
    done = replay_cli(later, tmp_path / "replayed.jsonl")
    assert done.returncode == 0, done.stderr
    again = frames(tmp_path / "replayed.jsonl")
    assert len(again) == len(live)

    # the part begins while the puck rests before its next line: its header carries where
    # the performer's gesture started and that it rests (``performers``), so the part alone
    # starts the line on the same sample, the characters alike to the last digit (a performer
    # started afresh did not rest yet and drew the line's onset a frame early)
    assert json.loads(later.read_text().splitlines()[0])["performers"]["mop"]["hand"][0][-1] == 1
    assert [f["characters"] for f in live] == [f["characters"] for f in again]

    # the --out file is the first part of its own session: it carries the performers' states
    # the part started from, so it replays to the same characters too
    done = replay_cli(tmp_path / "replayed.jsonl", tmp_path / "twice.jsonl")
    assert done.returncode == 0, done.stderr
    assert [f["characters"] for f in live] == [
        f["characters"] for f in frames(tmp_path / "twice.jsonl")]
