"""The operator panel's cost per frame (``Renderer.draw_overlay``) where it lies over what it
keeps clear of, at 640x360 (the operator's 13 lines: a panel over the table's centre in every
corner) and 1280x720.

Cases: ``clear`` (nothing under the panel: blitted as it is), ``still`` (a character's
rectangle under it, the same every frame), ``moving`` (the rectangle moves 1 px a frame, as a
walking character's does) and ``studio`` (the moving one and the studio's words under it).
Per frame: microseconds, median and p99 of 2000 frames after 50 warm-up frames.

``view refresh``: ``ProjectorView.consume`` per frame with the overlay on (1280x720, headless:
the frame drawn, nothing presented), five MOP characters whose lines' figures change every
frame, one of them beginning or ending an action every 8 frames (its line then changes on that
frame); its p90 shows the frames that make the panel again. Median and p90 microseconds of 600
frames at 60 Hz after 60 warm-up frames.

    OPENBLAS_NUM_THREADS=1 python bench/overlay_panel.py
"""

from __future__ import annotations

import json
import os
import sys
import time
from pathlib import Path

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402
import pygame  # noqa: E402

from bench.common import check_flags  # noqa: E402
from tabletop.renderer import Renderer  # noqa: E402

LINES = ["tick 55   running 1.9 s", "30.8 fps   skipped 1   errors 0",
         *(f"  stage{i}\t1.00 ms median\t2.00 ms p99" for i in range(9)),
         "source scripted: ok   scripted visitor   age 0 ms", "humanoid wave 0.40"]


def per_frame(size: tuple[int, int], case: str, n: int = 2000) -> dict[str, float]:
    """Median and p99 microseconds of one ``draw_overlay`` call in ``case``."""
    W, H = size
    pygame.display.set_mode(size)
    r = Renderer((1.2, 0.8), size)
    target = pygame.Surface(size)
    out = []
    for k in range(n + 50):
        body = pygame.Rect(W // 2 - 80 + (k % 40 if case != "still" else 0), H // 2 - 120,
                           160, 240)
        avoid = [] if case == "clear" else [body]
        must = [pygame.Rect(W // 2 - 150, H // 2 - 20, 300, 24)] if case == "studio" else []
        t0 = time.perf_counter()
        r.draw_overlay(target, LINES, avoid, must)
        if k >= 50:
            out.append(time.perf_counter() - t0)
    us = np.array(out) * 1e6
    return {"median_us": round(float(np.median(us)), 1),
            "p99_us": round(float(np.percentile(us, 99)), 1)}


def view_refresh(n: int = 600) -> dict[str, float]:
    """Median and p90 microseconds of ``ProjectorView.consume`` with the overlay on (see the
    module's docstring)."""
    from tabletop.config import validate_config
    from tabletop.frames import CharacterState, Frame
    from tabletop.loop import LoopStats
    from tabletop.view import ProjectorView
    stats = LoopStats()
    for i, stage in enumerate(("capture_to_render", "inputs", "engines", "sinks", "tick")):
        for k in range(300):
            stats.record(stage, 0.001 * (k % 7 + i))
    cfg = validate_config({"sources": [{"kind": "scripted"}],
                           "view": {"size": [1280, 720], "headless": True, "overlay": True}})
    view = ProjectorView((1.2, 0.8), cfg["view"], stats=stats)
    out = []
    try:
        for k in range(n + 60):
            cs = []
            for j, name in enumerate(("dancer", "bird", "salamander", "face", "gecko")):
                acting = ((k + 8 * j) // 40) % 2 == 1
                label = f"line {k % 40 / 40:4.2f} p=0.9{k % 10}" if acting else "no action"
                cs.append(CharacterState(name, 0.2 + 0.2 * j, 0.3 + 0.1 * (j % 2), 0.0,
                                         size=0.1, color=(240, 170, 60), action="line",
                                         valid=acting, label=label))
            frame = Frame(seq=k, t=k / 60, characters=tuple(cs))
            t0 = time.perf_counter()
            view.consume(frame)
            dt = time.perf_counter() - t0
            if k >= 60:
                out.append(dt)
            time.sleep(max(0.0, 1 / 60 - dt))
    finally:
        view.close()
    us = np.array(out) * 1e6
    return {"median_us": round(float(np.median(us)), 1),
            "p90_us": round(float(np.percentile(us, 90)), 1)}


def main() -> dict:
    pygame.display.init()
    out = {f"{w}x{h} {case}": per_frame((w, h), case) for w, h in ((640, 360), (1280, 720))
           for case in ("clear", "still", "moving", "studio")}
    out["1280x720 view refresh"] = view_refresh()
    return out


if __name__ == "__main__":
    check_flags("overlay_panel", sys.argv[1:])
    result = main()
    for k, v in result.items():
        print(k, v)
    print(json.dumps(result))
