"""MOP actions a kiosk started without: what following their files costs the frame loop.

A kiosk started with two MOP creatures and three unreadable configured actions (a template
with a short row, a clip cut in half) runs :class:`tabletop.kiosk.actions.ActionReloader` as a
frame filter every tick. Times, in microseconds of wall time over many ticks:

- ``tick_us``: a tick between looks (the looks are a second apart; nothing is done);
- ``look_us``: a look at the four configured actions' files, unchanged (``os.stat`` of five
  files: the reloader watches every configured action for the kiosk's whole run, the one
  read too; 99 us, against 112 us measured in the same session watching the three unreadable
  ones alone, within this machine's drift);
- ``follow_ms``: the tick that reads the fixed template of two actions and retrains the
  followers (once, at the technician's fix; milliseconds, median of ``ROUNDS`` fixes).

Run: ``OPENBLAS_NUM_THREADS=1 python bench/action_reload.py``.
"""

from __future__ import annotations

import json
import shutil
import statistics
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from behaviors.motion.clips import clip_to_mapping  # noqa: E402
from behaviors.mop.creatures import creature_clips  # noqa: E402
from behaviors.mop.stage import MopStage  # noqa: E402
from bench.common import check_flags, emit  # noqa: E402
from tabletop.config import validate_config  # noqa: E402
from tabletop.frames import Frame  # noqa: E402
from tabletop.kiosk.actions import ActionReloader  # noqa: E402
from tabletop.plugins import mop  # noqa: E402
from tabletop.registry import BuildContext  # noqa: E402

GESTURES = Path(__file__).resolve().parents[1] / "examples" / "mop" / "gestures"
TICKS = 20_000
ROUNDS = 5


def _stage(tmp: Path) -> MopStage:
    """The MOP stage of a kiosk's start: walker (circle; line and square unreadable) and lone
    (line unreadable)."""
    for name in ("circle", "line", "square"):
        shutil.copy(GESTURES / f"{name}.csv", tmp / f"{name}.csv")
    clip = json.dumps(clip_to_mapping(creature_clips()["wag"]))
    (tmp / "wag.json").write_text(clip[:len(clip) // 2])
    with open(tmp / "line.csv", "a") as f:
        f.write("1e3,0.5\n")
    engine = {"kind": "mop", "name": "mop",
              "performers": [{"name": "hand", "inputs": [{"kind": "puck", "id": 1}]}],
              "characters": [
                  {"name": "walker", "kind": "creature", "performer": "hand", "actions": [
                      {"name": "circle", "template": "circle.csv", "motion": "walk"},
                      {"name": "line", "template": "line.csv", "motion": "curl"},
                      {"name": "square", "template": "square.csv", "motion": "wag.json"}]},
                  {"name": "lone", "kind": "creature", "performer": "hand", "actions": [
                      {"name": "line", "template": "line.csv", "motion": "strike"}]}]}
    cfg = validate_config({"sources": [{"kind": "scripted"}], "engines": [engine]},
                          str(tmp / "config.yaml"), tmp, start_without=True)
    ctx = BuildContext((1.2, 0.8), 60.0, cfg, tmp)
    ctx.shared["kiosk_start"] = True
    return mop.build(cfg["engines"][0], ctx)


def main() -> None:
    check_flags("action_reload", sys.argv[1:])
    frame = Frame(seq=0, t=1.0)
    tick, look, follow = [], [], []
    for _ in range(ROUNDS):
        tmp = Path(tempfile.mkdtemp())
        good = (GESTURES / "line.csv").read_text()
        stage = _stage(tmp)
        assert len(stage.missing) == 3
        reloader = ActionReloader(stage)
        reloader(frame)                       # the first look, at the files as read
        t0 = time.perf_counter()
        for _ in range(TICKS):
            reloader(frame)
        tick.append((time.perf_counter() - t0) / TICKS * 1e6)
        reloader = ActionReloader(stage, every_s=0.0)       # a look every tick
        t0 = time.perf_counter()
        for _ in range(TICKS // 10):
            reloader(frame)
        look.append((time.perf_counter() - t0) / (TICKS // 10) * 1e6)
        (tmp / "line.csv").write_text(good)
        reloader(frame)                       # the look that sees it written
        t0 = time.perf_counter()
        reloader(frame)
        follow.append((time.perf_counter() - t0) * 1e3)
        assert len(stage.missing) == 1, stage.start_problems
        shutil.rmtree(tmp)
    figures = {"tick_us": statistics.median(tick), "look_us": statistics.median(look),
               "follow_ms": statistics.median(follow)}
    print(", ".join(f"{k} {v:.2f}" for k, v in figures.items()))
    emit("action_reload", figures, {"tick_us": 5.0, "look_us": 200.0, "follow_ms": None})


if __name__ == "__main__":
    main()
