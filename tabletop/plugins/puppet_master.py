"""Engine ``puppet_master``: a reacting character driven by a demonstrated behaviour.

Config::

    - kind: puppet_master
      name: lover                     # the character's name (other reactors may bind to it)
      behavior: behaviors/library/lover   # a behaviour folder (relative to this config file)
      main: {puck: 1}                 # or {character: NAME}, {touch: ID},
                                      #    {stream: NAME, columns: [x, y, dir]}
      color: [240, 120, 160]
      size: 0.08                      # metres
      designer:                       # training from the table (optional)
        enabled: true
        main_puck: 1                  # the designer's two pucks: their poses are the demonstration
        react_puck: 2
        record_marker: 9              # a marker placed on the table records, lifted off stops
        library: library              # kept behaviours go to <library>/<name>/
        name: lover                   # default: this engine's name

With ``designer.enabled`` the engine is a target of the designer studio (``tabletop.studio``):
record a take with the two pucks, train it at once, try it, keep it in the library (never over
an existing behaviour: ``lover-2``, ``lover-3``...) or redo it.

The reactor steps at the behaviour's rate (40 Hz) on the frames' own times. While its main is
absent it keeps reacting to the main's last pose; before the main was ever seen it waits (drawn
dimmed). A main bound to a character must name an engine listed earlier in the config.
"""

from __future__ import annotations

import math
import time
from pathlib import Path
from typing import Any, Callable

from behaviors.puppet_master.engine import Behavior, Reactor
from tabletop import library
from tabletop.frames import CharacterState, Frame, InputError, wrap_angle
from tabletop.registry import BuildContext
from tabletop.schema import (Bool, Context, FilePath, ListOf, Number, Optional_, Record, Spec,
                             Str)

MAIN_KINDS = ("puck", "character", "touch", "stream")
TURN_SPEED = 0.02        # m/s: below it a touch or stream main keeps its look direction


class PuppetMasterError(InputError):
    """A Puppet Master engine cannot be built as configured; the message names what and where."""


class MainBinding(Spec):
    """What drives the main character: exactly one of ``puck``, ``character``, ``touch``,
    ``stream`` (with ``columns``: indices of x, y and optionally the look direction)."""

    def __init__(self, default: Any = None) -> None:
        self.default = {"kind": "puck", "puck": 1} if default is None else default
        self.doc = "the main character's input"

    def describe(self) -> str:
        return ("one of {puck: ID}, {character: NAME}, {touch: ID}, "
                "{stream: NAME, columns: [X, Y] or [X, Y, DIR]}")

    def validate(self, value: Any, path: str, ctx: Context) -> Any:
        if not isinstance(value, dict):
            raise ctx.error(path, f"expected {self.describe()}, got {value!r}")
        kinds = [k for k in value if k in MAIN_KINDS]
        if len(kinds) != 1:
            raise ctx.error(path, f"expected exactly one of {', '.join(MAIN_KINDS)}; got "
                            f"{', '.join(map(str, value)) or 'nothing'}")
        kind = kinds[0]
        fields: dict[str, Spec] = {
            "puck": {"puck": Number(integer=True, lo=0)},
            "touch": {"touch": Number(integer=True, lo=0)},
            "character": {"character": Str()},
            "stream": {"stream": Str(), "columns": ListOf(Number(integer=True, lo=0),
                                                          min_len=2, max_len=3)},
        }[kind]
        return {"kind": kind, **Record(fields).validate(value, path, ctx)}


DESIGNER = Record({
    "enabled": Bool(False, doc="training from the table"),
    "main_puck": Optional_(Number(integer=True, lo=0),
                           doc="the designer's main puck (default: main's puck, else 1)"),
    "react_puck": Number(2, integer=True, lo=0, doc="the designer's reactor puck"),
    "record_marker": Optional_(Number(integer=True, lo=0),
                               doc="marker id that records while it is on the table"),
    "library": FilePath("library", must_exist=False, kind="dir",
                        doc="folder the kept behaviours are saved in"),
    "name": Optional_(Str(), doc="name of kept behaviours (default: the engine's name)"),
    "min_seconds": Number(2.0, lo=0.1, doc="shortest take that is trained"),
})


def _check(opts: dict, path: str, ctx: Context) -> None:
    where = f"{path}.behavior" if path else "behavior"
    if opts["behavior"] is None:
        if not opts["designer"]["enabled"]:
            raise ctx.error(where, "missing; expected a behaviour folder (e.g. "
                            "behaviors/library/lover) unless designer.enabled is true")
        return
    try:
        library.read_description(opts["behavior"])
    except library.LibraryError as exc:
        raise ctx.error(where, str(exc)) from None


SCHEMA = Record({
    "behavior": Optional_(FilePath(kind="dir"), doc="behaviour folder (behavior.yaml + CSV)"),
    "main": MainBinding(),
    "color": ListOf(Number(integer=True, lo=0, hi=255), default=[240, 170, 60], min_len=3,
                    max_len=3, doc="RGB"),
    "size": Number(0.08, lo=0.005, hi=2.0, doc="body length, metres"),
    "rate_hz": Optional_(Number(lo=5.0, hi=400.0),
                         doc="generation rate (default: the behaviour's)"),
    "designer": DESIGNER,
}, check=_check)


class PuppetMasterEngine:
    """One reacting character on the bus. Designer mode (record, train, try, keep) is the
    studio's (:class:`tabletop.studio.targets.PuppetMasterTarget`): it plays takes through
    :meth:`play` and shows the reactor puck while recording through :attr:`hold`."""

    def __init__(self, name: str, main: dict, table: tuple[float, float],
                 behavior: Behavior | None = None, behavior_name: str = "",
                 color: tuple[int, int, int] = (240, 170, 60), size: float = 0.08,
                 designer: dict | None = None,
                 rate_hz: float | None = None, clock=time.monotonic) -> None:
        self.name, self.main, self.table = name, main, (0.0, 0.0, float(table[0]), float(table[1]))
        self.color, self.size, self.rate_hz, self.clock = color, size, rate_hz, clock
        self.designer = designer if designer and designer["enabled"] else None
        self.behavior_name = behavior_name
        self.behavior: Behavior | None = None
        self.reactor: Reactor | None = None
        self.play(behavior, behavior_name)
        self.last_main: tuple[float, float, float] | None = None
        self._last_t = -math.inf
        self._dir = 0.0
        self.hold: Callable[[Frame], CharacterState] | None = None  # replaces the reaction
        self.note = ""                                               # the studio's label
        if self.designer is not None:
            if self.designer["main_puck"] is None:
                self.designer["main_puck"] = main["puck"] if main["kind"] == "puck" else 1
            if self.designer["name"] is None:
                self.designer["name"] = name

    # -- the behaviour in play ----------------------------------------------------------------

    def play(self, behavior: Behavior | None, name: str = "") -> None:
        """Play ``behavior`` from here on (a fresh reactor, started at the main's next pose)."""
        self.behavior, self.behavior_name = behavior, name
        self.reactor = Reactor(behavior, self.table) if behavior is not None else None

    # -- inputs ---------------------------------------------------------------------------------

    def _main_pose(self, frame: Frame) -> tuple[float, float, float] | None:
        m = self.main
        kind = m["kind"]
        if kind == "puck":
            p = frame.puck(m["puck"])
            return None if p is None else (p.x, p.y, p.angle)
        if kind == "character":
            c = frame.character(m["character"])
            return None if c is None or not c.valid else (c.x, c.y, c.heading)
        if kind == "touch":
            for tc in frame.touches:
                if tc.id == m["touch"]:
                    return self._moving(tc.x, tc.y, tc.vx, tc.vy)
            return None
        a = frame.streams.get(m["stream"])
        cols = m["columns"]
        if a is None or a.ndim != 1 or max(cols) >= a.size:
            return None
        vals = [float(a[c]) for c in cols]
        if not all(math.isfinite(v) for v in vals):
            return None
        if len(vals) == 3:
            return vals[0], vals[1], wrap_angle(vals[2])
        if self.last_main is not None and frame.t > self._last_t:
            dt = frame.t - self._last_t
            vx, vy = (vals[0] - self.last_main[0]) / dt, (vals[1] - self.last_main[1]) / dt
            return self._moving(vals[0], vals[1], vx, vy)
        return vals[0], vals[1], self._dir

    def _moving(self, x: float, y: float, vx: float, vy: float) -> tuple[float, float, float]:
        """A pose for an input without a look direction: it looks where it moves."""
        if math.hypot(vx, vy) > TURN_SPEED:
            self._dir = math.atan2(vy, vx)
        return x, y, self._dir

    # -- the engine step ------------------------------------------------------------------------

    def step(self, frame: Frame) -> tuple[CharacterState, ...]:
        if self.hold is not None:
            return (self.hold(frame),)
        pose = self._main_pose(frame)
        if pose is not None and not all(math.isfinite(v) for v in pose):
            pose = None                      # a broken measurement counts as absent
        if pose is not None:
            self.last_main = pose
        elif self.last_main is not None:
            pose = self.last_main            # keeps reacting to the main's last pose
        self._last_t = max(self._last_t, frame.t)
        if self.reactor is None or pose is None:
            return (self._waiting(frame),)
        x, y, d = self.reactor.update(frame.t, *pose)
        return (self.character(x, y, d, True, self._label()),)

    def character(self, x: float, y: float, d: float, valid: bool, label: str) -> CharacterState:
        return CharacterState(self.name, float(x), float(y), float(d), kind="reactor",
                              size=self.size, color=self.color, valid=valid, label=label)

    def _waiting(self, frame: Frame) -> CharacterState:
        x0, y0, x1, y1 = self.table
        x, y, d = (x0 + x1) / 2, (y0 + y1) / 2, 0.0
        if self.designer is not None:
            p = frame.puck(self.designer["react_puck"])
            if p is not None:
                x, y, d = p.x, p.y, p.angle
        if self.reactor is None:
            why = "R to record a behaviour" if self.designer else "no behaviour"
        else:
            why = f"waiting for {self.main['kind']} {self.main[self.main['kind']]}"
        return self.character(x, y, d, False, self.note or why)

    def _label(self) -> str:
        if self.note:
            return self.note
        status = f"playing {self.behavior_name or 'behaviour'}"
        if self.reactor is not None and self.reactor.started:
            status += f", coherence {self.reactor.coherence_share:.0%}"
        return status


def _check_binding(options: dict, ctx: BuildContext) -> None:
    """A main bound to a character must name an engine listed before this one."""
    main = options["main"]
    if main["kind"] != "character":
        return
    engines = ctx.config.get("engines", []) if isinstance(ctx.config, dict) else []
    names = [e.get("name") for e in engines]
    mine = names.index(options["name"]) if options["name"] in names else len(names)
    if main["character"] not in names[:mine]:
        where = f"engines[{mine}].main.character" if mine < len(names) else "main.character"
        raise PuppetMasterError(
            f"{where}: {main['character']!r} is not an engine listed before {options['name']!r}; "
            "a reactor reacts to characters made earlier in the same tick")


def build(options: dict, ctx: BuildContext) -> PuppetMasterEngine:
    _check_binding(options, ctx)
    behavior, bname = None, ""
    if options["behavior"] is not None:
        stored = library.load_behavior(options["behavior"])
        params = dict(stored.parameters)
        if options["rate_hz"] is not None:
            params["rate_hz"] = options["rate_hz"]
        try:
            behavior = Behavior.train(stored.demonstration, **params)
        except InputError as exc:
            raise PuppetMasterError(f"{stored.folder}: {exc}") from None
        bname = stored.name
    designer = dict(options["designer"])
    lib = Path(designer["library"]).expanduser()
    designer["library"] = lib if lib.is_absolute() else Path(ctx.base) / lib
    engine = PuppetMasterEngine(options["name"], options["main"], ctx.table, behavior, bname,
                                tuple(options["color"]), options["size"], designer,
                                options["rate_hz"])
    engine.folder = options["behavior"]   # the studio reloads it when it changes on disk
    return engine
