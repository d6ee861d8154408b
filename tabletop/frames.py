"""The shared vocabulary of the frame bus: immutable value types and the three protocols.

Units (see DESIGN.md): table metres (origin at calibrated corner 0, x along the long edge, y along
the short edge), angles in radians counter-clockwise from +x wrapped to (-pi, pi], time in seconds
from ``time.monotonic()``. Image and projector pixels are x right, y down.

This module imports nothing else of the project but :class:`~tabletop.errors.InputError` (kept
numpy-free there); ``tracking``, ``calibration`` and ``behaviors`` may import it.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Literal, Mapping, Protocol, runtime_checkable

import numpy as np

from tabletop.errors import InputError  # noqa: F401  (every layer imports it from here too)

PuckState = Literal["seen", "coasting"]

MAX_POSITION_M = 1000.0   # m: no table position is further from the origin; a demonstration
# row at 1e300 m (a damaged file) was trained with only numpy's overflow warning
MAX_MARKER_ID = 1_000_000  # largest puck (marker) id read from the serial and TUIO inputs
MAX_FEATURE = 1e100       # largest magnitude of a followed feature (a stream's values have no
# known units): the action follower squares and sums differences over its window; one sample of
# 1e160 made its probabilities NaN and then stopped 'tabletop follow' with an IndexError (1e150
# and less followed on; a window of 1e100 samples squared stays far within float64)


def wrap_angle(a: float) -> float:
    """Wrap an angle in radians to (-pi, pi]."""
    w = math.remainder(a, math.tau)
    return math.pi if w == -math.pi else w


def wrap_angles(a: np.ndarray) -> np.ndarray:
    """Vectorised :func:`wrap_angle` for arrays of radians."""
    w = np.remainder(np.asarray(a, dtype=float) + np.pi, 2.0 * np.pi) - np.pi
    return np.where(w <= -np.pi, np.pi, w)


def _frozen_array(a: np.ndarray | None) -> np.ndarray | None:
    if a is None:
        return None
    out = np.array(a, dtype=float, copy=True)
    out.flags.writeable = False
    return out


@dataclass(frozen=True, slots=True)
class PuckMeasurement:
    """One marker seen by a source at time ``t`` (seconds): position in table metres, angle rad.

    ``quality`` in 0..1 (1 = confident). ``vx``, ``vy`` (m/s) and ``omega`` (rad/s) are the
    velocity the source itself measured (a TUIO sender's X, Y, A), NaN when it measured none
    (the tracker then estimates it from the positions).
    """

    id: int
    x: float
    y: float
    angle: float
    t: float
    quality: float = 1.0
    vx: float = math.nan
    vy: float = math.nan
    omega: float = math.nan


@dataclass(frozen=True, slots=True)
class Puck:
    """A tracked puck on the table.

    x, y: metres; angle: radians; vx, vy: m/s; omega: rad/s. ``state`` is ``"seen"`` when this
    tick carries a measurement and ``"coasting"`` while the puck is predicted through an occlusion.
    ``raw_x``, ``raw_y``, ``raw_angle`` are the last measured (unsmoothed) pose.
    """

    id: int
    x: float
    y: float
    angle: float
    vx: float = 0.0
    vy: float = 0.0
    omega: float = 0.0
    state: PuckState = "seen"
    raw_x: float = math.nan
    raw_y: float = math.nan
    raw_angle: float = math.nan


@dataclass(frozen=True, slots=True)
class Touch:
    """A finger (or cursor) on the table: id, position in metres, velocity in m/s."""

    id: int
    x: float
    y: float
    vx: float = 0.0
    vy: float = 0.0


@dataclass(frozen=True, slots=True)
class CharacterState:
    """What an engine wants drawn for one character this tick.

    x, y: metres; heading: radians; ``size``: body length in metres. ``points`` (N x 2, table
    metres) and ``bones`` (pairs of indices into points) describe an articulated figure to draw
    as segments; ``progress`` (0..1) and ``action`` name what an action-following engine plays;
    ``valid`` is False while the engine has nothing trustworthy to show (the view dims it).
    ``label`` is a short status text for the operator overlay. ``hints`` (action, probability,
    progress) and ``hint_points`` (N x 2, table metres, the likeliest one's pose) are what an
    action-following engine already suspects before anything drives the character: the view may
    draw them faintly. ``look_at`` (x, y, metres) is
    what the character attends to (a reactor's main puck): the view turns its eyes there.
    ``facing``: for a figure drawn as a virtual camera sees it (a touch-posed humanoid at its
    viewpoint), where its head faces in that view, a unit vector (x, y along the table as the
    points lie, then toward the viewer): its face is drawn as seen, one eye in profile and none
    from behind; None for figures seen from above.
    """

    name: str
    x: float
    y: float
    heading: float
    kind: str = "reactor"
    size: float = 0.08
    color: tuple[int, int, int] = (240, 170, 60)
    points: np.ndarray | None = None
    bones: tuple[tuple[int, int], ...] = ()
    progress: float | None = None
    action: str | None = None
    valid: bool = True
    label: str = ""
    hints: tuple[tuple[str, float, float], ...] = ()
    hint_points: np.ndarray | None = None
    look_at: tuple[float, float] | None = None
    facing: tuple[float, float, float] | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "points", _frozen_array(self.points))
        object.__setattr__(self, "hint_points", _frozen_array(self.hint_points))


@dataclass(frozen=True, slots=True)
class SourceHealth:
    """A source's health for the operator overlay: ok, a short message, and the age (s) of its
    newest observation (inf when it has none)."""

    name: str
    ok: bool
    message: str = ""
    age: float = math.inf


@dataclass(frozen=True, slots=True)
class Observation:
    """The newest data a source holds, stamped with its capture time ``t`` (monotonic seconds).

    A source fills what it has: puck measurements (table metres), touches, named motion-capture
    streams (1-D float arrays), and for cameras optionally the image it measured (kept for the
    view and the recorder's snapshots, never required downstream). ``seq`` rises by one per new
    observation of that source. ``removed`` lists puck ids the source says have left (a TUIO
    sender's ``alive``): the tracker drops them at once instead of coasting them.
    ``held``: nothing new came for a while and ``t`` is a stamp that moves the frame clock on
    (a network state held as of ``t``), not a capture time (no capture-to-render latency).
    """

    source: str
    t: float
    seq: int
    pucks: tuple[PuckMeasurement, ...] = ()
    touches: tuple[Touch, ...] = ()
    streams: Mapping[str, np.ndarray] = field(default_factory=dict)
    image: np.ndarray | None = None
    complete: bool = True
    removed: tuple[int, ...] = ()
    held: bool = False


@dataclass(frozen=True, slots=True)
class Frame:
    """One tick of the bus. ``t``: capture time of its newest input (monotonic seconds);
    ``seq``: tick number from 0. ``commands`` are operator commands (key presses, markers) that
    arrived since the previous tick, e.g. ``"designer.record"``. ``focus`` names the designer
    target those commands address (an engine name, or ``"ENGINE/PART"`` for an engine with
    several, e.g. a MOP character); None when nothing is selected, and then a lone designer
    engine takes the commands. ``status`` tells the view what the installation is doing:
    ``""`` (live), ``"attract"`` (nobody at the table: scripted pucks play) or ``"one_moment"``
    (an input that was working has vanished and is reconnecting: show the calm waiting screen).
    ``consumed``: what a frame filter took out of the frame before the engines, by filter (the
    studio's ``{"pucks": control-marker pucks, "commands": the commands it was given}``); a
    recording keeps it so a replay can run that filter again on the same inputs.
    """

    seq: int
    t: float
    pucks: tuple[Puck, ...] = ()
    touches: tuple[Touch, ...] = ()
    streams: Mapping[str, np.ndarray] = field(default_factory=dict)
    characters: tuple[CharacterState, ...] = ()
    commands: tuple[str, ...] = ()
    health: tuple[SourceHealth, ...] = ()
    focus: str | None = None
    status: str = ""
    consumed: Mapping[str, Mapping] = field(default_factory=dict)

    def __post_init__(self) -> None:
        frozen = {k: _frozen_array(v) for k, v in dict(self.streams).items()}
        object.__setattr__(self, "streams", MappingProxyType(frozen))

    def puck(self, puck_id: int) -> Puck | None:
        """The puck with this id, or None."""
        for p in self.pucks:
            if p.id == puck_id:
                return p
        return None

    def character(self, name: str) -> CharacterState | None:
        """The character with this name, or None."""
        for c in self.characters:
            if c.name == name:
                return c
        return None

    def with_characters(self, characters: tuple[CharacterState, ...]) -> "Frame":
        """A copy of this frame with ``characters`` appended to its characters."""
        # each field copied as it is, not through __init__ (dataclasses.replace): its streams
        # are frozen already and shared, not copied again. Once per engine a tick; in the
        # Puppet Master plugin tests 85k calls, 5.5 us each through replace (streams copied)
        new = object.__new__(type(self))
        for name in _FRAME_FIELDS:
            _set(new, name, getattr(self, name))
        _set(new, "characters", self.characters + tuple(characters))
        return new


_FRAME_FIELDS = tuple(f.name for f in dataclasses.fields(Frame))
_set = object.__setattr__


@runtime_checkable
class Source(Protocol):
    """An input: opened once, polled each tick for its newest observation, closed at the end.

    ``latest`` never blocks and never raises: a source that lost its device returns its last
    observation (or None) and reports it in ``health``.
    """

    name: str

    def open(self) -> None: ...

    def latest(self) -> Observation | None: ...

    def health(self) -> SourceHealth: ...

    def close(self) -> None: ...


@runtime_checkable
class Engine(Protocol):
    """An algorithm stepped once per tick with the frame so far; returns the characters it drives.

    An engine with a designer mode may also define ``designer_targets() -> tuple[str, ...]``:
    the names the operator's Tab key cycles through (see ``Frame.focus``).
    """

    name: str

    def step(self, frame: Frame) -> tuple[CharacterState, ...]: ...


@runtime_checkable
class Sink(Protocol):
    """Receives every completed frame (view, recorder, OSC out)."""

    name: str

    def consume(self, frame: Frame) -> None: ...

    def close(self) -> None: ...
