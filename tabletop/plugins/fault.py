"""Engine ``fault``: fails on purpose, to drill the kiosk's supervision (never in a gallery).

Config::

    - kind: fault
      faults:                       # each applies to one start of the supervised process
        - {start: 0, after_s: 2.0, kind: crash}   # SIGABRT, as a native crash in an engine
        - {start: 1, after_s: 2.0, kind: stall}   # the frame loop freezes
        - {start: 2, after_s: 2.0, kind: raise}   # an exception (the loop logs it, keeps going)

``start`` counts the supervisor's starts from 0 (``$TABLETOP_RESTARTS``); ``after_s`` is frame
time after this engine's first step. The engine draws nothing.
"""

from __future__ import annotations

import os
import time

from tabletop.frames import CharacterState, Frame
from tabletop.registry import BuildContext
from tabletop.schema import ListOf, Number, Record, Str

SCHEMA = Record({
    "faults": ListOf(Record({
        "start": Number(0, integer=True, lo=0, doc="which start of the supervised process"),
        "after_s": Number(1.0, lo=0.0, hi=3600.0, unit="seconds",
                          doc="seconds after the engine's first step"),
        "kind": Str(choices=("crash", "stall", "raise")),
    }), default=[]),
})


class FaultEngine:
    """The engine of the module docstring: this start's faults, each from ``after_s`` seconds of
    frame time after the first step (a ``raise`` on every step from then)."""

    def __init__(self, name: str, faults: list[dict]) -> None:
        self.name = name
        self.all_faults = faults
        self.faults: list[dict] = []
        self._t0: float | None = None

    def step(self, frame: Frame) -> tuple[CharacterState, ...]:
        if self._t0 is None:       # the start is known at the first step (a warm spare's
            self._t0 = frame.t     # engines are built before the supervisor numbers it)
            start = int(os.environ.get("TABLETOP_RESTARTS", "0") or 0)
            self.faults = [f for f in self.all_faults if f["start"] == start]
        for f in self.faults:
            if frame.t - self._t0 >= f["after_s"]:
                if f["kind"] == "crash":
                    os.abort()
                if f["kind"] == "stall":
                    while True:
                        time.sleep(3600)
                raise RuntimeError("fault engine: the drill's exception")
        return ()


def build(options: dict, ctx: BuildContext) -> FaultEngine:
    return FaultEngine(options["name"], options["faults"])
