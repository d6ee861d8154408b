"""The whole pipeline from rendered camera frames: `tabletop run` on a synthetic camera records
pucks where the scripted visitor put them, within millimetres."""

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import yaml

from tracking.visitor import ScriptedVisitor

TABLE = (1.2, 0.8)
PUCKS = [1, 2, 3, 4]
CONFIG = {
    "table": {"width": TABLE[0], "height": TABLE[1]},
    "loop": {"rate_hz": 60},
    "sources": [{"kind": "synthetic_camera", "name": "camera", "pucks": PUCKS, "seed": 3,
                 "tilt_deg": 15.0, "distortion": [-0.05, 0.01, 0.0, 0.0, 0.0],
                 "hands": {"every_s": 0}}],
    "view": {"size": [640, 360]},
    # A camera frame late on a busy machine leaves the pucks "seen" (not coasting or dropped):
    # what is counted below is how often the detector finds a puck in the frames it is given.
    "tracking": {"stale_s": 2.0, "coast_s": 2.0},
}


def run(tmp_path: Path, config: dict, seconds: float = 2.0) -> list[dict]:
    cfg = tmp_path / "config.yaml"
    cfg.write_text(yaml.safe_dump(config))
    out = tmp_path / "session.jsonl"
    proc = subprocess.run([sys.executable, "-m", "tabletop", "run", "--config", str(cfg),
                           "--headless", "--seconds", str(seconds), "--record", str(out)],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    lines = out.read_text().splitlines()
    return [json.loads(line) for line in lines[1:]]


def truth_errors(frames: list[dict], offset: float, visitor: ScriptedVisitor):
    """Position (m) and heading (degrees) errors of the seen pucks' measurements, each one
    once, at the frame it came in (frames repeating it while the camera is late on a busy
    machine are stamped later than its capture)."""
    pos, ang, last = [], [], {}
    for f in frames:
        truth = {pid: (x, y, a) for pid, x, y, a in visitor.poses(f["t"] + offset)}
        for p in f["pucks"]:
            raw = (p["raw_x"], p["raw_y"], p["raw_angle"])
            if p["state"] == "seen" and last.get(p["id"]) != raw:
                last[p["id"]] = raw
                x, y, a = truth[p["id"]]
                pos.append(math.hypot(p["raw_x"] - x, p["raw_y"] - y))
                ang.append(abs(math.remainder(p["raw_angle"] - a, math.tau)))
    return np.array(pos), np.degrees(ang)


def best_offset(frames: list[dict], visitor: ScriptedVisitor, offsets: np.ndarray) -> float:
    """The offset (s) of ``offsets`` with the smallest median position error (measured: the
    error grows steadily away from the true offset, about 2 cm per 0.1 s, either side)."""
    medians = [np.median(truth_errors(frames, o, visitor)[0]) for o in offsets]
    return float(offsets[int(np.argmin(medians))])


def test_run_on_synthetic_camera_matches_the_visitor(tmp_path):
    frames = run(tmp_path, CONFIG)
    assert len(frames) >= 40
    visitor = ScriptedVisitor(TABLE, PUCKS, seed=3)
    # The recording's clock starts at its first frame; the script started when the camera
    # opened, a fraction of a second earlier: find that one offset.
    late = [f for f in frames if f["pucks"]]
    best = best_offset(late[::4], visitor, np.arange(-0.1, 2.0, 0.02))            # coarse,
    best = best_offset(late[::4], visitor, np.arange(best - 0.02, best + 0.021, 0.002))  # fine
    pos, ang = truth_errors(late, best, visitor)
    seen = sum(1 for f in late for p in f["pucks"] if p["state"] == "seen")
    assert seen >= 0.9 * len(PUCKS) * len(late)
    assert all({p["id"] for p in f["pucks"]} <= set(PUCKS) for f in frames)  # no false ids
    assert np.median(pos) <= 0.002 and np.percentile(pos, 95) <= 0.005
    assert np.median(ang) <= 1.0
