"""DESIGN: ``behave``, ``follow`` and ``pose`` runs are reproducible, as outside scripts run
them: two processes, each with its own hash seed (dict and set orders of strings differ
between them), write the same bytes."""

import os
import subprocess
import sys
from pathlib import Path

import numpy as np

from tabletop.files import write_csv
from tests.puppet_master import demos

ROOT = Path(__file__).resolve().parents[2]


def twice(args: list[str], out: Path) -> tuple[bytes, bytes]:
    """The output file of ``tabletop ARGS`` run in two processes with different hash seeds."""
    got = []
    for seed in ("1", "2"):
        r = subprocess.run([sys.executable, "-m", "tabletop", *args], capture_output=True,
                           text=True, timeout=300, cwd=ROOT,
                           env=dict(os.environ, PYTHONHASHSEED=seed))
        assert r.returncode == 0, r.stderr
        got.append(out.read_bytes())
        out.unlink()
    return got[0], got[1]


def test_behave_follow_and_pose_write_the_same_bytes_in_every_process(tmp_path):
    main = demos.main_path(7, 6.0, rate_hz=30, table=(1.2, 0.8))
    write_csv(tmp_path / "main.csv", ["t", "main_x", "main_y", "main_dir"], main.tolist())
    out = tmp_path / "react.csv"
    a, b = twice(["behave", "--train", "behaviors/library/lover", "--input",
                  str(tmp_path / "main.csv"), "--out", str(out)], out)
    assert a == b and a.count(b"\n") == 1 + 6 * 40 + 1

    rng = np.random.default_rng(5)
    for name in ("wave", "circle", "zigzag"):
        write_csv(tmp_path / f"{name}.csv", ["x", "y"], rng.standard_normal((40, 2)).cumsum(0))
    write_csv(tmp_path / "perf.csv", ["x", "y"], rng.standard_normal((80, 2)).cumsum(0))
    out = tmp_path / "progress.csv"
    a, b = twice(["follow", *[a for n in ("wave", "circle", "zigzag") for a in
                              ("--template", f"{n}={tmp_path / (n + '.csv')}")],
                  "--input", str(tmp_path / "perf.csv"), "--out", str(out)], out)
    assert a == b and a.count(b"\n") == 81

    rows = [(round(k / 15, 4), 1, 0.6 + 0.002 * k, 0.45) for k in range(15)]
    rows += [(1.0, 1, 0.63, 0.45), (1.0, 2, 0.55, 0.3)]
    write_csv(tmp_path / "touches.csv", ["t", "id", "x", "y"], rows)
    out = tmp_path / "poses.jsonl"
    a, b = twice(["pose", "--input", str(tmp_path / "touches.csv"), "--out", str(out)], out)
    assert a == b and a.count(b"\n") == 91
