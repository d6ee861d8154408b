"""Review benchmark: seconds ``tabletop review`` takes to draw a session's contact sheet.

A synthetic session of N tries (30, 100, 300; ``--tries=A,B``) is written the way the studio
writes one: a JSON line per try naming its review sheet, a PNG drawn by
:func:`tabletop.studio.review.review_sheet` (a behaviour's, an action's and a touch-pose
action's, 640 x 288 px, drawn once each and copied per try). Each size is drawn in a fresh
process (``python -m tabletop review``, as a designer runs it), wall and CPU seconds, with the
sheet's pixel size and bytes. ``--columns=1`` draws one sheet per row.
"""

from __future__ import annotations

import json
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import numpy as np  # noqa: E402

from bench.common import check_flags, emit  # noqa: E402

KINDS = ("behaviour", "action", "pose action")


def sample_sheets(folder: Path) -> list[Path]:
    """One review sheet of each kind, drawn as the studio draws them."""
    from behaviors.puppet_master import designers
    from tabletop.studio.review import review_sheet
    demo = designers.demonstrate("lover", seed=8, seconds=6)
    t = np.linspace(0.0, 3.0, 90)
    action = np.column_stack([np.sin(2 * t), np.cos(3 * t), t / 3])
    pose = np.column_stack([t, 0.1 * np.sin(t), 0.2 + 0.05 * t, 0.1 * np.cos(t)])
    out = []
    for what, data in zip(KINDS, (demo, action, pose)):
        p = folder / f"sample-{what.replace(' ', '-')}.png"
        review_sheet(what, data, p, title=f"pet: kept {what}")
        out.append(p)
    return out


def session(folder: Path, tries: int, sheets: list[Path]) -> Path:
    """A session log of ``tries`` tries, each with its own review sheet file."""
    log = folder / f"session-{tries}.jsonl"
    outcomes = ("kept", "discarded", "redone", "too short")
    lines = []
    for i in range(tries):
        png = f"{log.stem}-try{i + 1:03d}.png"
        shutil.copyfile(sheets[i % len(sheets)], folder / png)
        outcome = outcomes[i % len(outcomes)]
        d = {"target": "pet", "outcome": outcome, "duration_s": 4.0 + i % 7,
             "samples": 160 + i, "training_s": 0.2, "review": png}
        if outcome == "kept":
            d["name"] = f"pet-{i}"
        lines.append(json.dumps(d))
    log.write_text("\n".join(lines) + "\n")
    return log


def timed_review(log: Path, out: Path, columns: int) -> tuple[float, float]:
    """(wall s, CPU s) of one ``tabletop review`` run in its own process."""
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-m", "tabletop", "review", str(log), "--out", str(out),
                    "--columns", str(columns)], check=True, cwd=ROOT, env=env,
                   stdout=subprocess.DEVNULL)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)


def main(argv: list[str]) -> None:
    check_flags("review", argv, values={"tries": "30,100,300", "columns": "3"})
    sizes, columns = [30, 100, 300], 3
    for a in argv:
        try:
            if a.startswith("--tries="):
                sizes = [int(x) for x in a.split("=", 1)[1].split(",")]
            else:
                columns = int(a.split("=", 1)[1])
        except ValueError:
            sys.exit(f"review: {a}: expected whole numbers")
    figures: dict[str, object] = {"columns": columns}
    from PIL import Image
    with tempfile.TemporaryDirectory() as d:
        folder = Path(d)
        sheets = sample_sheets(folder)
        for n in sizes:
            log = session(folder, n, sheets)
            out = folder / f"sheet-{n}.png"
            wall, cpu = timed_review(log, out, columns)
            pages = sorted(folder.glob(f"sheet-{n}*.png"))
            sizes_px = [Image.open(p).size for p in pages]
            figures[f"tries_{n}"] = {
                "wall_s": round(wall, 2), "cpu_s": round(cpu, 2), "files": len(pages),
                "tallest_px": max(h for _, h in sizes_px), "width_px": sizes_px[0][0],
                "bytes": sum(p.stat().st_size for p in pages)}
            print(f"{n} tries: {figures[f'tries_{n}']}", flush=True)
    emit("review", figures, {"wall_s_300_tries": 20.0})


if __name__ == "__main__":
    main(sys.argv[1:])
