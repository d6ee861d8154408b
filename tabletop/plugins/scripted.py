"""Source ``scripted``: a scripted visitor moving pucks, reported directly as table poses.

``pucks`` wander about the table (:class:`ScriptedVisitor`); each entry of ``performers`` draws
recorded gestures with its own puck from a home point (:class:`GesturePerformer`), to show and
test action following without a person at the table.
"""

from __future__ import annotations

import logging
import time
from pathlib import Path
from typing import Any, Callable

import numpy as np

from tabletop.files import (MAX_TEMPLATE_BYTES, FileFormatError, ReadFile, carrying,
                            read_shared, read_table)
from tabletop.frames import Observation, PuckMeasurement, SourceHealth
from tabletop.registry import BuildContext
from tabletop.schema import Context, FilePath, ListOf, Number, Range, Record
from tracking.visitor import GesturePerformer, ScriptedVisitor

log = logging.getLogger("tabletop")


def check_pucks(options: dict, path: str, ctx: Context) -> None:
    """Each puck once in ``pucks`` and once among the ``performers``: ``pucks: [1, 1]`` would
    put two markers of one id on the table (the tracker takes them for one puck jumping
    between them), and a second performer of a puck would silently replace the first. (A
    performer's puck may be in ``pucks``, as by default: it performs instead of wandering.)"""
    for key, ids in (("pucks", options["pucks"]),
                     ("performers", [p["puck"] for p in options["performers"]])):
        first: dict[int, int] = {}
        for j, pid in enumerate(ids):
            if pid in first:
                where = f"{path}.{key}[{j}]" + (".puck" if key == "performers" else "")
                raise ctx.error(where, f"puck {pid} is also {key}[{first[pid]}]; give each "
                                       "puck once")
            first[pid] = j


class Gesture(ReadFile):
    """A gesture CSV's path carrying the rows read from it when its config was loaded
    (:class:`ReadFile`; ``content``: columns t, dx, dy: s, m, m from the start; read-only), so
    the build takes them without reading the file again while it is unchanged."""

    content: np.ndarray


def read_gesture(path: str | Path) -> Gesture:
    """A gesture CSV (columns ``t,dx,dy`` among others, at least two rows) read."""
    table = read_table(Path(path), "gesture CSV", ("t", "dx", "dy"), 2, MAX_TEMPLATE_BYTES)
    return gesture_of(path, *table.content[:2], table.read)


def gesture_of(path: str | Path, cols: list[str], data: np.ndarray,
               read: tuple | None = None) -> Gesture:
    """The :class:`Gesture` of a CSV read from ``path`` (``read``: the file's signature taken
    before): its columns ``cols`` (t, dx, dy among them) and rows ``data``."""
    rows = data[:, [cols.index("t"), cols.index("dx"), cols.index("dy")]]
    rows.setflags(write=False)       # shared by every build of the config it was read for
    return carrying(Gesture, str(path), rows, read)


class GestureFile(FilePath):
    """A gesture CSV named in the config, read at load as a MOP template is (a damaged one is
    refused naming its key, not only the file); its value is the :class:`Gesture`."""

    def __init__(self, doc: str = "") -> None:
        super().__init__(kind="file", doc=doc)

    def validate(self, value: Any, path: str, ctx: Context) -> Gesture:
        p = super().validate(value, path, ctx)
        key = ("gesture", p)     # (examples/mop.yaml's two performers: 11 keys, 6 files)
        if key not in ctx.read:
            try:    # (read once with the MOP templates that name the same file)
                table = read_shared(ctx.read, p, "gesture CSV", ("t", "dx", "dy"), 2,
                                    MAX_TEMPLATE_BYTES)
            except FileFormatError as exc:
                raise ctx.error(path, str(exc)) from None
            ctx.read[key] = gesture_of(p, *table.content[:2], table.read)
        return ctx.read[key]


SCHEMA = Record({
    "pucks": ListOf(Number(integer=True, lo=0, hi=10_000), default=[1, 2], min_len=0,
                    doc="marker ids of the pucks the visitor moves"),
    "seed": Number(0, integer=True, lo=0, doc="seed of the visitor's paths"),
    "performers": ListOf(Record({
        "puck": Number(integer=True, lo=0, hi=10_000, doc="marker id of the performing puck"),
        "home": ListOf(Number(lo=0.0), min_len=2, max_len=2, doc="where it rests, metres"),
        "gestures": ListOf(GestureFile(), min_len=1,
                           doc="CSV files with columns t,dx,dy (s, m, m from the start)"),
        "speed": Range(Number(lo=0.05, hi=20.0), default=[0.6, 1.6],
                       doc="range of speed factors (1 = as recorded)"),
    }), default=[], doc="pucks drawing recorded gestures"),
}, check=check_pucks)


class ScriptedSource:
    """Poses of a :class:`ScriptedVisitor` at the moment they are asked for (t in seconds)."""

    def __init__(self, name: str, visitor: ScriptedVisitor,
                 performers: dict[int, GesturePerformer] | None = None,
                 clock: Callable[[], float] = time.monotonic) -> None:
        self.name, self.visitor, self.clock = name, visitor, clock
        self.performers = dict(performers or {})
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
                      for pid, x, y, a in self.poses(t - self._t0))
        return Observation(self.name, t, self._seq, pucks=pucks)

    def poses(self, t: float) -> list[tuple[int, float, float, float]]:
        """(id, x m, y m, angle rad) of every scripted puck ``t`` seconds after opening."""
        out = self.visitor.poses(t) if self.visitor.puck_ids else []
        return out + [(pid, *p.pose(t)) for pid, p in self.performers.items()]

    def health(self) -> SourceHealth:
        return SourceHealth(self.name, True, "scripted visitor",
                            max(0.0, self.clock() - self._last_t))

    def close(self) -> None:
        pass


def _rows(g: Path) -> np.ndarray:
    """The rows of gesture ``g`` its config's load read, unless the file changed since (saved
    while the installation started): then as it is now, as a MOP template is; a file gone bad
    meanwhile is said and the rows read before are drawn."""
    if isinstance(g, Gesture) and g.unchanged():
        return g.content
    try:
        return read_gesture(g).content
    except FileFormatError as exc:
        if not isinstance(g, Gesture):
            raise
        log.warning("%s; drawing the gesture as it was read before", exc)
        return g.content


def build(options: dict, ctx: BuildContext) -> ScriptedSource:
    performers = {}
    for k, p in enumerate(options["performers"]):
        gestures = [_rows(g) for g in p["gestures"]]
        performers[p["puck"]] = GesturePerformer(gestures,
                                                 tuple(p["home"]),
                                                 seed=options["seed"] * 31 + k,
                                                 speed=tuple(p["speed"]))
    wandering = [pid for pid in options["pucks"] if pid not in performers]
    visitor = ScriptedVisitor(ctx.table, wandering, seed=options["seed"])
    return ScriptedSource(options["name"], visitor, performers,
                          clock=ctx.shared.get("clock", time.monotonic))
