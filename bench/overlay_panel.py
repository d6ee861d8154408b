"""The operator panel's cost per frame (``Renderer.draw_overlay``) where it lies over what it
keeps clear of, at 640x360 (the operator's 13 lines: a panel over the table's centre in every
corner) and 1280x720.

Cases: ``clear`` (nothing under the panel: blitted as it is), ``still`` (a character's
rectangle under it, the same every frame), ``moving`` (the rectangle moves 1 px a frame, as a
walking character's does) and ``studio`` (the moving one and the studio's words under it).
Per frame: microseconds, median and p99 of 2000 frames after 50 warm-up frames.

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


def main() -> dict:
    pygame.display.init()
    return {f"{w}x{h} {case}": per_frame((w, h), case) for w, h in ((640, 360), (1280, 720))
            for case in ("clear", "still", "moving", "studio")}


if __name__ == "__main__":
    result = main()
    for k, v in result.items():
        print(k, v)
    print(json.dumps(result))
