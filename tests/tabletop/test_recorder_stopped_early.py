"""A run stopped while it is built, before its first frame, leaves no recording: a header alone
is nothing replay can play ("no complete frame"), and the failure path removes such a part
too. A run that recorded a frame keeps its file."""

import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

from tabletop.app import build_live
from tabletop.cli import main as tabletop
from tabletop.config import validate_config
from tabletop.recorder import read_frames
from tests import children

ROOT = Path(__file__).resolve().parents[2]
CONFIG = {
    "sources": [{"kind": "scripted", "name": "visitor", "pucks": [1, 2], "seed": 4}],
    "view": {"headless": True, "size": [320, 180]},
}


def test_a_run_stopped_before_its_first_frame_removes_its_header_only_recording(tmp_path,
                                                                                  caplog):
    """The stop (a signal while the installation is built sets it) comes before any frame."""
    cfg = validate_config(CONFIG, "test", tmp_path)
    path = tmp_path / "session.jsonl"
    stop = threading.Event()
    live = build_live(cfg, headless=True, record_path=path, stop=stop)
    assert path.exists()            # the header is written as the recorder starts
    stop.set()
    with caplog.at_level("WARNING", logger="tabletop"):
        assert live.loop.run(seconds=5.0) == 0
    assert not path.exists() and list(tmp_path.glob("session*")) == []
    said = [r.getMessage() for r in caplog.records if "recording" in r.getMessage()]
    assert said == [f"recording {path}: stopped before its first frame: nothing recorded, "
                    "the file removed"]


def test_a_header_only_recording_that_cannot_be_removed_is_said_so(tmp_path, caplog):
    """A directory where the part was (its file moved away): the removal fails, the log says
    so instead of "the file removed", and the recorder lists no part."""
    cfg = validate_config(CONFIG, "test", tmp_path)
    path = tmp_path / "session.jsonl"
    stop = threading.Event()
    live = build_live(cfg, headless=True, record_path=path, stop=stop)
    path.rename(tmp_path / "moved.jsonl")
    path.mkdir()
    stop.set()
    with caplog.at_level("WARNING", logger="tabletop"):
        assert live.loop.run(seconds=5.0) == 0
    said = [r.getMessage() for r in caplog.records if "recording" in r.getMessage()]
    assert len(said) == 1 and said[0].startswith(
        f"recording {path}: stopped before its first frame: nothing recorded; the file could "
        "not be removed: "), said
    assert live.recorder.paths == []


def test_a_run_with_a_frame_keeps_its_recording(tmp_path):
    cfg = validate_config(CONFIG, "test", tmp_path)
    path = tmp_path / "session.jsonl"
    ran = build_live(cfg, headless=True, record_path=path).loop.run(seconds=0.2)
    assert ran >= 1 and len(list(read_frames(path))) == ran


def test_a_signal_during_a_run_s_build_never_leaves_a_recording_replay_refuses(tmp_path):
    """SIGTERM as soon as the recording's file appears (the recorder is built first, the view
    after it): the run ends cleanly (0) and leaves either no file or one that replays."""
    path = tmp_path / "s.jsonl"
    cfg = tmp_path / "c.yaml"
    cfg.write_text("sources: [{kind: scripted, name: s, pucks: [1]}]\n"
                   "view: {headless: true, size: [320, 180]}\n")
    p = children.popen([sys.executable, "-m", "tabletop", "run", "--headless", "--config",
                        str(cfg), "--record", str(path), "--seconds", "60"], cwd=ROOT,
                       stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    while p.poll() is None and not path.exists():
        time.sleep(0.001)
    p.send_signal(signal.SIGTERM)
    _, err = p.communicate(timeout=60)
    assert p.returncode == 0 and "Traceback" not in err, err
    if path.exists():
        assert tabletop(["replay", str(path), "--fast", "--no-view"]) == 0
    else:
        assert "stopped before its first frame: nothing recorded, the file removed" in err
