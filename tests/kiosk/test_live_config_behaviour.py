"""Editing config.yaml while a Puppet Master behaviour file on disk is bad: the edit applies and
the character plays on with the behaviour read before (tests/kiosk/test_live_config.py edits
configs whose files read)."""

import shutil

import yaml

from tabletop.config import load_config
from tabletop.frames import Frame
from tabletop.kiosk.runner import Runner
from tests.kiosk.running import replays_without
from tests.kiosk.test_live_config import ROOT, config, rebuilt, running, write
from tracking.scenes import wait_for


def test_an_edit_applies_while_a_behaviour_file_is_bad_and_the_behaviour_plays_on(tmp_path):
    """A behaviour file that went bad mid-run refused every unrelated edit under a kiosk (and
    the log blamed the new config); the edit applies, and the character plays on with the
    behaviour read before (not dropped from the table), the status saying the new file is
    refused; the rebuilt installation's recording replays to the same characters."""
    lover = tmp_path / "lover"
    shutil.copytree(ROOT / "behaviors" / "library" / "lover", lover)
    path = tmp_path / "config.yaml"

    def edit(color, rate_hz=None) -> str:
        cfg = config(color)
        cfg["engines"][0]["behavior"] = "lover"
        if rate_hz is not None:
            cfg["engines"][0]["rate_hz"] = rate_hz
        return yaml.safe_dump(cfg)
    path.write_text(edit([10, 20, 30]))
    session = tmp_path / "session.jsonl"
    with running(Runner(path, load_config(path), headless=True, kiosk=True,
                        record_path=session)) as runner:
        first = runner.inst
        played = first.engines[0].behavior
        assert played is not None
        good = (lover / "demonstration.csv").read_text()
        with open(lover / "demonstration.csv", "a") as f:
            f.write("1e3,0.5,0.5\n")                     # a short row: a copy cut short
        write(path, edit([200, 100, 50]))
        assert wait_for(rebuilt(runner, first, ticks=60), 30)
        second = runner.inst
        assert runner.watcher.error is None and runner.watcher.applied == 1
        engine = second.engines[0]
        assert engine.color == (200, 100, 50)
        assert engine.behavior is played and engine.reactor is not None
        status = runner.reporter.status(Frame(seq=0, t=0.0))
        (error,) = status["behavior_errors"]
        assert error.startswith("lover: ") and "demonstration.csv: line" in error
        assert error.endswith("; refused, still playing the behaviour read before"), error
        assert "refused" in engine.note
        # an edit of its rate retrains the behaviour read before at the new rate
        write(path, edit([200, 100, 50], rate_hz=25))
        assert wait_for(rebuilt(runner, second), 30)
        engine = runner.inst.engines[0]
        kept = engine.behavior
        assert kept is not None and kept is not played and kept.params.rate_hz == 25
        # fixed on disk, the folder plays and the status says nothing more
        (lover / "demonstration.csv").write_text(good)
        assert wait_for(lambda: runner.reporter.status(Frame(seq=0, t=0.0))["behavior_errors"]
                        == [] and engine.behavior is not kept, 30)
    # the rebuilt installation's recording: started without the refused file, it plays the
    # behaviour read before from its first frame, in the replay too
    live = replays_without(tmp_path / "session-2.jsonl", tmp_path / "replayed.jsonl", {"lover"})
    assert live[0]["characters"][0]["valid"] and live[-1]["characters"][0]["valid"]
