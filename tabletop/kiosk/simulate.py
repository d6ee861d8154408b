"""Simulated time for soaks and drills: the whole installation stepped on a clock that jumps.

:class:`SimClock` is the clock (seconds); :class:`SteppedCamera` renders a synthetic camera
frame synchronously at the clock's time and measures it with the real detector, so an hour of
table time runs as fast as the machine can render, detect, step the engines and draw.
:func:`simulated` builds an installation from a config on that clock.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

from tabletop.frames import Observation, SourceHealth

if TYPE_CHECKING:
    from tabletop.app import Installation
    from tabletop.kiosk.runner import Runner


class SimClock:
    """A clock that moves only when told (seconds)."""

    def __init__(self, t: float = 1000.0) -> None:
        self.t = t

    def __call__(self) -> float:
        return self.t

    def advance(self, dt: float) -> None:
        self.t += dt


class SteppedCamera:
    """A synthetic camera source read synchronously: each ``latest()`` renders and measures one
    frame at the clock's time (no capture thread). ``down`` makes it fail like an unplugged
    camera (no new frame, unhealthy)."""

    def __init__(self, source: Any) -> None:
        self.source, self.name = source, source.name
        self.reader = None
        self.n = 0
        self.down = False
        self._last: Observation | None = None

    def open(self) -> None:
        self.reader = self.source.opener(self.source.settings)

    def latest(self) -> Observation | None:
        if self.down:
            return self._last
        image = self.reader.read()
        self.n += 1
        self._last = self.source.process(image, self.reader.capture_t, self.n)
        return self._last

    def health(self) -> SourceHealth:
        if self.down:
            return SourceHealth(self.name, False, "camera lost; reconnecting", float("inf"))
        return SourceHealth(self.name, True, "stepped synthetic camera", 0.0)

    def close(self) -> None:
        pass


def stepped(source: Any, entry: dict) -> Any:
    """``wrap_source`` for :func:`tabletop.app.build_live`: synthetic cameras are stepped."""
    return SteppedCamera(source) if entry["kind"] == "synthetic_camera" else source


def simulated(cfg: dict[str, Any], config_path: Path, clock: SimClock, kiosk: bool = True,
              studio: bool = True) -> tuple[Runner, Installation]:
    """A :class:`~tabletop.kiosk.runner.Runner` and its installation on ``clock``: synthetic
    cameras stepped, the loop unpaced, headless. Step it with ``inst.loop.tick()`` and
    ``clock.advance(dt)``."""
    from tabletop.kiosk.runner import Runner
    r = Runner(config_path, cfg, headless=True, kiosk=kiosk, studio=studio, clock=clock,
               wrap_source=stepped)
    r.inst = r._build(cfg)
    r.inst.loop.inputs.open()
    return r, r.inst


def rss_bytes() -> int:
    """This process's resident memory now (Linux /proc), bytes."""
    import os
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def soak(config_path: Path, seconds: float, rate_hz: float, warmup_s: float = 300.0,
         every_s: float = 60.0, studio_keys_every_s: float = 120.0) -> dict[str, Any]:
    """Run the installation of ``config_path`` (kiosk and studio on) for ``seconds`` of
    simulated time at ``rate_hz`` ticks per simulated second; a studio take is recorded and
    discarded every ``studio_keys_every_s``. Returns memory (RSS after ``warmup_s`` and at the
    end, bytes; sampled every ``every_s``), the Python objects alive at the same moments,
    ticks, wall-clock seconds per 1,000 ticks in the first and last sampling period and the
    process's CPU seconds per 1,000 ticks in every period (the rate staying steady)."""
    import gc
    import time

    from tabletop.config import load_config
    clock = SimClock()
    runner, inst = simulated(load_config(config_path), config_path, clock)
    loop = inst.loop
    dt = 1.0 / rate_hz
    n = int(round(seconds * rate_hz))
    per = max(1, int(round(every_s * rate_hz)))
    key_every = max(1, int(round(studio_keys_every_s * rate_hz)))
    script = {0: "designer.record", int(20 * rate_hz): "designer.record",
              int(30 * rate_hz): "designer.discard"}
    session = getattr(getattr(runner, "studio", None), "session", None)
    if session is not None:
        session.wait()       # what the studio loads at start, before the clock runs
    samples, objects, walls, cpus, base, base_objects = [], [], [], [], None, None
    wall, cpu = time.perf_counter(), time.process_time()
    for i in range(n):
        cmd = script.get(i % key_every)
        if cmd:
            loop.commands.put(cmd)
        loop.tick()
        if cmd and session is not None:
            session.wait()   # its review sheet is drawn in wall time, the soak runs simulated
        clock.advance(dt)
        if (i + 1) % per == 0:
            now, now_cpu = time.perf_counter(), time.process_time()
            walls.append((now - wall) / per * 1000.0)
            cpus.append((now_cpu - cpu) / per * 1000.0)
            wall, cpu = now, now_cpu
            gc.collect()
            samples.append(rss_bytes())
            objects.append(len(gc.get_objects()))
            if base is None and (i + 1) * dt >= warmup_s:
                base, base_objects = samples[-1], objects[-1]
    loop.close()
    runner.notifier.close()
    studio = getattr(runner, "studio", None)
    return {"ticks": n, "rss_start_bytes": base if base is not None else samples[0],
            "rss_end_bytes": samples[-1], "rss_samples": samples,
            "objects_start": base_objects if base_objects is not None else objects[0],
            "objects_end": objects[-1], "objects_samples": objects,
            "wall_s_per_1000_ticks_first": walls[0], "wall_s_per_1000_ticks_last": walls[-1],
            "cpu_s_per_1000_ticks": cpus,
            "tries": len(studio.tries) if studio is not None else 0,
            "errors": int(sum(loop.stats.errors.values()))}


def soak_config(root: Path, rate_hz: float, resolution: tuple[int, int] = (320, 180),
                review: bool = True) -> dict:
    """A config with every engine (Puppet Master reacting to a wandering puck and trainable
    in the studio, MOP following a puck drawing gestures) seen through the synthetic camera,
    kiosk and studio on: what :func:`soak` runs."""
    g = root / "examples" / "mop" / "gestures"
    return {
        "loop": {"rate_hz": rate_hz},
        "sources": [{"kind": "synthetic_camera", "name": "camera", "pucks": [1],
                     "resolution": list(resolution), "fps": rate_hz, "hands": {"every_s": 600},
                     "performers": [{"puck": 2, "home": [0.75, 0.35],
                                     "gestures": [str(g / "circle.csv"), str(g / "zigzag.csv")]}]}],
        "engines": [
            {"kind": "puppet_master", "name": "lover", "main": {"puck": 1}, "rate_hz": 5,
             "behavior": str(root / "behaviors" / "library" / "lover"),
             "designer": {"enabled": True, "library": "lib", "main_puck": 1, "react_puck": 2}},
            {"kind": "mop", "name": "mop", "rate_hz": 4,
             "performers": [{"name": "hand", "inputs": [{"kind": "puck", "id": 2}]}],
             "characters": [
                 {"name": "lizard", "kind": "creature", "performer": "hand", "actions": [
                     {"name": "circle", "template": str(g / "circle.csv"), "motion": "curl"}]},
                 {"name": "face", "kind": "face", "performer": "hand", "actions": [
                     {"name": "zigzag", "template": str(g / "zigzag.csv"), "motion": "laugh"}]}]}],
        "view": {"size": list(resolution)},
        "kiosk": {"idle_s": 30, "heartbeat": {"enabled": True, "port": 9}},
        "studio": {"enabled": True, "review": review},
    }
