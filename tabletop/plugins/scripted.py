"""Source ``scripted``: a scripted visitor moving pucks, reported directly as table poses.

For a camera-free run; the default installation renders the same visitor through the synthetic
camera instead (source ``synthetic_camera``).
"""

from __future__ import annotations

import time

from tabletop.frames import Observation, PuckMeasurement, SourceHealth
from tabletop.registry import BuildContext
from tabletop.schema import ListOf, Number, Record
from tracking.visitor import ScriptedVisitor

SCHEMA = Record({
    "pucks": ListOf(Number(integer=True, lo=0, hi=10_000), default=[1, 2], min_len=1,
                    doc="marker ids of the pucks the visitor moves"),
    "seed": Number(0, integer=True, lo=0, doc="seed of the visitor's paths"),
})


class ScriptedSource:
    """Poses of a :class:`ScriptedVisitor` at the moment they are asked for (t in seconds)."""

    def __init__(self, name: str, visitor: ScriptedVisitor, clock=time.monotonic) -> None:
        self.name, self.visitor, self.clock = name, visitor, clock
        self._t0 = 0.0
        self._seq = 0
        self._last_t = float("-inf")

    def open(self) -> None:
        self._t0 = self.clock()

    def latest(self) -> Observation:
        t = self.clock()
        self._seq += 1
        self._last_t = t
        pucks = tuple(PuckMeasurement(pid, x, y, a, t)
                      for pid, x, y, a in self.visitor.poses(t - self._t0))
        return Observation(self.name, t, self._seq, pucks=pucks)

    def health(self) -> SourceHealth:
        return SourceHealth(self.name, True, "scripted visitor", max(0.0, self.clock() - self._last_t))

    def close(self) -> None:
        pass


def build(options: dict, ctx: BuildContext) -> ScriptedSource:
    visitor = ScriptedVisitor(ctx.table, options["pucks"], seed=options["seed"])
    return ScriptedSource(options["name"], visitor)
