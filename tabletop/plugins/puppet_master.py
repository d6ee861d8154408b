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

With ``designer.enabled`` the engine is a target of the designer studio (``tabletop.studio``):
record a take with the two pucks, train it at once, try it, keep it in the library (never over
an existing behaviour: ``lover-2``, ``lover-3``...) or redo it.

The reactor steps at the behaviour's rate (40 Hz) on the frames' own times. While its main is
absent it keeps reacting to the main's last pose; before the main was ever seen it waits (drawn
dimmed). A main bound to a character reads that character in the same tick when its engine
is listed earlier; a Puppet Master engine listed later, or one reacting back (a mutual pair),
is read one tick old (see :mod:`tabletop.plugins.puppet_master_mains`).
"""

from __future__ import annotations

import functools
import logging
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable

from tabletop import library
from tabletop.frames import CharacterState, Frame, InputError
from tabletop.kiosk.watch import tree_signature
from tabletop.registry import BuildContext
from tabletop.plugins.puppet_master_mains import (Board, MainBinding, MainReader, Posted,
                                                  bound_characters, singles)
from tabletop.plugins.puppet_master_mains import board as shared_board
from tabletop.plugins.puppet_master_together import Together, group_of
from tabletop.schema import Bool, Context, FilePath, ListOf, Number, Optional_, Record, Str

log = logging.getLogger("tabletop")

if TYPE_CHECKING:   # the engine (its compiled kernels) loads when an engine is built, so that
    # validating a config (the kiosk supervisor does) does not load them (bench/cold_start.py)
    from behaviors.puppet_master.engine import Behavior, Reactor


class PuppetMasterError(InputError):
    """A Puppet Master engine cannot be built as configured; the message names what and where."""


DESIGNER = Record({
    "enabled": Bool(False, doc="training from the table"),
    "main_puck": Optional_(Number(integer=True, lo=0),
                           doc="the designer's main puck (default: main's puck, else 1)"),
    "react_puck": Number(2, integer=True, lo=0, doc="the designer's reactor puck"),
    "record_marker": Optional_(Number(integer=True, lo=0),
                               doc="marker id that records while it is on the table"),
    "library": FilePath("library", must_exist=False, kind="dir", embed=True,
                        doc="folder the kept behaviours are saved in"),
    "name": Optional_(Str(), doc="name of kept behaviours (default: the engine's name)"),
    "min_seconds": Number(2.0, lo=0.1, hi=300.0, unit="seconds",
                          doc="shortest take that is trained"),
    "sequential": Bool(False, doc="one hand: R records the main, R stops, R plays it back "
                       "and records the reactor against it (paper 3.1)"),
    "background_training": Bool(True, doc="train in a worker thread, swapped in between "
                                "ticks 0.15 s after the stop (false: within the stop's tick)"),
})


def designer_main_puck(main: dict) -> int:
    """The designer's main puck where its config names none: the engine's first main binding's
    puck, or puck 1 where that binding is no puck."""
    first = singles(main)[0]
    return first["puck"] if first["kind"] == "puck" else 1


def _check_designer(opts: dict, path: str, ctx: Context) -> None:
    """A designer whose take cannot be recorded or kept is refused at load, not at the first
    take: the reactor puck is the main puck (a take in parts may use one puck for both), the
    record marker is one of the two pucks (the studio takes a marker off the table before the
    engines see it), or the library cannot be made."""
    d = opts["designer"]
    where = f"{path}.designer" if path else "designer"
    main = d["main_puck"] if d["main_puck"] is not None else designer_main_puck(opts["main"])
    if d["react_puck"] == main and not d["sequential"]:
        raise ctx.error(f"{where}.react_puck", f"puck {main} is also the designer's main puck; "
                        "give the reactor another puck (or sequential: true to play both parts "
                        "with one)")
    for role, puck in (("main", main), ("reactor", d["react_puck"])):
        if d["record_marker"] == puck:
            raise ctx.error(f"{where}.record_marker", f"{puck} is the designer's {role} puck; "
                            "the record marker needs a marker id of its own")
    from tabletop.studio.session import unusable
    why = unusable(d["library"])
    if why:
        raise ctx.error(f"{where}.library", f"cannot hold kept behaviours: {why}")


def _check(opts: dict, path: str, ctx: Context) -> None:
    where = f"{path}.behavior" if path else "behavior"
    if opts["designer"]["enabled"]:
        _check_designer(opts, path, ctx)
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
    "size": Number(0.08, unit="metres", lo=0.005, hi=2.0, doc="body length, metres"),
    "keep_apart": Bool(True, doc="keep at least the body sizes away from other reactors"),
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
                 rate_hz: float | None = None,
                 board: Board | None = None, delayed: set[str] | None = None,
                 keep_apart: bool = True, cycle: set[str] | None = None,
                 group: Together | None = None) -> None:
        self.name, self.main, self.table = name, main, (0.0, 0.0, float(table[0]), float(table[1]))
        self.board = board if board is not None else Board()
        self.group = group          # the engines stepped together (puppet_master_together)
        if group is not None:
            group.join(self)
        self.mains = MainReader(main, set(delayed or ()), self.board, set(cycle or ()))
        self.keep_apart = keep_apart
        self.color, self.size, self.rate_hz = color, size, rate_hz
        self.designer = designer if designer and designer["enabled"] else None
        self.behavior_name = behavior_name
        self.behavior: Behavior | None = None
        self.reactor: Reactor | None = None
        self.play(behavior, behavior_name)
        self.last_main: tuple[float, float, float] | None = None
        # where the character was last drawn (x, y m, heading rad): a studio take holds it there
        # until the reactor puck is seen
        self.last_pose: tuple[float, float, float] | None = None
        # the studio's characters while recording (the first is this one), replacing the reaction
        self.hold: Callable[[Frame], tuple[CharacterState, ...]] | None = None
        self.note = ""                                               # the studio's label
        if self.designer is not None:
            if self.designer["main_puck"] is None:
                self.designer["main_puck"] = designer_main_puck(main)
            if self.designer["name"] is None:
                self.designer["name"] = name

    # -- the behaviour in play ----------------------------------------------------------------

    def play(self, behavior: Behavior | None, name: str = "",
             reactor: Reactor | None = None) -> None:
        """Play ``behavior`` from here on (a fresh reactor, started at the main's next pose;
        ``reactor``: one already built for it, e.g. in a training worker)."""
        self.behavior, self.behavior_name = behavior, name
        if reactor is None and behavior is not None:
            from behaviors.puppet_master.engine import Reactor
            reactor = Reactor(behavior, self.table)
        self.reactor = reactor

    # -- the engine step ------------------------------------------------------------------------

    def step(self, frame: Frame) -> tuple[CharacterState, ...]:
        self.board.begin(frame)
        out = self.group.step(self, frame) if self.group is not None else None
        if out is None:
            out = self._step(frame)
        c = out[0]
        self.last_pose = (c.x, c.y, c.heading)
        self.board.post(self.name, Posted(c.x, c.y, c.heading, c.size, c.valid))
        return out

    def prepare(self, frame: Frame) -> tuple[str, Any]:
        """The group's step (puppet_master_together): ("react", the main pose), ("done",
        this tick's characters: waiting) or ("alone", None): a take steps at its own place."""
        if self.hold is not None:
            return "alone", None
        pose = self._main_pose(frame)
        if self.reactor is None or pose is None:
            return "done", (self._waiting(frame),)
        return "react", pose

    def _main_pose(self, frame: Frame) -> tuple[float, float, float] | None:
        """The main pose to react to this tick (the reactor rebound where the main in use
        changed; the main's last pose while it is absent), or None."""
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
        return pose

    def _step(self, frame: Frame) -> tuple[CharacterState, ...]:
        if self.hold is not None:
            return self.hold(frame)
        r = self.reactor
        pose = self._main_pose(frame)
        if r is None or pose is None:
            return (self._waiting(frame),)
        r.obstacles = self.board.others(self.name, self.size) if self.keep_apart else []
        x, y, d = r.update(frame.t, *pose)
        return (self.reacting(x, y, d, pose),)

    def reacting(self, x: float, y: float, d: float,
                 main: tuple[float, float, float]) -> CharacterState:
        """The reacting character drawn at (x, y) heading ``d``, looking at its main."""
        return self.character(x, y, d, True, self._label(), main[:2])

    def character(self, x: float, y: float, d: float, valid: bool, label: str,
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
        return self.character(x, y, d, False, self.note or why)

    def _label(self) -> str:
        if self.note:
            return self.note
        status = f"playing {self.behavior_name or 'behaviour'}"
        if self.reactor is not None and self.reactor.started:
            status += f", coherence {self.reactor.coherence_share:.0%}"
        return status


def _check_kept_name(options: dict, ctx: BuildContext) -> None:
    """A designer's kept behaviours are folders named ``designer.name`` (default: the engine's
    name): a name no folder may have is refused at load, not at the first keep of a take."""
    d = options["designer"]
    if not d["enabled"]:
        return
    own = d["name"] is not None
    try:
        library.check_name(d["name"] if own else options["name"])
    except library.LibraryError as exc:
        raise PuppetMasterError(
            f"{ctx.where(options, 'designer.name' if own else 'name')}: kept behaviours are "
            f"saved under this name{'' if own else ' (give designer.name for another)'}: "
            f"{exc}") from None


def _reads_back(name: str, own: str, engines: list[dict]) -> bool:
    """Whether the Puppet Master engine ``name`` reacts, through its main bindings and theirs,
    to the engine ``own``: the two are in one cycle (a mutual pair, or A -> B -> C -> A; an
    engine bound to itself is refused by :func:`_delayed`)."""
    made = {e.get("name"): e for e in engines if e.get("kind") == "puppet_master"}
    seen, todo = set(), [name]
    while todo:
        e = made.get(todo.pop())
        if e is None or e["name"] in seen:
            continue
        seen.add(e["name"])
        bound = bound_characters(e.get("main", {"kind": "x"}))
        if own in bound:
            return True
        todo += bound
    return False


def _characters_of(engine: dict) -> list[str]:
    """The names of the characters a config engine entry makes: a MOP engine's characters,
    any other engine's own name."""
    if engine.get("kind") == "mop":
        return [str(c.get("name")) for c in engine.get("characters") or ()
                if isinstance(c, dict)]
    return [str(engine.get("name"))]


def _no_maker(name: str, engines: list[dict]) -> str:
    """Why ``name`` is no character: the likely one, and the characters the engines make
    (with their engine where its own name is not theirs: a MOP engine's)."""
    import difflib
    groups, every = [], []
    for e in engines:
        engine, chars = str(e.get("name")), _characters_of(e)
        every += chars
        if chars == [engine]:
            groups.append(engine)
        elif chars:
            groups.append(f"{', '.join(chars)} (engine {engine!r})")
    close = difflib.get_close_matches(name, every, n=1)
    return (f"no engine makes a character named {name!r}"
            + (f" (did you mean {close[0]!r}?)" if close else "")
            + f"; the characters are {', '.join(groups)}")


def binding_problem(options: dict, engines: list[dict], mine: int) -> str:
    """Why the main of the Puppet Master engine ``options`` (``engines[mine]`` of the config's
    ``engines``) cannot be read, or "": a character of its own, one no engine makes, or one
    made by an engine listed after it that is no Puppet Master engine. Said at the config's
    load, so a config edit binding one is refused with the installation running on (checked
    at the build only, the running installation was torn down and its previous config built
    again)."""
    made = [_characters_of(e) for e in engines]
    for name in bound_characters(options["main"]):
        if name == options["name"]:     # it would chase its own last pose (nearest: always)
            return f"character {name!r} is this engine's own; a reactor cannot react to itself"
        k = next((i for i, chars in enumerate(made) if name in chars), -1)
        if k < 0:
            return _no_maker(name, engines)
        if k >= mine and engines[k].get("kind") != "puppet_master":
            return (f"character {name!r} is not made by an engine listed before "
                    f"{options['name']!r} (a puppet_master engine may also be listed after it "
                    "or react back: it is then read one tick old)")
    return ""


def _delayed(options: dict, ctx: BuildContext) -> tuple[set[str], set[str]]:
    """Characters this engine reads from the previous tick: Puppet Master engines listed at or
    after it, or bound back to it (a mutual pair); and of those, the ones in a cycle with it,
    which count while they still wait for their own mains (drawn at the table's centre), as
    a cycle would otherwise wait for itself for ever. Any other waiting character is absent,
    as one listed earlier is: read while it waited, a reactor bound to an engine listed after
    it played against that placeholder at the centre of the table. Any other bound character
    must be made by an engine listed earlier."""
    engines, names, mine = ctx.engines(options)
    why = binding_problem(options, engines, mine)
    if why:
        raise PuppetMasterError(f"{ctx.where(options, 'main')}: {why}")
    delayed, cycle = set(), set()
    made = [_characters_of(e) for e in engines]
    for name in bound_characters(options["main"]):
        k = next(i for i, chars in enumerate(made) if name in chars)
        other = engines[k]
        back = (other.get("kind") == "puppet_master"
                and options["name"] in bound_characters(other.get("main", {"kind": "x"})))
        if k >= mine or back:
            delayed.add(name)
            if _reads_back(name, options["name"], engines):   # back: its first step
                cycle.add(name)
    return delayed, cycle


def build(options: dict, ctx: BuildContext) -> PuppetMasterEngine:
    from behaviors.puppet_master import kept
    _check_kept_name(options, ctx)
    delayed, cycle = _delayed(options, ctx)
    behavior, bname, read, problem, played = None, "", None, "", None
    recorded = ctx.shared.get("started_without", {})
    if options["behavior"] is not None and options["name"] in recorded \
            and not ctx.shared.get("kiosk_start"):
        # a replay of a kiosk start that ran it without its behaviour runs it so, whatever the
        # folder holds now (a file completed since, or too large to be carried)
        read = tree_signature(Path(options["behavior"]))
        problem = str(recorded[options["name"]])
    elif options["behavior"] is not None:
        read = tree_signature(Path(options["behavior"]))   # its reloader's first baseline
        try:
            stored = library.load_behavior(options["behavior"])
            params = dict(stored.parameters)
            if options["rate_hz"] is not None:
                params["rate_hz"] = options["rate_hz"]
            try:
                behavior = kept.train(stored.demonstration, **params)   # (a rebuild's)
            except InputError as exc:   # its parameters or demonstration: named with its key
                said = library.parameter_refused(
                    stored, exc, () if options["rate_hz"] is None else ("rate_hz",))
                raise PuppetMasterError(f"{ctx.where(options, 'behavior')}: "
                                        f"{said or f'{stored.folder}: {exc}'}") from None
            bname = stored.name
            # what it was trained from, encoded only if a config edit's rebuild keeps it playing
            played = (behavior, functools.partial(library.recorded_source, bname, params,
                                                  stored.demonstration))
        except InputError as exc:
            if not ctx.shared.get("kiosk_start"):
                if isinstance(exc, PuppetMasterError):
                    raise
                # a corrupt or cut demonstration.csv, named at the config's key as a corrupt
                # behavior.yaml is (it named the file and line alone)
                raise PuppetMasterError(f"{ctx.where(options, 'behavior')}: {exc}") from None
            problem = _start_without(options["name"], exc,
                                     options["name"] in ctx.shared.get("keeping", ()))
    designer = dict(options["designer"])
    lib = Path(designer["library"]).expanduser()
    designer["library"] = lib if lib.is_absolute() else Path(ctx.base) / lib
    engine = PuppetMasterEngine(options["name"], options["main"], ctx.table, behavior, bname,
                                tuple(options["color"]), options["size"], designer,
                                options["rate_hz"], board=shared_board(ctx.shared),
                                delayed=delayed, keep_apart=options["keep_apart"],
                                cycle=cycle,
                                group=group_of(options, ctx, delayed, _characters_of))
    engine.folder = options["behavior"]   # the studio reloads it when it changes on disk
    engine.folder_read = read
    engine.problem = problem
    engine.played_from = played   # (behaviour, its recorded source): kept by a bad edit's rebuild
    if problem:
        engine.note = f"bad file, no behaviour until it is fixed: {problem}"
    return engine


def _start_without(name: str, exc: InputError, kept: bool = False) -> str:
    """A kiosk's start (a reboot, a restart by its supervisor) whose behaviour folder holds a
    corrupt or half-written file: the character ``name`` starts without a behaviour, and the
    table with the rest, rather than the kiosk restarting for ever on the same refusal (the
    last good config names the same folder); its reloader plays the folder once it is fixed.
    Returns the refusal (one line naming the file), logged and shown in the status; not logged
    when ``kept`` (a config edit's rebuild: the behaviour read before plays on, as logged by
    :func:`tabletop.studio.reloader.keep_playing`)."""
    problem = str(exc)
    if not kept:
        log.error("%s starts without its behaviour until the file is fixed: %s", name, problem)
    return problem
