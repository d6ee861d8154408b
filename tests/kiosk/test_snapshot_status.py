"""A kiosk whose snapshots cannot be written (a full disk, the folder taken away) says so in its
status and heartbeat, not only in a log line, and says when they are written again."""

import json
import threading
from pathlib import Path

import yaml

from tabletop.config import load_config
from tabletop.kiosk.runner import Runner
from tracking.scenes import wait_for


def _snapshots(path: Path) -> dict | None:
    try:
        return json.loads(path.read_text()).get("snapshots", "missing")
    except (OSError, ValueError):
        return "missing"


def _snap(path: Path) -> dict:
    """The status's snapshots field, {} while there is none."""
    s = _snapshots(path)
    return s if isinstance(s, dict) else {}


def test_snapshots_that_fail_are_in_the_status_until_they_are_saved_again(tmp_path):
    cfg_path = tmp_path / "config.yaml"
    cfg_path.write_text(yaml.safe_dump({
        "loop": {"rate_hz": 30},
        "sources": [{"kind": "scripted", "name": "visitor", "pucks": [1]}],
        "view": {"size": [160, 90], "headless": True, "snapshot_every_s": 0.2,
                 "snapshot_folder": "snaps"},
        "kiosk": {"heartbeat": {"enabled": False}, "status_file": "status.json"},
    }))
    runner = Runner(cfg_path, load_config(cfg_path), headless=True, kiosk=True)
    inst = runner._build(runner.cfg)
    status, snaps = tmp_path / "status.json", tmp_path / "snaps"
    th = threading.Thread(target=inst.loop.run, kwargs={"seconds": 60})
    th.start()
    try:
        assert wait_for(lambda: _snap(status).get("last"), 20.0)
        first = _snap(status)
        assert first["folder"] == str(snaps) and first["failed"] is None
        # taken away (moved in one rename: removed file by file, it raced the snapshot writer
        # making its next file in it, "Directory not empty"), a file where the folder was
        snaps.rename(tmp_path / "taken")
        snaps.write_text("not a folder")
        assert wait_for(lambda: _snap(status).get("failed"), 20.0)
        failed = _snap(status)["failed"]
        assert failed.startswith(str(snaps / "snapshot-")) and ": " in failed
        snaps.unlink()
        snaps.mkdir()
        assert wait_for(lambda: (s := _snap(status)) and s["failed"] is None
                        and s["last"] != first["last"], 20.0)
    finally:
        inst.loop.stop.set()
        th.join(10)


def test_a_kiosk_without_snapshots_says_null(tmp_path):
    cfg_path = tmp_path / "config.yaml"
    cfg_path.write_text(yaml.safe_dump({
        "sources": [{"kind": "scripted", "name": "visitor", "pucks": [1]}],
        "view": {"size": [160, 90], "headless": True},
        "kiosk": {"heartbeat": {"enabled": False}, "status_file": "status.json"},
    }))
    runner = Runner(cfg_path, load_config(cfg_path), headless=True, kiosk=True)
    inst = runner._build(runner.cfg)
    th = threading.Thread(target=inst.loop.run, kwargs={"seconds": 30})
    th.start()
    try:
        assert wait_for(lambda: _snapshots(tmp_path / "status.json") != "missing", 20.0)
        assert _snapshots(tmp_path / "status.json") is None
    finally:
        inst.loop.stop.set()
        th.join(10)
