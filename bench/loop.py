"""Whole-loop benchmark: the installation with its 1280x720 view, headless (SDL's dummy driver)
and in a real X window (a private Xvfb, see bench/xwindow.py; skipped with a reason when none can
be had).

Configurations: the scripted visitor straight to the view; the shipped config.yaml (synthetic
camera -> marker detection -> tracker -> one reactor -> view); and the synthetic camera with four
Puppet Master reactors (one reacting to another), the DESIGN.md whole-loop case.

Capture-to-render (``capture_age``), per presented frame: from the moment its newest input was
captured to the moment the view has presented it (its sink is done:
``pygame.display.update``/``flip`` returned; sinks after it, e.g. a recorder, do not count). The
capture moment is the camera's shutter: a device camera's frame is stamped when the driver hands it
over; the synthetic camera renders the scene as it stands at the end of its render and never
delivers an image before that moment (its rendering simulates the world and the optics, which cost a
real installation nothing; a render that overruns delivers late and its lateness counts). Each
capture counts once, at its first drawing: a tick that draws it again (nothing new arrived) or runs
on the stamp of a stalled camera measures nothing (counting them, a 30 fps camera on the 60 Hz loop
read 21.6 ms median where the same run at 60 fps read 8.8: the repeats' age is the camera's period,
not latency).

Per-stage figures from the running loop (medians and p99 of the measured seconds), in the order
a frame goes through them: ``camera_render`` (synthetic image, not part of the latency; with a
render process, the wait for its frame, and ``camera_render_cpu`` this process's share),
``source`` (capture -> observation ready: grey conversion, marker detection, mapping),
``queued`` (ready -> the tick that takes it), ``inputs`` (tracker), ``engine:NAME``,
``sink:view`` (the view's draw and present) of which ``present``, and the whole ``tick``;
``gc_pause`` lists the garbage collector's passes (count and longest) while measuring; and the
CPU time of the stages (``*_cpu``, see :class:`Probes`), which the machine's load does not
inflate.

For each configuration and display: the loop unpaced (as fast as it can tick: ticks per second)
and paced at 60 Hz (the shipped loop: it ticks when a camera frame arrives). For comparison the
camera configurations are also run paced
- with the synthetic camera rendering where the config does not have it render
  (``render_process``: in a child process; ``render_thread``: in the camera's thread, as the
  shipped config does);
- in the X window with ``loop.realtime_priority`` (``realtime``: the installation's threads and
  the X server ahead of the machine's other programs; where refused, ordinary scheduling);
- with ``--timer``, as before the loop followed its camera (``timer``: a fixed 60 Hz timer, the
  synthetic camera phase-locked to it, its shutter at the start of its render, no
  garbage-collector freeze, Python's default 5 ms thread switch interval).
Configurations run interleaved in rounds so drifting machine speed favours none; each run is
measured from one second after its first camera frame.
Budgets (DESIGN.md): >= 60 ticks/s; capture-to-render p99 <= 15 ms.

Run: ``.venv/bin/python bench/loop.py`` (about 200 s); ``--quick`` runs one round of 2 s.
"""

from __future__ import annotations

import contextlib
import gc
import math
import os
import sys
import time
from pathlib import Path
from typing import Iterator

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402
import pygame  # noqa: E402

from bench.common import check_flags, emit  # noqa: E402
from bench.xwindow import xvfb  # noqa: E402
from tabletop.app import build_live  # noqa: E402
from tabletop.config import load_config, validate_config  # noqa: E402
from tabletop.loop import LoopStats  # noqa: E402
from tabletop.plugins.synthetic_render import RenderProcessReader, SyntheticReader  # noqa: E402
from tabletop.recorder import jsonable  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
REALTIME = 10   # the ``paced60_realtime`` runs' loop.realtime_priority (and the X server's)
VIEW = {"headless": True, "size": [1280, 720], "overlay": True}


def configs() -> dict[str, dict]:
    out = {"scripted_view": validate_config(
        {"sources": [{"kind": "scripted", "pucks": [1, 2]}], "view": VIEW}, "bench", ROOT)}
    default = load_config(ROOT / "config.yaml")
    default["view"] = dict(default["view"], headless=True, size=[1280, 720])
    out["default_config"] = default
    lib = ROOT / "behaviors" / "library"
    reactors = [
        {"kind": "puppet_master", "name": "lover", "behavior": str(lib / "lover"),
         "main": {"puck": 1}},
        {"kind": "puppet_master", "name": "bully", "behavior": str(lib / "bully"),
         "main": {"puck": 2}},
        {"kind": "puppet_master", "name": "stalker", "behavior": str(lib / "stalker"),
         "main": {"puck": 1}},
        {"kind": "puppet_master", "name": "afraid", "behavior": str(lib / "afraid"),
         "main": {"character": "lover"}},
    ]
    out["synthetic_camera_4_reactors"] = validate_config(
        {"sources": jsonable(default["sources"]), "engines": reactors, "view": VIEW}, "bench", ROOT)
    return out


CPU_STAGES = ("tick_cpu", "camera_render_cpu", "source_cpu", "after_publish_cpu")


class Probes:
    """Stage timings the loop does not take itself, recorded into its LoopStats while
    installed: the view's present, the synthetic camera's render, garbage-collector passes;
    and the CPU time (of the thread doing it) of a tick, of the camera's render, of its
    processing before the observation is out (``source_cpu``) and after (``after_publish_cpu``,
    the put-off full-frame search). On a machine shared with other work the CPU times leave out
    the waiting for a core: they say what each stage costs on a quiet machine."""

    def __init__(self, stats: LoopStats, loop, sources) -> None:
        self.stats, self.loop, self.sources = stats, loop, sources
        self._saved = (pygame.display.update, pygame.display.flip, SyntheticReader.read,
                       RenderProcessReader.read)
        self._gc_t = 0.0

    def __enter__(self) -> "Probes":
        update, flip, read, read_process = self._saved
        st = self.stats
        for stage in ("present", "camera_render", "gc_pause", *CPU_STAGES):  # other threads too
            st.record(stage, 0.0)
            st.samples[stage].clear()

        def timed(fn, stage, cpu_stage=None):
            def wrapper(*a, **k):
                t0, c0 = time.perf_counter(), time.thread_time()
                try:
                    return fn(*a, **k)
                finally:
                    st.record(stage, time.perf_counter() - t0)
                    if cpu_stage:
                        st.record(cpu_stage, time.thread_time() - c0)
            return wrapper

        def cpu(fn, stage):
            def wrapper(*a, **k):
                c0 = time.thread_time()
                try:
                    return fn(*a, **k)
                finally:
                    st.record(stage, time.thread_time() - c0)
            return wrapper

        pygame.display.update = timed(update, "present")
        pygame.display.flip = timed(flip, "present")
        SyntheticReader.read = timed(read, "camera_render", "camera_render_cpu")
        # A render process: the wait for its frame, and this process's CPU for taking it over.
        RenderProcessReader.read = timed(read_process, "camera_render", "camera_render_cpu")
        self.loop.tick = cpu(self.loop.tick, "tick_cpu")
        for src in self.sources:
            process = getattr(src, "process", None)
            if process is not None:
                after = getattr(process, "after_publish", None)
                src.process = cpu(process, "source_cpu")
                if after is not None:
                    src.process.after_publish = cpu(after, "after_publish_cpu")
        gc.callbacks.append(self._gc)
        return self

    def _gc(self, phase: str, info: dict) -> None:
        if phase == "start":
            self._gc_t = time.perf_counter()
        else:
            self.stats.record("gc_pause", time.perf_counter() - self._gc_t)

    def __exit__(self, *exc) -> None:
        (pygame.display.update, pygame.display.flip, SyntheticReader.read,
         RenderProcessReader.read) = self._saved
        gc.callbacks.remove(self._gc)


@contextlib.contextmanager
def x_server_priority(display: str | None, priority: int) -> Iterator[None]:
    """The X server of ``display`` (its lock file names its process) at SCHED_FIFO
    ``priority`` meanwhile, when ``priority`` and the system allow it."""
    pid, before = None, None
    if display and priority:
        try:
            pid = int(Path(f"/tmp/.X{display.lstrip(':')}-lock").read_text().strip())
            before = os.sched_getscheduler(pid), os.sched_getparam(pid)
            os.sched_setscheduler(pid, os.SCHED_FIFO, os.sched_param(priority))
        except (OSError, ValueError, AttributeError):
            pid = None
    try:
        yield
    finally:
        if pid is not None and before is not None:
            try:
                os.sched_setscheduler(pid, *before)
            except OSError:
                pass


def measure(cfg: dict, seconds: float, paced: bool, warmup: float = 1.0,
            display: str | None = None, timer: bool = False,
            render: str | None = None, realtime: int = 0) -> dict[str, float]:
    """Run the installation until ``warmup`` seconds after its first camera frame (or its
    start, without a camera), then ``seconds`` more; figures are of those last ``seconds`` only
    (steady state: caches settled). With ``display`` the view opens a real window on that X
    display, else it runs on SDL's dummy driver. ``timer``: the loop as it was before it
    followed its camera (see the module's docstring). ``render``: "thread" or "process" sets
    where the synthetic camera renders (its ``render_process``), None keeps the config's.
    ``realtime``: the loop's ``realtime_priority`` (and the same for the X server meanwhile)."""
    if display is None:
        os.environ["SDL_VIDEODRIVER"] = "dummy"
    else:
        os.environ["SDL_VIDEODRIVER"] = "x11"
        os.environ["DISPLAY"] = display
        cfg = dict(cfg, view=dict(cfg["view"], headless=False))
    if render is not None:
        cfg = dict(cfg, sources=[dict(s, render_process=render == "process")
                                 if s["kind"] == "synthetic_camera" else s
                                 for s in cfg["sources"]])
    stats = LoopStats(window=100_000)
    SyntheticReader.shutter_at_end = not timer
    inst = build_live(cfg, headless=display is None, stats=stats)
    inst.loop.paced = paced
    inst.loop.inputs.follow = not timer
    inst.loop.freeze_gc = not timer
    inst.loop.switch_interval_s = None if timer else inst.loop.switch_interval_s
    inst.loop.realtime_priority = realtime
    t_start = time.monotonic()
    camera = any(s["kind"] == "synthetic_camera" for s in cfg["sources"])
    first = [None if camera else t_start]   # the first camera frame's tick, monotonic s
    warm = [True]
    end = [math.inf]

    def steady(frame) -> None:  # figures of the last ``seconds`` only
        now = time.monotonic()
        if first[0] is None and frame.pucks:
            first[0] = now
        if warm[0] and first[0] is not None and now - first[0] >= warmup:
            warm[0] = False
            end[0] = now + seconds
            for d in stats.samples.values():
                d.clear()
            stats.tick_times.clear()
        if now >= end[0] or now - t_start > 60.0:
            inst.loop.stop.set()

    inst.loop.hooks.append(steady)
    with Probes(stats, inst.loop, inst.loop.inputs.sources), x_server_priority(display, realtime):
        inst.loop.run()
    SyntheticReader.shutter_at_end = True
    times = np.asarray(stats.tick_times)
    fig: dict[str, float] = {"ticks": len(times),
                             "ticks_per_s": (len(times) - 1) / (times[-1] - times[0])}
    for stage, d in stats.samples.items():
        a = np.asarray(d) * 1e3
        if stage == "gc_pause":
            fig["gc_pause_count"] = len(a)
            fig["gc_pause_max_ms"] = float(a.max()) if len(a) else 0.0
        elif len(a):
            fig[f"{stage}_median_ms"] = float(np.median(a))
            fig[f"{stage}_p99_ms"] = float(np.percentile(a, 99))
    fig["run_s"] = time.monotonic() - t_start
    return fig


def main() -> None:
    check_flags("loop", sys.argv[1:], ["--quick", "--timer"])
    quick = "--quick" in sys.argv
    cfgs = configs()
    rounds, seconds = (1, 2.0) if quick else (2, 3.0)
    load0 = os.getloadavg()[0]
    results: dict[str, dict[str, list[float]]] = {}
    figures: dict[str, object] = {}
    with xvfb((1280, 720)) as display:
        displays = {"dummy": None}
        if display is None:
            figures["x11_skipped"] = xvfb.reason
        else:
            displays["x11"] = display
        for _ in range(rounds):
            for name, cfg in cfgs.items():
                camera = any(s["kind"] == "synthetic_camera" for s in cfg["sources"])
                modes = [("unpaced", False, False, None, 0), ("paced60", True, False, None, 0)]
                if camera:   # the synthetic camera rendering where the config does not
                    other = "thread" if any(s.get("render_process") for s in cfg["sources"]) \
                        else "process"
                    modes.append((f"paced60_render_{other}", True, False, other, 0))
                    if "--timer" in sys.argv:
                        modes.append(("paced60_timer", True, True, "thread", 0))
                for driver, disp in displays.items():
                    extra = [("paced60_realtime", True, False, None, REALTIME)] \
                        if camera and disp is not None else []
                    for label, paced, timer, render, realtime in modes + extra:
                        key = f"{driver}.{name}_{label}"
                        for k, v in measure(cfg, seconds, paced, display=disp, timer=timer,
                                            render=render, realtime=realtime).items():
                            results.setdefault(key, {}).setdefault(k, []).append(v)
    for key, figs in results.items():
        for k, vals in figs.items():
            if k != "run_s":
                figures[f"{key}.{k}"] = float(np.median(vals))
    figures["load_average_1min_start_end"] = [load0, os.getloadavg()[0]]
    budgets = {"*_unpaced.ticks_per_s": ">= 60", "*_paced60.ticks_per_s": ">= 60",
               "*_paced60.capture_age_p99_ms": "<= 15"}
    emit("loop", figures, budgets)


if __name__ == "__main__":
    main()
