"""``tabletop run --seconds N`` ends every thread it started: the camera's capture, the snapshot
writer, the stop relay and the behaviour reloader's worker, and with ``--studio`` the targets'
training and loading workers, are stopped and joined as the installation closes, and the review
sheets' drawing thread (one for every build) as the run ends, so none outlives the run (a kiosk
rebuilt on every config edit would otherwise gather them)."""

import threading
from pathlib import Path

import cv2
import numpy as np
import pytest
import yaml

from tabletop.cli import main as cli

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("extra", [[], ["--studio"]])
def test_a_timed_run_leaves_no_thread_of_its_own(tmp_path, extra):
    video = tmp_path / "table.avi"
    writer = cv2.VideoWriter(str(video), cv2.VideoWriter_fourcc(*"MJPG"), 30.0, (160, 120))
    for i in range(30):
        writer.write(np.full((120, 160, 3), 80 + i, np.uint8))
    writer.release()
    cfg = yaml.safe_load((ROOT / "config.yaml").read_text(encoding="utf-8"))
    cfg["sources"] = [{"kind": "camera", "name": "cam", "device": str(video), "fps": 30},
                      {"kind": "scripted", "pucks": [1, 2]}]
    cfg["engines"][0]["behavior"] = str(ROOT / "behaviors" / "library" / "lover")
    cfg["view"].update(snapshot_every_s=0.2, snapshot_folder=str(tmp_path / "snapshots"))
    path = tmp_path / "config.yaml"
    path.write_text(yaml.safe_dump(cfg), encoding="utf-8")
    before = set(threading.enumerate())
    assert cli(["run", "--config", str(path), "--headless", "--seconds", "1.5", *extra]) == 0
    assert list((tmp_path / "snapshots").glob("*.png"))      # the writer ran
    left = [t.name for t in threading.enumerate() if t not in before and t.is_alive()]
    assert left == [], left
