"""Simulated time for soaks and drills: the whole installation stepped on a clock that jumps.

:class:`SimClock` is the clock (seconds); :class:`SteppedCamera` renders a synthetic camera
frame synchronously at the clock's time and measures it with the real detector, so an hour of
table time runs as fast as the machine can render, detect, step the engines and draw.
:func:`simulated` builds an installation from a config on that clock.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from tabletop.frames import Observation, SourceHealth


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
              studio: bool = True):
    """A :class:`~tabletop.kiosk.runner.Runner` and its installation on ``clock``: synthetic
    cameras stepped, the loop unpaced, headless. Step it with ``inst.loop.tick()`` and
    ``clock.advance(dt)``."""
    from tabletop.kiosk.runner import Runner
    r = Runner(config_path, cfg, headless=True, kiosk=kiosk, studio=studio, clock=clock,
               wrap_source=stepped)
    r.inst = r._build(cfg)
    r.inst.loop.inputs.open()
    return r, r.inst
