"""A kiosk started (a reboot, a restart) while a behaviour folder holds a corrupt file: the table
runs, the character waits without its behaviour, the status names the file, and fixing the file
on disk plays it; its recording replays to the same characters. Outside a kiosk the same start
is refused, naming the file."""

import json
import shutil
from pathlib import Path

import pytest
import yaml

from tabletop.config import load_config
from tabletop.frames import InputError
from tabletop.kiosk.runner import Runner
from tests.kiosk.running import Latest, replays_alike, running
from tests.kiosk.test_kiosk_lock import status
from tracking.scenes import wait_for

LOVER = Path(__file__).resolve().parents[2] / "behaviors" / "library" / "lover"


def _config(tmp_path: Path) -> Path:
    shutil.copytree(LOVER, tmp_path / "lover")
    cfg_path = tmp_path / "config.yaml"
    cfg_path.write_text(yaml.safe_dump({
        "loop": {"rate_hz": 30},
        "sources": [{"kind": "scripted", "name": "visitor", "pucks": [1]}],
        "engines": [{"kind": "puppet_master", "name": "lover", "behavior": "lover",
                     "main": {"puck": 1}}],
        "view": {"size": [320, 180], "headless": True},
        "kiosk": {"heartbeat": {"enabled": False}, "status_file": "status.json"},
    }))
    return cfg_path


def _corrupt(folder: Path) -> str:
    """Append a short row to the demonstration, as a copy cut short leaves it; its text."""
    good = (folder / "demonstration.csv").read_text()
    with open(folder / "demonstration.csv", "a") as f:
        f.write("1e3,0.5,0.5\n")
    return good


def test_a_kiosk_starts_without_a_corrupt_behaviour_and_plays_it_once_fixed(tmp_path, caplog):
    cfg_path = _config(tmp_path)
    good = _corrupt(tmp_path / "lover")
    session = tmp_path / "session.jsonl"
    runner = Runner(cfg_path, load_config(cfg_path), headless=True, kiosk=True,
                    record_path=session)
    inst = runner._build(runner.cfg)
    engine = inst.engines[0]
    assert engine.reactor is None and "demonstration.csv" in engine.note
    assert any("lover starts without its behaviour" in r.getMessage()
               and "demonstration.csv: line" in r.getMessage() for r in caplog.records)
    latest = Latest()
    inst.loop.sinks.insert(0, latest)
    with running(inst, 30):
        assert wait_for(lambda: status(tmp_path).get("behavior_errors"), 10.0)
        (error,) = status(tmp_path)["behavior_errors"]
        assert error.startswith("lover: ") and "demonstration.csv: line" in error
        (tmp_path / "lover" / "demonstration.csv").write_text(good)
        assert wait_for(lambda: engine.reactor is not None, 20.0)
        assert wait_for(lambda: status(tmp_path).get("behavior_errors") == [], 10.0)
        assert wait_for(lambda: any(c.valid for c in latest.characters), 10.0)
    # the replay starts the character without its behaviour too (the header's started_without)
    # and trains the fixed folder in the frame the live run did
    live = replays_alike(session, tmp_path / "replayed.jsonl")
    assert not live[0]["characters"][0]["valid"] and live[-1]["characters"][0]["valid"]
    # a recording carrying the folder readable (completed after the start read it) replays as
    # the run went too: without the behaviour until the recorded reload
    lines = session.read_text().splitlines()
    header = json.loads(lines[0])
    key = next(k for k in header["files"] if k.endswith("demonstration.csv"))
    header["files"][key] = {"text": good}
    readable = tmp_path / "readable.jsonl"
    readable.write_text("\n".join([json.dumps(header)] + lines[1:]) + "\n")
    assert replays_alike(readable, tmp_path / "replayed-2.jsonl") == live


def test_a_kiosk_start_in_designer_mode_lists_the_corrupt_behaviour_until_fixed(tmp_path):
    """The character driven by the studio (designer mode) starts without its behaviour as
    outside it, and the status's behavior_errors names the file, a take tried meanwhile
    included, until the fixed folder plays; the recording replays to the same characters."""
    cfg_path = _config(tmp_path)
    cfg = yaml.safe_load(cfg_path.read_text())
    cfg["engines"][0]["designer"] = {"enabled": True, "main_puck": 1, "react_puck": 2,
                                     "library": "lib", "min_seconds": 0.5}
    cfg["studio"] = {"countdown_s": 0.1, "review": False}
    cfg["sources"][0]["pucks"] = [1, 2]
    cfg_path.write_text(yaml.safe_dump(cfg))
    good = _corrupt(tmp_path / "lover")
    session = tmp_path / "session.jsonl"
    runner = Runner(cfg_path, load_config(cfg_path), headless=True, kiosk=True,
                    record_path=session)
    inst = runner._build(runner.cfg)
    engine, studio = inst.engines[0], runner.studio
    assert engine.reactor is None and studio is not None
    with running(inst, 40):
        assert wait_for(lambda: status(tmp_path).get("behavior_errors"), 10.0)
        (error,) = status(tmp_path)["behavior_errors"]
        assert error.startswith("lover: ") and "demonstration.csv: line" in error
        inst.loop.commands.put("designer.record")
        assert wait_for(lambda: studio.state == "recording" and studio.target.seconds() > 2.0,
                        20.0)
        inst.loop.commands.put("designer.record")
        assert wait_for(lambda: studio.state == "trying", 20.0)
        assert wait_for(lambda: status(tmp_path)["studio"]["state"] == "trying", 10.0)
        assert len(status(tmp_path)["behavior_errors"]) == 1     # the take is not the fix
        inst.loop.commands.put("designer.discard")
        assert wait_for(lambda: studio.state == "idle", 10.0)
        (tmp_path / "lover" / "demonstration.csv").write_text(good)
        assert wait_for(lambda: engine.reactor is not None, 20.0)
        assert wait_for(lambda: status(tmp_path).get("behavior_errors") == [], 10.0)
    live = replays_alike(session, tmp_path / "replayed.jsonl")
    lover = [c for f in live for c in f["characters"] if c["name"] == "lover"]
    assert not lover[0]["valid"] and lover[-1]["valid"]


def test_outside_a_kiosk_a_corrupt_behaviour_stops_the_start_naming_the_file(tmp_path):
    cfg_path = _config(tmp_path)
    _corrupt(tmp_path / "lover")
    runner = Runner(cfg_path, load_config(cfg_path), headless=True, kiosk=False, strict=True)
    with pytest.raises(InputError, match="demonstration.csv: line"):
        runner._build(runner.cfg)
