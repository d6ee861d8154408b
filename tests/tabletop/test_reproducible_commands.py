"""DESIGN: ``behave``, ``follow`` and ``pose`` runs are reproducible, as outside scripts run
them: two processes, each with its own hash seed (dict and set orders of strings differ
between them), write the same bytes. Each process runs the three commands in turn (the
command line's ``main``, as ``tabletop`` does): the test's own process and a fresh one whose
hash seed is shown to differ from it."""

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

from tabletop.files import write_csv
from tests.puppet_master import demos

ROOT = Path(__file__).resolve().parents[2]

# each argument a command's words (JSON); the first failing status ends the process with it;
# its last line on stdout: its hash of a string (the seed's mark)
COMMANDS = """
import json, sys
from tabletop.cli import main
for words in sys.argv[1:]:
    status = main(json.loads(words))
    if status:
        sys.exit(status)
print(hash("tabletop"))
"""


def twice(commands: list[list[str]], outs: list[Path]) -> list[tuple[bytes, bytes]]:
    """Each command's output file (``outs``, in order) from two processes with different hash
    seeds, each running ``tabletop COMMAND`` for every command: this one (the command line's
    ``main``), then a fresh one. (This process as one of the two: one start, its imports
    and the commands' first loads, ~1.4 CPU s, fewer.)"""
    from tabletop.cli import main
    got = []
    for words in commands:
        assert main(words) == 0, words
    got.append([out.read_bytes() for out in outs])
    for out in outs:
        out.unlink()
    seed = "2" if os.environ.get("PYTHONHASHSEED") == "1" else "1"
    r = subprocess.run([sys.executable, "-c", COMMANDS, *map(json.dumps, commands)],
                       capture_output=True, text=True, timeout=300, cwd=ROOT,
                       env=dict(os.environ, PYTHONHASHSEED=seed))
    assert r.returncode == 0, r.stderr
    assert int(r.stdout.split()[-1]) != hash("tabletop")     # another hash seed than ours
    got.append([out.read_bytes() for out in outs])
    return list(zip(*got))


def test_behave_follow_and_pose_write_the_same_bytes_in_every_process(tmp_path):
    main = demos.main_path(7, 6.0, rate_hz=30, table=(1.2, 0.8))
    write_csv(tmp_path / "main.csv", ["t", "main_x", "main_y", "main_dir"], main.tolist())
    react = tmp_path / "react.csv"
    behave = ["behave", "--train", str(ROOT / "behaviors" / "library" / "lover"), "--input",
              str(tmp_path / "main.csv"), "--out", str(react)]

    rng = np.random.default_rng(5)
    for name in ("wave", "circle", "zigzag"):
        write_csv(tmp_path / f"{name}.csv", ["x", "y"], rng.standard_normal((40, 2)).cumsum(0))
    write_csv(tmp_path / "perf.csv", ["x", "y"], rng.standard_normal((80, 2)).cumsum(0))
    progress = tmp_path / "progress.csv"
    follow = ["follow", *[a for n in ("wave", "circle", "zigzag") for a in
                          ("--template", f"{n}={tmp_path / (n + '.csv')}")],
              "--input", str(tmp_path / "perf.csv"), "--out", str(progress)]

    rows = [(round(k / 15, 4), 1, 0.6 + 0.002 * k, 0.45) for k in range(15)]
    rows += [(1.0, 1, 0.63, 0.45), (1.0, 2, 0.55, 0.3)]
    write_csv(tmp_path / "touches.csv", ["t", "id", "x", "y"], rows)
    poses = tmp_path / "poses.jsonl"
    pose = ["pose", "--input", str(tmp_path / "touches.csv"), "--out", str(poses)]

    (a, b), (c, d), (e, f) = twice([behave, follow, pose], [react, progress, poses])
    assert a == b and a.count(b"\n") == 1 + 6 * 40 + 1
    assert c == d and c.count(b"\n") == 81
    assert e == f and e.count(b"\n") == 91
    assert not (tmp_path / "rec").exists()   # nothing ran
