"""Engine ``puppet_master``: a reacting character driven by a demonstrated behaviour.

Config::

    - kind: puppet_master
      name: lover                     # the character's name (other reactors may bind to it)
      behavior: behaviors/library/lover   # a behaviour folder (relative to this config file)
      main: {puck: 1}                 # or {character: NAME}, {touch: ID},
                                      #    {stream: NAME, columns: [x, y, dir]},
                                      #    {nearest: [...]} or {first: [...]} of those
      color: [240, 120, 160]
      size: 0.08                      # metres
      keep_apart: true                # keep the body sizes away from other reactors
      designer:                       # training from the table (optional)
        enabled: true
        main_puck: 1                  # the designer's two pucks: their poses are the demonstration
        react_puck: 2
        record_marker: 9              # a marker placed on the table records, lifted off stops
        library: library              # kept behaviours go to <library>/<name>/
        name: lover                   # default: this engine's name
        background_training: true     # train in a worker thread (false: within the tick)
        sequential: false             # true: record the main, then the reactor against its
                                      #   playback (R, R, R, R / the playback's end)

Operator commands go to the designer target in ``frame.focus`` (the main loop's Tab cycles
through every engine's ``designer_targets``; with no focus, every designer engine takes them):
``designer.record`` starts and stops recording; the take is trained at once (in a worker
thread, swapped in between ticks) and the character reacts with it straight away; ``designer.keep`` saves it to the library (never over an existing
behaviour: ``lover-2``, ``lover-3``...), ``designer.discard`` drops it and goes back to the
previous behaviour, recording again redoes it.

The reactor steps at the behaviour's rate (40 Hz) on the frames' own times. While its main is
absent it keeps reacting to the main's last pose; before the main was ever seen it waits (drawn
dimmed). A main bound to a character reads that character in the same tick when its engine
is listed earlier; a Puppet Master engine listed later, or one reacting back (a mutual pair),
is read one tick old (see :mod:`tabletop.plugins.puppet_master_mains`).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from behaviors.puppet_master.engine import Behavior, Reactor
from behaviors.puppet_master.sequential import SequentialSession
from behaviors.puppet_master.training import BackgroundTrainer
from tabletop import library
from tabletop.frames import CharacterState, Frame, InputError
from tabletop.registry import BuildContext
from tabletop.plugins.puppet_master_mains import (Board, MainBinding, MainReader, Posted,
                                                  bound_characters, singles)
from tabletop.plugins.puppet_master_mains import board as shared_board
from tabletop.schema import Bool, Context, FilePath, ListOf, Number, Optional_, Record, Str

MESSAGE_S = 4.0          # seconds an operator message stays in the label
MARKER_DEBOUNCE_S = 0.3  # the record marker must be on (or off) the table this long


class PuppetMasterError(InputError):
    """A Puppet Master engine cannot be built as configured; the message names what and where."""


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
    "sequential": Bool(False, doc="one hand: R records the main, R stops, R plays it back "
                       "and records the reactor against it (paper 3.1)"),
    "background_training": Bool(True, doc="train in a worker thread, swapped in between "
                                "ticks (false: within the tick, for exact replays)"),
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
    "keep_apart": Bool(True, doc="keep at least the body sizes away from other reactors"),
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
                 rate_hz: float | None = None, clock=None,
                 board: Board | None = None, delayed: set[str] | None = None,
                 keep_apart: bool = True) -> None:
        self.name, self.main, self.table = name, main, (0.0, 0.0, float(table[0]), float(table[1]))
        # Messages time out on the frames' times (``clock``: another time source), so a
        # replay reproduces the labels as well as the motion.
        self.board = board if board is not None else Board()
        self.mains = MainReader(main, set(delayed or ()), self.board)
        self.keep_apart = keep_apart
        self.color, self.size, self.rate_hz, self.clock = color, size, rate_hz, clock
        self._now = -math.inf
        self.designer = designer if designer and designer["enabled"] else None
        self.behavior_name = behavior_name
        self.behavior: Behavior | None = None
        self.reactor: Reactor | None = None
        self._use(behavior)
        self.last_main: tuple[float, float, float] | None = None
        self.mode = "idle"                   # idle | recording | trying
        self.take: list[tuple[float, ...]] = []
        self.pending: Behavior | None = None
        self.kept: list[Path] = []
        self._message, self._message_until = "", -math.inf
        self._marker_on, self._marker_since = False, -math.inf
        self._focused = True
        self.trainer = BackgroundTrainer()
        self.sequential = SequentialSession()
        self._now = 0.0
        self._training_demo = np.zeros((0, 7))
        if self.designer is not None:
            if self.designer["main_puck"] is None:
                first = singles(main)[0]
                self.designer["main_puck"] = first["puck"] if first["kind"] == "puck" else 1
            if self.designer["name"] is None:
                self.designer["name"] = name

    # -- the behaviour in play ----------------------------------------------------------------

    def _use(self, behavior: Behavior | None) -> None:
        """Play ``behavior`` from here on (a fresh reactor, started at the main's next pose)."""
        self.behavior = behavior
        self.reactor = Reactor(behavior, self.table) if behavior is not None else None

    # -- the engine step ------------------------------------------------------------------------

    def step(self, frame: Frame) -> tuple[CharacterState, ...]:
        self._now = frame.t if self.clock is None else self.clock()
        self.board.begin(frame)
        out = self._step(frame)
        c = out[0]
        self.board.post(self.name, Posted(c.x, c.y, c.heading, c.size, c.valid))
        return out

    def _step(self, frame: Frame) -> tuple[CharacterState, ...]:
        if self.designer is not None:
            self._now = frame.t
            self._poll_training()
            self._designer_commands(frame)
            if self.mode == "recording":
                if self.designer["sequential"]:
                    return self._record_sequential(frame)
                return (self._record(frame),)
        r = self.reactor
        near = r.pose[:2] if r is not None and r.started else None
        previous = self.mains.chosen
        chosen, pose = self.mains.read(frame, near)
        if pose is not None:
            if r is not None and r.started and chosen != previous and previous >= 0:
                r.rebind(frame.t, *pose)     # another main: its motion starts afresh
            self.last_main = pose
        elif self.last_main is not None:
            pose = self.last_main            # keeps reacting to the main's last pose
        if r is None or pose is None:
            return (self._waiting(frame),)
        r.obstacles = self.board.others(self.name, self.size) if self.keep_apart else []
        x, y, d = r.update(frame.t, *pose)
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
            why = f"waiting for {self.mains.describe()}"
        return self._character(x, y, d, False, self._label(frame, why))

    def _label(self, frame: Frame, status: str = "") -> str:
        if self._now < self._message_until:
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
        self._message, self._message_until = message, self._now + MESSAGE_S

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
        if self.designer["sequential"]:
            self._toggle_sequential()
            return
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

    # sequential training (paper 3.1): the main take first, then the reactor against its
    # playback (behaviors.puppet_master.sequential)

    def _toggle_sequential(self) -> None:
        if self.mode == "trying":
            behavior, self.behavior_name = self._previous
            self._use(behavior)
        self.pending = None
        phase = self.sequential.toggle(self._now)
        if phase == "done":
            self._train_sequential()
            return
        self.mode = "recording" if phase in ("main", "ready", "react") else "idle"
        if phase == "idle":
            self._say("main take too short: R to record the main")

    def _train_sequential(self) -> None:
        try:
            demo = self.sequential.demonstration()
        except InputError as exc:
            self.mode = "idle"
            self._say(f"cannot train: {exc}")
            return
        self._train_take(demo)

    def _record_sequential(self, frame: Frame) -> tuple[CharacterState, ...]:
        seq = self.sequential
        m = frame.puck(self.designer["main_puck"])
        r = frame.puck(self.designer["react_puck"])
        ghost = seq.record(frame.t, None if m is None else (m.x, m.y, m.angle),
                           None if r is None else (r.x, r.y, r.angle))
        if seq.phase == "done":                # the playback ended: the take is complete
            self._train_sequential()
        status = {"main": f"recording the main {seq.seconds():.1f} s, R stop",
                  "ready": "main recorded: R plays it back and records the reaction",
                  "react": f"reacting to the playback {seq.seconds():.1f} s, R stop",
                  }.get(seq.phase, "training the take")
        out = []
        if r is not None:
            out.append(self._character(r.x, r.y, r.angle, True, status + self._selection()))
        else:
            x0, y0, x1, y1 = self.table
            out.append(self._character((x0 + x1) / 2, (y0 + y1) / 2, 0.0, False,
                                       status + self._selection()))
        if ghost is not None:                  # the played-back main, drawn for the designer
            out.append(CharacterState(f"{self.name}.main", *ghost, kind="playback",
                                      size=self.size, color=self.color, valid=True,
                                      label="playback"))
        return tuple(out)

    def take_array(self) -> np.ndarray:
        """The recorded take as a demonstration (n, 7), times from 0."""
        a = np.array(self.take, dtype=float).reshape(-1, 7)
        if a.size:
            a[:, 0] -= a[0, 0]
        return a

    def _train_take(self, demo: np.ndarray | None = None) -> None:
        demo = self.take_array() if demo is None else demo
        secs = float(demo[-1, 0]) if len(demo) else 0.0
        need = self.designer["min_seconds"]
        self.mode = "idle"
        if secs < need:
            self._say(f"take too short ({secs:.1f} s of both pucks, needs {need:g} s): R to record")
            return
        rate = self.rate_hz or (self.behavior.params.rate_hz if self.behavior else 40.0)
        window = self.behavior.params.window if self.behavior else 40
        params = {"rate_hz": rate, "window": window}
        if self.designer.get("background_training", False):
            self.trainer.start(demo, params, self.table)       # off the hot path
            self._training_demo = demo
            self._say(f"training {secs:.1f} s take...")
            return
        try:
            behavior = Behavior.train(demo, **params)
        except InputError as exc:
            self._say(f"cannot train: {exc}")
            return
        self._trained(behavior, Reactor(behavior, self.table), demo)

    def _poll_training(self) -> None:
        """Swap in a behaviour trained in the background, between ticks."""
        done = self.trainer.poll()
        if done is None or self.mode == "recording":   # a new take makes the old one moot
            return
        behavior, reactor, error = done
        if error is not None or behavior is None or reactor is None:
            self._say(f"cannot train: {error}")
            return
        self._trained(behavior, reactor, self._training_demo)

    def _trained(self, behavior: Behavior, reactor: Reactor, demo: np.ndarray) -> None:
        self.pending = behavior
        self.pending_demo = demo
        self._previous = (self.behavior, self.behavior_name)
        self.behavior, self.reactor = behavior, reactor
        self.behavior_name = "new take"
        self.mode = "trying"
        self._message_until = -math.inf

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


def _delayed(options: dict, ctx: BuildContext) -> set[str]:
    """Characters this engine reads from the previous tick: Puppet Master engines listed at or
    after it, or bound back to it (a mutual pair). Any other bound character must be made by
    an engine listed earlier."""
    engines = ctx.config.get("engines", []) if isinstance(ctx.config, dict) else []
    names = [e.get("name") for e in engines]
    mine = names.index(options["name"]) if options["name"] in names else len(names)
    delayed = set()
    for name in bound_characters(options["main"]):
        k = names.index(name) if name in names else -1
        other = engines[k] if k >= 0 else {}
        is_pm = other.get("kind") == "puppet_master"
        back = is_pm and options["name"] in bound_characters(other.get("main", {"kind": "x"}))
        if k < 0 or (k >= mine and not is_pm):
            where = f"engines[{mine}].main" if mine < len(names) else "main"
            raise PuppetMasterError(
                f"{where}: character {name!r} is not made by an engine listed before "
                f"{options['name']!r} (a puppet_master engine may also be listed after it or "
                "react back: it is then read one tick old)")
        if k >= mine or back:
            delayed.add(name)
    return delayed


def build(options: dict, ctx: BuildContext) -> PuppetMasterEngine:
    delayed = _delayed(options, ctx)
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
                              options["rate_hz"], board=shared_board(ctx.shared),
                              delayed=delayed, keep_apart=options["keep_apart"])
