"""What a Puppet Master reactor reacts to, and the other reactors it keeps apart from.

A main binding is one of ``{puck: ID}``, ``{touch: ID}``, ``{character: NAME}``,
``{stream: NAME, columns: [X, Y] or [X, Y, DIR]}``, or several of them:

- ``{nearest: [BINDING, ...]}``: the present main nearest to the reactor (another must be
  ``SWITCH_SHARE`` nearer before the reactor turns to it, so two mains at about the same
  distance do not make it flicker between them);
- ``{first: [BINDING, ...]}``: the first present in the list (the config names which main
  counts in which situation: e.g. a visitor's puck when it is on the table, else a character).

A ``character`` binding reads that character in the same tick when its engine is listed
earlier and does not react back (any engine's: a MOP character counts where it stands, whether
an action drives it or not); otherwise (listed later, itself, or a mutual pair) it reads
the character's state of the previous tick from the :class:`Board`, so both of a mutual pair
see each other one tick old, whatever their order, and the run stays reproducible. A
character still waiting for its own main is absent, whatever the order, except to the
characters of a cycle with it (a mutual pair), which start from each other's waiting places.

Every Puppet Master reactor posts its pose to the board; a reactor keeps at least the sum of
both body radii (half the ``size``) from every other reactor. The reactors of an installation
step together at the first Puppet Master engine's step of a tick (puppet_master_together):
each against the others' poses of the previous tick, then their steps' ends and shown poses
are moved apart jointly, so no engine order decides who yields. One that cannot step with them
(it reads a character made later in the tick) keeps apart from the others' latest poses.

Positions in table metres, angles in radians.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from tabletop.frames import Frame
from tabletop.schema import Context, ListOf, Number, Record, Spec, Str

SINGLE_KINDS = ("puck", "character", "touch", "stream")
MANY_KINDS = ("nearest", "first")
TURN_SPEED = 0.02        # m/s: below it a touch or stream main keeps its look direction
SWITCH_SHARE = 0.2       # a nearer main must be this much nearer to take over
BOARD_KEY = "puppet_master.board"


class _Single(Spec):
    """Exactly one of puck, character, touch, stream."""

    default: Any = None

    def describe(self) -> str:
        return ("one of {puck: ID}, {character: NAME}, {touch: ID}, "
                "{stream: NAME, columns: [X, Y] or [X, Y, DIR]}")

    def validate(self, value: Any, path: str, ctx: Context) -> Any:
        if not isinstance(value, dict):
            raise self.wrong_type(value, path, ctx)
        kinds = [k for k in value if k in SINGLE_KINDS]
        if len(kinds) != 1:
            raise ctx.error(path, f"expected exactly one of {', '.join(SINGLE_KINDS)}; got "
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


class MainBinding(Spec):
    """The main character's input: one binding, or ``{nearest: [...]}`` / ``{first: [...]}``."""

    def __init__(self, default: Any = None) -> None:
        self.default = {"kind": "puck", "puck": 1} if default is None else default
        self.doc = "the main character's input"

    def describe(self) -> str:
        return f"{_Single().describe()}, or {{nearest: [...]}} or {{first: [...]}} of them"

    def validate(self, value: Any, path: str, ctx: Context) -> Any:
        if isinstance(value, dict) and any(k in value for k in MANY_KINDS):
            kinds = [k for k in value if k in MANY_KINDS]
            extra = [k for k in value if k not in MANY_KINDS]
            if len(kinds) != 1 or extra:
                raise ctx.error(path, "expected exactly one of nearest, first with a list of "
                                f"mains; got {', '.join(map(str, value))}")
            kind = kinds[0]
            items = ListOf(_Single(), min_len=1).validate(value[kind], f"{path}.{kind}", ctx)
            return {"kind": kind, "mains": items}
        return _Single().validate(value, path, ctx)


def singles(main: dict) -> list[dict]:
    """The single bindings of a main binding."""
    return list(main["mains"]) if main["kind"] in MANY_KINDS else [main]


def bound_characters(main: dict) -> list[str]:
    """Names of the characters a main binding reads."""
    return [b["character"] for b in singles(main) if b["kind"] == "character"]


@dataclass(slots=True)
class Posted:
    """A reactor's pose on the board: metres, radians; ``size`` its body length."""

    x: float
    y: float
    heading: float
    size: float
    valid: bool


class Board:
    """The Puppet Master reactors' poses of this tick and the previous one, shared by every
    engine of one installation (``BuildContext.shared``)."""

    def __init__(self) -> None:
        self.seq: int | None = None
        self.previous: dict[str, Posted] = {}
        self.current: dict[str, Posted] = {}
        # every name's latest pose (this tick's where posted, else the previous one): a new
        # tick leaves it as it is, so others() reads it without merging the two per call
        self._latest: dict[str, Posted] = {}

    def begin(self, frame: Frame) -> None:
        """Called by every engine at the start of its step; the first call of a new tick
        makes this tick's poses the previous ones."""
        if frame.seq != self.seq:
            self.previous.update(self.current)
            self.current = {}
            self.seq = frame.seq

    def post(self, name: str, pose: Posted) -> None:
        """This tick's pose of ``name``."""
        self.current[name] = pose
        self._latest[name] = pose

    def latest(self, name: str) -> Posted | None:
        """This tick's pose if ``name`` has stepped already, else its previous one."""
        return self.current.get(name) or self.previous.get(name)

    def others(self, name: str, size: float) -> list[tuple[float, float, float]]:
        """(x, y, least distance m) of every other posted reactor, at its latest pose."""
        out = [(p.x, p.y, 0.5 * (size + p.size)) for other, p in self._latest.items()
               if p.valid and other != name]
        out.sort()
        return out


def board(shared: dict[str, Any]) -> Board:
    """The installation's board (made on first use)."""
    b = shared.get(BOARD_KEY)
    if b is None:
        b = shared[BOARD_KEY] = Board()
    return b


class MainReader:
    """Reads the main pose of one reactor from a frame and the board; keeps the look of
    inputs without one (touches, two-column streams) and which of several mains is in use."""

    def __init__(self, main: dict, delayed: set[str], board_: Board,
                 cycle: set[str] | None = None) -> None:
        self.main, self.delayed, self.board = main, delayed, board_
        self.cycle = set(cycle or ())   # delayed characters that count while they wait
        self.items = singles(main)
        self._dir = [0.0] * len(self.items)
        self._last: list[tuple[float, float, float] | None] = [None] * len(self.items)
        self._last_t = -math.inf
        self.chosen = -1                 # index into items of the main in use
        self._puck = main["puck"] if main["kind"] == "puck" else None

    def describe(self) -> str:
        """What the reactor waits for, for the overlay."""
        if self.main["kind"] in MANY_KINDS:
            return f"{self.main['kind']} of {len(self.items)} mains"
        return f"{self.main['kind']} {self.main[self.main['kind']]}"

    def _one(self, k: int, frame: Frame) -> tuple[float, float, float] | None:
        m = self.items[k]
        kind = m["kind"]
        if kind == "puck":
            p = frame.puck(m["puck"])
            return None if p is None else (p.x, p.y, p.angle)
        if kind == "character":
            name = m["character"]
            if name in self.delayed:      # a waiting reactor counts in a cycle (a mutual
                c = self.board.previous.get(name)   # pair would wait for each other), no other
                if c is None or not (c.valid or name in self.cycle):
                    return None
                return c.x, c.y, c.heading
            ch = frame.character(name)    # another engine's character (a MOP one) stands
            if ch is None or not (ch.valid or ch.kind != "reactor"):   # where it is drawn,
                return None                                   # an action driving it or not
            return ch.x, ch.y, ch.heading
        if kind == "touch":
            for tc in frame.touches:
                if tc.id == m["touch"]:
                    return self._moving(k, tc.x, tc.y, tc.vx, tc.vy)
            return None
        a = frame.streams.get(m["stream"])
        cols = m["columns"]
        if a is None or a.ndim != 1 or max(cols) >= a.size:
            return None
        vals = [float(a[c]) for c in cols]
        if not all(math.isfinite(v) for v in vals):
            return None
        if len(vals) == 3:
            return vals[0], vals[1], math.remainder(vals[2], math.tau)
        last = self._last[k]
        if last is not None and frame.t > self._last_t:
            dt = frame.t - self._last_t
            return self._moving(k, vals[0], vals[1], (vals[0] - last[0]) / dt,
                                (vals[1] - last[1]) / dt)
        return vals[0], vals[1], self._dir[k]

    def _moving(self, k: int, x: float, y: float, vx: float,
                vy: float) -> tuple[float, float, float]:
        if math.hypot(vx, vy) > TURN_SPEED:
            self._dir[k] = math.atan2(vy, vx)
        return x, y, self._dir[k]

    def read(self, frame: Frame, near: tuple[float, float] | None) -> tuple[int, Any]:
        """(index of the main in use, its pose or None) this frame; ``near`` is the reactor's
        position (for ``nearest``)."""
        if self._puck is not None:           # one puck (the usual binding): the same result
            p = frame.puck(self._puck)       # as the general path below, without its lists
            if frame.t > self._last_t:
                self._last_t = frame.t
            if p is None:
                return self.chosen, None
            pose = (p.x, p.y, p.angle)
            if not (math.isfinite(pose[0]) and math.isfinite(pose[1])
                    and math.isfinite(pose[2])):
                return self.chosen, None
            self._last[0] = pose
            self.chosen = 0
            return 0, pose
        poses = []
        isfinite = math.isfinite
        for k in range(len(self.items)):
            pose = self._one(k, frame)
            if pose is not None and not (isfinite(pose[0]) and isfinite(pose[1])
                                         and isfinite(pose[2])):
                pose = None                  # a broken measurement counts as absent
            poses.append(pose)
            if pose is not None:
                self._last[k] = pose
        self._last_t = max(self._last_t, frame.t)
        present = [k for k, p in enumerate(poses) if p is not None]
        if not present:
            return self.chosen, None
        if self.main["kind"] == "nearest" and near is not None:
            dist = {k: math.hypot(poses[k][0] - near[0], poses[k][1] - near[1]) for k in present}
            best = min(present, key=lambda k: (dist[k], k))
            if self.chosen in dist and dist[best] > (1.0 - SWITCH_SHARE) * dist[self.chosen]:
                best = self.chosen
            self.chosen = best
        else:
            self.chosen = present[0]
        return self.chosen, poses[self.chosen]
