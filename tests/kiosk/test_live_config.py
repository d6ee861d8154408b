"""Editing config.yaml while the table runs: a bad edit is refused (the running configuration
stays and keeps running), a good one is applied."""

import threading
from pathlib import Path

import yaml

from tabletop.config import load_config
from tabletop.frames import Frame
from tabletop.kiosk.runner import Runner
from tests.tracking.scenes import wait_for

ROOT = Path(__file__).resolve().parents[2]


def config(color) -> dict:
    return {
        "loop": {"rate_hz": 30},
        "sources": [{"kind": "scripted", "pucks": [1, 2]}],
        "engines": [{"kind": "puppet_master", "name": "lover", "color": color,
                     "behavior": str(ROOT / "behaviors" / "library" / "lover"), "main": {"puck": 1}}],
        "view": {"size": [320, 180], "headless": True},
        "kiosk": {"heartbeat": {"enabled": False}},
    }


def write(path: Path, text: str) -> None:
    tmp = path.with_suffix(".tmp")
    tmp.write_text(text)
    tmp.replace(path)


def test_bad_edit_refused_good_edit_applied(tmp_path):
    path = tmp_path / "config.yaml"
    path.write_text(yaml.safe_dump(config([10, 20, 30])))
    runner = Runner(path, load_config(path), headless=True, kiosk=True)
    th = threading.Thread(target=runner.run)
    th.start()
    try:
        assert wait_for(lambda: runner.inst is not None and runner.inst.loop.stats.ticks > 5, 15)
        first = runner.inst
        bad = config([10, 20, 30])
        bad["engines"][0]["colour"] = [1, 2, 3]
        write(path, yaml.safe_dump(bad))
        assert wait_for(lambda: runner.watcher.refused == 1, 15)
        assert "engines[0].colour: unknown key" in runner.watcher.error
        ticks = first.loop.stats.ticks
        assert wait_for(lambda: first.loop.stats.ticks > ticks + 10, 15)   # still running
        assert runner.inst is first and runner.watcher.applied == 0
        status = runner.reporter.status(Frame(seq=0, t=0.0))
        assert "colour: unknown key" in status["config_error"]
        view = next(s for s in first.loop.sinks if s.name == "view")
        assert any("config refused" in n and "colour" in n for fn in view.notices for n in fn())
        write(path, "engines: [{kind: puppet_master\n")            # not even YAML
        assert wait_for(lambda: runner.watcher.refused == 2, 15)
        assert "config.yaml" in runner.watcher.error and runner.inst is first
        ticks = first.loop.stats.ticks
        assert wait_for(lambda: first.loop.stats.ticks > ticks + 10, 15)   # still running
        write(path, yaml.safe_dump(config([200, 100, 50])))
        assert wait_for(lambda: runner.inst is not first and runner.inst.loop.stats.ticks > 5, 15)
        assert runner.watcher.error is None and runner.watcher.applied == 1
        assert runner.inst.engines[0].color == (200, 100, 50)
        assert first.loop.stop.is_set()                     # the old one was closed
    finally:
        runner.stop.set()
        th.join(20)
    assert not th.is_alive()

