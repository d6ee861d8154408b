"""A MOP engine on a scripted table, for its tests and benchmarks: the example gestures
(``examples/make_mop_gestures.py``), an engine built from a config, and a table that drives it
at 60 Hz (one clock, frames of pucks moved along the gestures)."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING, Callable, Iterable

import numpy as np

from tabletop.config import validate_config
from tabletop.frames import CharacterState, Frame, Puck
from tabletop.plugins import mop
from tabletop.registry import BuildContext

if TYPE_CHECKING:
    from behaviors.mop.stage import MopStage

ROOT = Path(__file__).resolve().parents[2]   # the project's folder
EXAMPLES = ROOT / "examples"
RATE = 60.0


def _gestures() -> ModuleType:
    """examples/make_mop_gestures.py, loaded as a module."""
    spec = importlib.util.spec_from_file_location("make_mop_gestures",
                                                  EXAMPLES / "make_mop_gestures.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules["make_mop_gestures"] = module
    spec.loader.exec_module(module)
    return module


G = _gestures()


def build(data: dict, base: Path) -> MopStage:
    """The MOP engine of config ``data`` (its first engine), files relative to ``base``."""
    cfg = validate_config(data, str(base / "test.yaml"), base)
    ctx = BuildContext(table=(1.2, 0.8), rate_hz=RATE, config=cfg, base=base)
    return mop.build(cfg["engines"][0], ctx)


class Table:
    """Drives an engine with frames at 60 Hz on one clock."""

    def __init__(self, engine: MopStage) -> None:
        self.engine, self.t, self.seq = engine, 0.0, 0
        self.pucks: dict[int, tuple[float, float]] = {1: (0.3, 0.3), 2: (0.9, 0.5)}
        self.touches: tuple = ()
        self.streams: dict = {}

    def tick(self, commands: Iterable[str] = (),
             focus: str | None = None) -> dict[str, CharacterState]:
        pucks = tuple(Puck(i, x, y, 0.0) for i, (x, y) in self.pucks.items())
        frame = Frame(self.seq, self.t, pucks=pucks, touches=self.touches,
                      streams=dict(self.streams), commands=tuple(commands), focus=focus)
        out = {c.name: c for c in self.engine.step(frame)}
        self.t += 1.0 / RATE
        self.seq += 1
        return out

    def rest(self, seconds: float) -> list[dict[str, CharacterState]]:
        """``seconds`` of ticks with the pucks still."""
        return [self.tick() for _ in range(int(seconds * RATE))]

    def perform(self, name: str, puck: int = 1, speed: Callable[[float], float] = lambda u: 1.0,
                noise: float = 0.0, seed: int = 0, upto: float = 1.0
                ) -> list[tuple[float, dict[str, CharacterState]]]:
        """Move ``puck`` along gesture ``name`` from where it is, up to progress ``upto``;
        ``speed(u)`` is the playback rate at gesture progress u, ``noise`` each position's
        Gaussian noise (standard deviation, metres). Returns [(true progress, characters)]."""
        g = G.gesture(name)
        x0, y0 = self.pucks[puck]
        rng = np.random.default_rng(seed)
        dur = g[-1, 0]
        tau, out = 0.0, []
        while tau < dur * upto:
            dx = np.interp(tau, g[:, 0], g[:, 1]) + rng.normal(0, noise)
            dy = np.interp(tau, g[:, 0], g[:, 2]) + rng.normal(0, noise)
            self.pucks[puck] = (x0 + dx, y0 + dy)
            out.append((tau / dur, self.tick()))
            tau += speed(tau / dur) / RATE
        return out


def designer_config(tmp_path: Path) -> dict:
    return {"sources": [{"kind": "scripted"}], "engines": [{
        "kind": "mop", "library": "lib",
        "performers": [{"name": "hand", "inputs": [{"kind": "puck", "id": 1}]}],
        "characters": [
            {"name": "face", "kind": "face", "performer": "hand",
             "actions": [{"name": "circle", "template": str(EXAMPLES / "mop/gestures/circle.csv"),
                          "motion": "talk"}]},
            {"name": "lizard", "kind": "creature", "performer": "hand",
             "motions": ["strike", "curl"]}]}]}
