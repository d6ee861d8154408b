"""Projector view speed: draw + present per frame, where a visitor sees it.

Eight characters of every kind and sixteen pucks (tabletop/scene_frames.py), at 1280x720
and 1920x1080, on SDL's dummy driver and in a real X window (a private Xvfb, installed by
bench/xwindow.py when missing; skipped with a reason when it cannot be had). Displays:

- ``dummy``: SDL's dummy driver (no present at all);
- ``x11gl``: an X window presented through SDL's default texture framebuffer (every frame
  uploaded into an OpenGL texture: Mesa's software OpenGL here);
- ``x11``: an X window presented straight (shared-memory images; the view's default, see
  ``tabletop.display.direct_framebuffer``).

Candidates, interleaved A B A B ... (every candidate once per round, rounds alternate):

- ``flip``: draw the whole frame, present the whole window (``display.flip``);
- ``dirty``: repaint the table and present only where this or the previous frame drew
  (``display.update(rects)``), the view's way;
- ``half_scaled``: draw at half the resolution, scale up, present the whole window;
- ``sdl2_texture``: draw as ``dirty`` into a surface, upload the changed rectangles into a
  streaming texture of pygame-ce's ``_sdl2.video.Renderer`` (software renderer) and present it.

Per frame: wall milliseconds of draw + present (median, p99), this thread's CPU, and the X
server's CPU (what presenting costs the server; 10 ms clock ticks summed over the run); for
``dirty``, the pixels and rectangles presented per frame.
Budget (DESIGN.md, issue 14): <= 4 ms median and <= 8 ms p99 per 1280x720 frame in the real window,
with or without hints (``.hinted``: three MOP characters suspecting an action, outlined and named).
"""

from __future__ import annotations

import dataclasses
import os
import sys
import time
from pathlib import Path

os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import pygame  # noqa: E402

from bench.common import check_flags, emit, stats_ms  # noqa: E402
from bench.xwindow import server_cpu_s, xvfb  # noqa: E402
from tabletop.scene_frames import TABLE, busy_frames, hinted_frames  # noqa: E402
from tabletop.view import Renderer, overlay_lines  # noqa: E402

SIZES = ((1280, 720), (1920, 1080))
CANDIDATES = ("flip", "dirty", "half_scaled", "sdl2_texture")
FRAMES_PER_RUN = 60
ROUNDS = 2
SHIPPED = "x11.1280x720.dirty"
HINTED = "x11.1280x720.hinted.dirty"   # the same with 3 of its characters hinted (MOP)


def open_display(driver: str, display: str | None, gl: bool) -> None:
    """(Re)open SDL's video with ``driver``; ``gl``: SDL's texture framebuffer (its default)."""
    pygame.display.quit()
    os.environ["SDL_VIDEODRIVER"] = driver
    os.environ["SDL_FRAMEBUFFER_ACCELERATION"] = "1" if gl else "0"
    if display:
        os.environ["DISPLAY"] = display
    pygame.display.init()
    pygame.font.init()


class Run:
    """One candidate's window and renderer at one size."""

    def __init__(self, candidate: str, size: tuple[int, int]) -> None:
        self.candidate, self.size = candidate, size
        self.overlay = overlay_lines(busy_frames(1, pucks=0)[0], None)
        self.tex = self.sdl = self.window = None
        if candidate == "sdl2_texture":
            from pygame._sdl2 import video
            self.window = video.Window("Tabletop bench", size=size)
            self.sdl = video.Renderer(self.window, accelerated=0)
            self.tex = video.Texture(self.sdl, size, streaming=True)
            self.surface = pygame.Surface(size)
        else:
            self.surface = pygame.display.set_mode(size)
        inner = (size[0] // 2, size[1] // 2) if candidate == "half_scaled" else size
        self.renderer = Renderer(TABLE, inner, margin=24 * inner[0] // size[0])
        self.renderer.incremental = candidate in ("dirty", "sdl2_texture")
        self.inner = pygame.Surface(inner) if candidate == "half_scaled" else None
        self.presented: list[tuple[int, int]] = []   # (pixels, rectangles) per dirty present

    def frame(self, frame) -> tuple[float, float, float]:
        """Draw and present one frame; (draw seconds, present seconds, this thread's CPU
        seconds for both: what the view costs without the machine's other load)."""
        c0 = time.thread_time()
        t0 = time.perf_counter()
        target = self.inner if self.inner is not None else self.surface
        self.renderer.draw(target, frame, self.overlay)
        t1 = time.perf_counter()
        if self.candidate == "flip":
            pygame.display.flip()
        elif self.candidate == "dirty":
            pygame.display.update(self.renderer.dirty)
            self.presented.append((sum(r.w * r.h for r in self.renderer.dirty),
                                   len(self.renderer.dirty)))
        elif self.candidate == "half_scaled":
            pygame.transform.scale(self.inner, self.size, self.surface)
            pygame.display.flip()
        else:
            for r in self.renderer.dirty:
                self.tex.update(self.surface.subsurface(r), area=r)
            self.sdl.clear()
            self.sdl.blit(self.tex)
            self.sdl.present()
        pygame.event.pump()
        return t1 - t0, time.perf_counter() - t1, time.thread_time() - c0

    def close(self) -> None:
        if self.window is not None:
            self.tex = self.sdl = None
            self.window.destroy()


def plan(display: str) -> list[tuple[str, tuple[int, int], str]]:
    """(candidate, size, scene suffix) runs on one display, in order (the _sdl2 window last:
    no set_mode after it)."""
    if display == "x11gl":    # SDL's default present, for comparison: the shipped drawing only
        return [("dirty", s, "") for s in SIZES] + [("dirty", SIZES[0], ".sparse")]
    runs = [(c, s, "") for c in CANDIDATES for s in SIZES]
    # the sparse table, where presenting only what changed pays most; the busy one with three
    # MOP characters hinted (early feedback: outlined and named), the view's way
    return [(c, SIZES[0], ".sparse") for c in ("flip", "dirty")] + runs + [
        ("dirty", SIZES[0], ".hinted")]


def main() -> None:
    check_flags("view", sys.argv[1:])
    t_start = time.monotonic()
    load0 = os.getloadavg()[0]   # other processes' load slows a real window most
    busy = busy_frames(FRAMES_PER_RUN * 2)
    # The shipped installation's load: one reactor and two pucks.
    sparse = [dataclasses.replace(f, characters=f.characters[:1], pucks=f.pucks[:2]) for f in busy]
    scenes = {"": busy, ".sparse": sparse, ".hinted": hinted_frames(busy)}
    samples: dict[str, dict[str, list[float]]] = {}
    server: dict[str, float] = {}
    skipped: dict[str, str] = {}
    with xvfb((1920, 1080)) as xdisplay:
        displays = [("dummy", "dummy", None)]
        if xdisplay is None:
            skipped["x11"] = xvfb.reason
        else:
            displays += [("x11gl", "x11", xdisplay), ("x11", "x11", xdisplay)]
        for rnd in range(ROUNDS):
            for name, driver, disp in (displays if rnd % 2 == 0 else displays[::-1]):
                open_display(driver, disp, gl=name == "x11gl")
                for cand, size, scene in plan(name):
                    frames = scenes[scene]
                    key = f"{name}.{size[0]}x{size[1]}{scene}.{cand}"
                    try:
                        run = Run(cand, size)
                    except pygame.error as exc:
                        skipped[key] = f"could not open: {exc}"
                        continue
                    start = (rnd * 37) % FRAMES_PER_RUN
                    for f in frames[start:start + 10]:      # warm caches, settle the window
                        run.frame(f)
                    d = samples.setdefault(key, {"draw": [], "present": [], "total": [],
                                                 "cpu": []})
                    x0 = server_cpu_s(disp)
                    for f in frames[start + 10:start + 10 + FRAMES_PER_RUN]:
                        a, b, c = run.frame(f)
                        d["draw"].append(a)
                        d["present"].append(b)
                        d["total"].append(a + b)
                        d["cpu"].append(c)
                    server[key] = server.get(key, 0.0) + server_cpu_s(disp) - x0
                    if run.presented:
                        d.setdefault("presented", []).extend(run.presented[10:])
                    run.close()
        pygame.display.quit()
    figures: dict[str, object] = {}
    for key, d in samples.items():
        tot, dr, pr = stats_ms(d["total"]), stats_ms(d["draw"]), stats_ms(d["present"])
        cpu = stats_ms(d["cpu"])
        xs = server[key] / len(d["total"]) * 1e3 if key in server else float("nan")
        figures[key] = {"median_ms": tot["median_ms"], "p99_ms": tot["p99_ms"],
                        "draw_median_ms": dr["median_ms"], "present_median_ms": pr["median_ms"],
                        "cpu_median_ms": cpu["median_ms"], "cpu_p99_ms": cpu["p99_ms"],
                        "frames": len(d["total"])}
        if xs == xs:
            figures[key]["xserver_cpu_mean_ms"] = xs
        if d.get("presented"):
            figures[key]["presented_kpx_mean"] = sum(p for p, _ in d["presented"]) / len(
                d["presented"]) / 1e3
            figures[key]["presented_rects_mean"] = sum(n for _, n in d["presented"]) / len(
                d["presented"])
        print(f"{key:34s} {tot['median_ms']:6.2f} ms median {tot['p99_ms']:6.2f} ms p99 "
              f"(draw {dr['median_ms']:5.2f}, present {pr['median_ms']:5.2f}; cpu "
              f"{cpu['median_ms']:5.2f} median {cpu['p99_ms']:5.2f} p99; X server "
              f"{xs:5.2f} mean)", flush=True)
    figures["shipped"] = SHIPPED
    figures["scene"] = "8 characters (3 reactors, 2 humanoids, creature, face, bird) + 16 pucks"
    figures["sparse_scene"] = "1 reactor + 2 pucks (keys with .sparse)"
    figures["hinted_scene"] = "the busy one, 3 MOP characters hinted (keys with .hinted)"
    figures["skipped"] = skipped
    figures["wall_s"] = time.monotonic() - t_start
    figures["load_average_1min_start_end"] = [load0, os.getloadavg()[0]]
    budget = {"median_ms": "<= 4", "p99_ms": "<= 8"}
    emit("view", figures, {SHIPPED: budget, HINTED: budget})


if __name__ == "__main__":
    main()
