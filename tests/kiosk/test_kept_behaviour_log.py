"""A config edit applied while a behaviour file is bad, its character playing on with the
behaviour read before: the log says so in one line naming the file, not also that the character
starts without its behaviour (two lines, the first untrue)."""

import logging
import shutil

import yaml

from tabletop.config import load_config
from tabletop.kiosk.runner import Runner
from tests.kiosk.test_supervisor import ROOT


def test_a_kept_behaviour_is_logged_once_as_kept(tmp_path, caplog):
    shutil.copytree(ROOT / "behaviors" / "library" / "lover", tmp_path / "lover")
    path = tmp_path / "config.yaml"
    path.write_text(yaml.safe_dump({
        "loop": {"rate_hz": 30},
        "sources": [{"kind": "scripted", "pucks": [1]}],
        "engines": [{"kind": "puppet_master", "name": "lover", "behavior": "lover",
                     "main": {"puck": 1}}],
        "view": {"size": [320, 180], "headless": True},
        "kiosk": {"heartbeat": {"enabled": False}}}))
    runner = Runner(path, load_config(path), headless=True, kiosk=True)
    runner.inst = runner._build(runner.cfg)
    played = runner.inst.engines[0].behavior
    with open(tmp_path / "lover" / "demonstration.csv", "a") as f:
        f.write("1e3,0.5,0.5\n")                          # a short row: a copy cut short
    runner._drop()
    caplog.clear()
    with caplog.at_level(logging.INFO, logger="tabletop"):
        inst = runner._build(runner.cfg)
    assert inst.engines[0].behavior is played
    said = [r.getMessage() for r in caplog.records if "demonstration.csv" in r.getMessage()]
    assert len(said) == 1 and "lover plays on with the behaviour read before" in said[0], said
    # a start (nothing played before) says the character starts without it
    runner._playing = {}
    caplog.clear()
    with caplog.at_level(logging.INFO, logger="tabletop"):
        assert runner._build(runner.cfg).engines[0].behavior is None
    assert any("lover starts without its behaviour" in r.getMessage() for r in caplog.records)
