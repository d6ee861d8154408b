"""The config watcher's first look: the file as the running configuration was read from it is
not validated again (examples/mop.yaml: 20-30 ms of the frame loop's CPU in one tick at every
start); an edit saved after that read is. A changed file is validated in a worker thread, off
the frame loop's tick."""

import threading
from pathlib import Path

import yaml

from tabletop.config import load_config
from tabletop.kiosk.runner import Runner
from tabletop.kiosk.watch import ConfigWatcher

ROOT = Path(__file__).resolve().parents[2]


def config(color: list[int]) -> dict:
    return {"sources": [{"kind": "scripted", "pucks": [1, 2]}],
            "engines": [{"kind": "puppet_master", "name": "lover", "color": color,
                         "behavior": str(ROOT / "behaviors" / "library" / "lover"),
                         "main": {"puck": 1}}],
            "view": {"size": [320, 180], "headless": True},
            "kiosk": {"heartbeat": {"enabled": False}}}


def watcher(path: Path, loads: list, applied: list) -> ConfigWatcher:
    cfg = load_config(path)

    def load(p: Path) -> dict:
        loads.append(p)
        return load_config(p)
    return ConfigWatcher(path, cfg, load, applied.append, every_s=0.0, read=cfg.read)


def test_the_first_look_skips_the_file_as_it_was_read(tmp_path):
    path = tmp_path / "config.yaml"
    path.write_text(yaml.safe_dump(config([10, 20, 30])))
    loads, applied = [], []
    w = watcher(path, loads, applied)
    w()
    w()
    assert loads == [] and applied == [] and w.error is None


def test_an_edit_saved_after_the_read_is_looked_at_first(tmp_path):
    path = tmp_path / "config.yaml"
    path.write_text(yaml.safe_dump(config([10, 20, 30])))
    loads, applied = [], []
    w = watcher(path, loads, applied)
    path.write_text(yaml.safe_dump(config([200, 100, 50])))
    w()
    assert loads == [path] and [c["engines"][0]["color"] for c in applied] == [[200, 100, 50]]


def test_the_runner_hands_the_read_to_its_watcher(tmp_path, monkeypatch):
    """The config read from the watched file: its signature; the last good one a refused file
    left running (read from another file): none, the first look says the refusal."""
    path = tmp_path / "config.yaml"
    path.write_text(yaml.safe_dump(config([10, 20, 30])))
    cfg = load_config(path)
    monkeypatch.setattr(Runner, "_run_loops", lambda self, seconds: None)
    for error, first in ((None, (cfg.read,)), ("config.yaml: refused", None)):
        runner = Runner(path, cfg, headless=True, studio=True, config_error=error)
        runner.run()
        assert runner.watcher.poller.signature == first
        # validated in its worker, whose thread ended with the run
        assert runner.watcher.worker is not None
        assert not runner.watcher.worker._thread.is_alive()


def test_a_changed_file_is_validated_off_the_loop_thread(tmp_path):
    path = tmp_path / "config.yaml"
    path.write_text(yaml.safe_dump(config([10, 20, 30])))
    cfg = load_config(path)
    go, threads, applied = threading.Event(), [], []

    def load(p: Path) -> dict:
        threads.append(threading.current_thread())
        assert go.wait(10)
        return load_config(p)
    w = ConfigWatcher(path, cfg, load, applied.append, every_s=0.0, read=cfg.read,
                      background=True)
    try:
        path.write_text(yaml.safe_dump(config([200, 100, 50])))
        w()                          # returns at once, the file being validated meanwhile
        w()
        assert applied == [] and threading.current_thread() not in threads
        go.set()
        w.wait()
        assert [c["engines"][0]["color"] for c in applied] == [[200, 100, 50]]
        path.write_text("loop: {rate_hz: sixty}\n" + path.read_text())
        w()
        w.wait()
        assert w.refused == 1 and "loop.rate_hz" in w.error and len(threads) == 2
    finally:
        w.close()


def test_a_save_between_the_load_and_the_first_look_is_applied(tmp_path, monkeypatch):
    """A curator saves config.yaml while the kiosk starts: after its config was loaded, before
    the watcher's first look (the build between them takes seconds)."""
    path = tmp_path / "config.yaml"
    path.write_text(yaml.safe_dump(config([10, 20, 30])))
    cfg = load_config(path)
    path.write_text(yaml.safe_dump(config([200, 100, 50])))     # saved meanwhile
    applied = []

    def first_look(self, seconds):
        self.watcher()
        self.watcher.wait()
    monkeypatch.setattr(Runner, "_run_loops", first_look)
    monkeypatch.setattr(Runner, "_apply", lambda self, c: applied.append(c))
    Runner(path, cfg, headless=True, kiosk=True).run()
    assert [c["engines"][0]["color"] for c in applied] == [[200, 100, 50]]
