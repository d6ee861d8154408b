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

Operator commands go to the designer target in ``frame.focus`` (the main loop's Tab cycles
through every engine's ``designer_targets``; with no focus, every designer engine takes them):
``designer.record`` starts and stops recording; the take is trained at once and the character
reacts with it straight away; ``designer.keep`` saves it to the library (never over an existing
behaviour: ``lover-2``, ``lover-3``...), ``designer.discard`` drops it and goes back to the
previous behaviour, recording again redoes it.

The reactor steps at the behaviour's rate (40 Hz) on the frames' own times. While its main is
absent it keeps reacting to the main's last pose; before the main was ever seen it waits (drawn
dimmed). A main bound to a character must name an engine listed earlier in the config.
"""

from __future__ import annotations

import math
import time
from pathlib import Path
from typing import Any

import numpy as np

from behaviors.puppet_master.engine import Behavior, Reactor
from tabletop import library
from tabletop.frames import CharacterState, Frame, InputError, wrap_angle
from tabletop.registry import BuildContext
from tabletop.schema import (Bool, Context, FilePath, ListOf, Number, Optional_, Record, Spec,
                             Str)

MAIN_KINDS = ("puck", "character", "touch", "stream")
MESSAGE_S = 4.0          # seconds an operator message stays in the label
MARKER_DEBOUNCE_S = 0.3  # the record marker must be on (or off) the table this long
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
    """One reacting character on the bus, optionally trainable from the table (designer mode)."""

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
        self._use(behavior)
        self.last_main: tuple[float, float, float] | None = None
        self._last_t = -math.inf
        self._dir = 0.0
        self.mode = "idle"                   # idle | recording | trying
        self.take: list[tuple[float, ...]] = []
        self.pending: Behavior | None = None
        self.kept: list[Path] = []
        self._message, self._message_until = "", -math.inf
        self._marker_on, self._marker_since = False, -math.inf
        self._focused = True
        if self.designer is not None:
            if self.designer["main_puck"] is None:
                self.designer["main_puck"] = main["puck"] if main["kind"] == "puck" else 1
            if self.designer["name"] is None:
                self.designer["name"] = name

    # -- the behaviour in play ----------------------------------------------------------------

    def _use(self, behavior: Behavior | None) -> None:
        """Play ``behavior`` from here on (a fresh reactor, started at the main's next pose)."""
        self.behavior = behavior
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
        if self.designer is not None:
            self._designer_commands(frame)
            if self.mode == "recording":
                return (self._record(frame),)
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
        return (self._character(x, y, d, True, self._label(frame), pose[:2]),)

    def _character(self, x: float, y: float, d: float, valid: bool, label: str,
                   look_at: tuple[float, float] | None = None) -> CharacterState:
        look = (float(look_at[0]), float(look_at[1])) if look_at is not None else None
        return CharacterState(self.name, float(x), float(y), float(d), kind="reactor",
                              size=self.size, color=self.color, valid=valid, label=label,
                              look_at=look)

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
        return self._character(x, y, d, False, self._label(frame, why))

    def _label(self, frame: Frame, status: str = "") -> str:
        now = self.clock()
        if now < self._message_until:
            status = self._message
        elif self.mode == "trying" and self.pending is not None:
            status = (f"trained {self.pending.samples} samples, try it: K keep, X discard, "
                      "R record again")
        elif not status and self.reactor is not None:
            status = f"playing {self.behavior_name or 'behaviour'}"
            if self.reactor.started:
                status += f", coherence {self.reactor.coherence_share:.0%}"
        return status + self._selection()

    def designer_targets(self) -> tuple[str, ...]:
        """This engine, when in designer mode, is one of the targets Tab cycles through."""
        return (self.name,) if self.designer is not None else ()

    def _selection(self) -> str:
        if self.designer is None:
            return ""
        return " [selected]" if self._focused else " [Tab selects]"

    def _say(self, message: str) -> None:
        self._message, self._message_until = message, self.clock() + MESSAGE_S

    # -- designer mode --------------------------------------------------------------------------

    def _designer_commands(self, frame: Frame) -> None:
        selected = self._focused = frame.focus is None or frame.focus == self.name
        for cmd in frame.commands:
            if not selected:
                break
            if cmd == "designer.record":
                self._toggle_record()
            elif cmd == "designer.keep":
                self._keep()
            elif cmd == "designer.discard":
                self._discard()
        marker = self.designer["record_marker"]
        if marker is not None and selected:
            on = frame.puck(marker) is not None
            if on != self._marker_on:
                if self._marker_since == -math.inf:
                    self._marker_since = frame.t
                if frame.t - self._marker_since >= MARKER_DEBOUNCE_S:
                    self._marker_on, self._marker_since = on, -math.inf
                    if on != (self.mode == "recording"):
                        self._toggle_record()
            else:
                self._marker_since = -math.inf

    def _toggle_record(self) -> None:
        if self.mode == "recording":
            self._train_take()
            return
        if self.mode == "trying":            # recording again redoes the take being tried
            behavior, self.behavior_name = self._previous
            self._use(behavior)
        self.mode, self.take, self.pending = "recording", [], None

    def _record(self, frame: Frame) -> CharacterState:
        m = frame.puck(self.designer["main_puck"])
        r = frame.puck(self.designer["react_puck"])
        if m is not None and r is not None and (not self.take or frame.t > self.take[-1][0]):
            self.take.append((frame.t, m.x, m.y, m.angle, r.x, r.y, r.angle))
        secs = self.take[-1][0] - self.take[0][0] if self.take else 0.0
        missing = [f"puck {p}" for p, q in ((self.designer["main_puck"], m),
                                            (self.designer["react_puck"], r)) if q is None]
        status = f"recording {secs:.1f} s, R stop"
        status += f" (no {', '.join(missing)})" if missing else ""
        status += self._selection()
        if r is not None:
            return self._character(r.x, r.y, r.angle, True, status)
        x0, y0, x1, y1 = self.table
        return self._character((x0 + x1) / 2, (y0 + y1) / 2, 0.0, False, status)

    def take_array(self) -> np.ndarray:
        """The recorded take as a demonstration (n, 7), times from 0."""
        a = np.array(self.take, dtype=float).reshape(-1, 7)
        if a.size:
            a[:, 0] -= a[0, 0]
        return a

    def _train_take(self) -> None:
        demo = self.take_array()
        secs = float(demo[-1, 0]) if len(demo) else 0.0
        need = self.designer["min_seconds"]
        self.mode = "idle"
        if secs < need:
            self._say(f"take too short ({secs:.1f} s of both pucks, needs {need:g} s): R to record")
            return
        rate = self.rate_hz or (self.behavior.params.rate_hz if self.behavior else 40.0)
        window = self.behavior.params.window if self.behavior else 40
        try:
            self.pending = Behavior.train(demo, rate_hz=rate, window=window)
        except InputError as exc:
            self._say(f"cannot train: {exc}")
            return
        self.pending_demo = demo
        self._previous = (self.behavior, self.behavior_name)
        self._use(self.pending)
        self.behavior_name = "new take"
        self.mode = "trying"

    def _keep(self) -> None:
        if self.mode != "trying" or self.pending is None:
            self._say("nothing to keep: R records a take")
            return
        lib = self.designer["library"]
        try:
            name = library.free_name(lib, self.designer["name"])
            folder = library.save_behavior(
                lib, name, self.pending_demo,
                {"rate_hz": self.pending.params.rate_hz, "window": self.pending.params.window},
                description=f"demonstrated at the table for {self.name}",
                source="designer mode, recorded from the table")
        except InputError as exc:
            self._say(f"not saved: {exc}")
            return
        self.kept.append(folder)
        self.behavior_name, self.mode, self.pending = name, "idle", None
        self._say(f"kept as {name} in {folder.parent}")

    def _discard(self) -> None:
        if self.mode == "trying":
            behavior, name = self._previous
            self._use(behavior)
            self.behavior_name, self.mode, self.pending = name, "idle", None
            self._say("take discarded")
        else:
            self._say("nothing to discard")


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
    return PuppetMasterEngine(options["name"], options["main"], ctx.table, behavior, bname,
                              tuple(options["color"]), options["size"], designer,
                              options["rate_hz"])
