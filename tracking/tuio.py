"""TUIO 1.1 (``/tuio/2Dobj``, ``/tuio/2Dcur``, ``/tuio/2Dblb``) as pure functions and one state
machine, no sockets: decoded OSC messages in, committed objects out; and frames out as bundles.

Receiving follows the reference client (TUIO11_CPP ``TuioClient``): ``source`` names the
sender, for this packet and the later ones from its UDP address until another ``source`` (else
the packet's UDP address does; a name is kept apart per IP address, so two machines
sending one name never mix), ``alive`` lists the live session ids, ``set`` stages one entity, and
``fseq`` commits that profile: entities in ``alive`` take their staged values, the others leave.
As in the reference clients, which read message by message, what a UDP address stages for a
profile waits for that profile's ``fseq`` across packets: a frame sent as one bundle, or as
single messages (``source``, ``alive``, ``set``..., ``fseq``, one datagram each, as python-osc's
``send_message`` sends them), commits alike. A frame whose ``alive`` is followed by another
``alive`` before its ``fseq`` (its fseq lost: the second ``alive`` begins a new frame, the lost
one's sets dropped), or left unfinished for ``restart_s``, is counted ``no_fseq``. An ``fseq`` below
the sender's current one is late and its bundle is dropped, unless the gap is over 100 (the sender
restarted) or the sender was silent for ``restart_s``; ``fseq`` <= 0 (-1: a redundant resend) always
commits. Every sender and profile keeps its own state, so several senders never mix. Bad messages
raise :class:`TuioError`, whose ``kind`` names the counter it belongs to; the rest of the packet
still applies.

Units: TUIO positions are 0..1 with y down, angles 0..2pi clockwise on screen, velocities in
those units per second, rotation speed in turns per second. :func:`to_table` and
:func:`from_table` map them to table metres (x * W, (1 - y) * H), angle -a wrapped, as DESIGN.md
states, and back.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Iterable, Sequence

from tabletop.frames import MAX_MARKER_ID, wrap_angle
from tracking.badinput import CountedError
from tracking.osc_codec import encode_bundle, encode_message

MAX_SOURCE = 200   # characters of a sender's source name kept (a longer one is cut)

PROFILES = ("2Dobj", "2Dcur", "2Dblb")
ADDRESSES = {f"/tuio/{p}": p for p in PROFILES}
# s i x y a X Y A m r | s x y X Y m | s x y a w h f X Y A m r
SET_ARGS = {"2Dobj": 10, "2Dcur": 6, "2Dblb": 12}
LATE_GAP = 100            # a larger backwards jump of fseq is a restarted sender
MAX_FSEQ = 2**31 - 1      # fseq is an int32: a sender counts 1 .. MAX_FSEQ, then from 1 again
MAX_ALIVE = 1024          # live entities per sender and profile
MAX_PENDING = 64          # unfinished frames (UDP address and profile) waiting for their fseq,
#                           and UDP addresses whose source name is kept
MAX_COORD = 100.0         # |x|, |y| beyond this (in TUIO units) is refused
MAX_SPEED = 1e6           # |X|, |Y| (TUIO units/s) and |A| (turns/s) beyond this are refused:
# finite doubles near 1.7e308 become infinite once mapped to table metres (x width)
PACKET_LIMIT = 4096       # reference servers split bundles at this size


class TuioError(CountedError):
    """A TUIO message is wrong; ``kind`` is its counter name (wrong_arguments, non_finite,
    out_of_range, unknown_command, too_many, no_fseq, not_alive)."""


@dataclass(frozen=True, slots=True)
class Entity:
    """One TUIO object, cursor or blob in TUIO units. ``class_id`` is the marker id (objects;
    -1 otherwise); ``angle`` radians clockwise (0 for cursors); ``vx``, ``vy`` per second;
    ``rotation`` turns per second."""

    profile: str
    session: int
    class_id: int
    x: float
    y: float
    angle: float = 0.0
    vx: float = 0.0
    vy: float = 0.0
    rotation: float = 0.0


def _int(v: Any, what: str) -> int:
    if isinstance(v, bool) or not isinstance(v, int):
        raise TuioError("wrong_arguments", f"{what} must be an int32, got {type(v).__name__}")
    return v


def _floats(args: Sequence[Any], what: str) -> list[float]:
    """The arguments as finite floats (ints accepted), or TuioError."""
    out = [v if type(v) is float else _as_float(v, what) for v in args]
    if not all(map(math.isfinite, out)):
        raise TuioError("non_finite", f"{what} has {[v for v in out if not math.isfinite(v)]}")
    return out


def _as_float(v: Any, what: str) -> float:
    if isinstance(v, bool) or not isinstance(v, int):
        raise TuioError("wrong_arguments", f"{what} must be floats, got {type(v).__name__}")
    return float(v)


def parse_set(profile: str, args: Sequence[Any]) -> Entity:
    """The arguments after ``set`` of one profile -> :class:`Entity` (raises TuioError)."""
    n = SET_ARGS[profile]
    if len(args) != n:
        raise TuioError("wrong_arguments", f"/tuio/{profile} set takes {n} arguments, "
                                           f"got {len(args)}")
    s = _int(args[0], "session id")
    if profile == "2Dobj":
        c = _int(args[1], "class id")
        if not 0 <= c <= MAX_MARKER_ID:   # the class id is the marker id: a puck id
            raise TuioError("out_of_range", f"/tuio/2Dobj class id {c} of session {s} is not a "
                                            f"marker id 0..{MAX_MARKER_ID}")
        x, y, a, vx, vy, va, _m, _r = _floats(args[2:], "2Dobj set")
    elif profile == "2Dcur":
        c, a, va = -1, 0.0, 0.0
        x, y, vx, vy, _m = _floats(args[1:], "2Dcur set")
    else:
        c = -1
        x, y, a, _w, _h, _f, vx, vy, va, _m, _r = _floats(args[1:], "2Dblb set")
    if abs(x) > MAX_COORD or abs(y) > MAX_COORD:
        raise TuioError("out_of_range", f"/tuio/{profile} position ({x}, {y}) is far off 0..1")
    if max(abs(vx), abs(vy), abs(va)) > MAX_SPEED:
        raise TuioError("out_of_range", f"/tuio/{profile} velocity ({vx}, {vy}, {va}) is beyond "
                                        f"{MAX_SPEED:g} a second")
    return Entity(profile, s, c, x, y, a, vx, vy, va)


def parse_alive(args: Sequence[Any]) -> list[int]:
    if len(args) > MAX_ALIVE:
        raise TuioError("too_many", f"alive lists {len(args)} ids (at most {MAX_ALIVE})")
    return [_int(v, "alive session id") for v in args]


def parse_fseq(args: Sequence[Any]) -> int:
    if len(args) != 1:
        raise TuioError("wrong_arguments", f"fseq takes 1 argument, got {len(args)}")
    return _int(args[0], "fseq")


# ---------------------------------------------------------------------- receiving
@dataclass
class ProfileState:
    """One sender's state of one profile: the committed entities and the frame counter."""

    fseq: int = -1
    committed: dict[int, Entity] = field(default_factory=dict)
    alive: list[int] = field(default_factory=list)
    t: float = -math.inf          # time of the last commit (monotonic s)


@dataclass
class Pending:
    """One UDP address's frame of one profile, staged until its ``fseq``: the sender it names
    (``key``, ``name``), the ``alive`` list (None: none yet), the staged sets and when the frame
    began (monotonic s)."""

    key: str
    name: str
    t: float
    alive: list[int] | None = None
    sets: dict[int, Entity] = field(default_factory=dict)


@dataclass
class Sender:
    """A TUIO sender: one ``source`` name from one IP address, or one UDP address (IP and
    port) when it sends no name. ``name`` is what it is called by (its source name, else its
    address)."""

    key: str
    name: str = ""
    profiles: dict[str, ProfileState] = field(default_factory=dict)
    heard_t: float = -math.inf    # when a bundle of it last committed or came late
    commits: int = 0


class TuioClient:
    """The TUIO 1.1 receiving state of every sender (see the module docstring).

    ``apply(messages, address, t)`` applies the TUIO messages of one packet received at ``t``
    (monotonic s) from ``address`` and returns (committed profiles, errors, late bundles); an
    error in one message is collected and the others still apply. What the packet stages
    without its ``fseq`` waits in ``pending`` for a later packet from that address. ``senders`` is
    bounded by ``max_senders``: a new sender replaces the one heard from longest ago.
    """

    def __init__(self, restart_s: float = 2.0, max_senders: int = 32) -> None:
        self.restart_s, self.max_senders = restart_s, max_senders
        self.senders: dict[str, Sender] = {}
        self.pending: dict[tuple[str, str], Pending] = {}   # (UDP address, profile) -> frame
        self.names: dict[str, tuple[str, str]] = {}  # UDP address -> (sender key, source name)

    def sender(self, key: str, name: str = "") -> Sender:
        """The sender of ``key``, made when new (the one heard longest ago forgotten past
        ``max_senders``)."""
        s = self.senders.get(key)
        if s is None:
            if len(self.senders) >= self.max_senders:
                oldest = min(self.senders.values(), key=lambda x: x.heard_t)
                del self.senders[oldest.key]
            s = self.senders[key] = Sender(key, name or key)
        return s

    def apply(self, messages: Iterable[tuple[str, tuple[Any, ...]]], address: str, t: float
              ) -> tuple[int, list[TuioError], int]:
        """Apply one packet's ``messages`` from UDP ``address`` received at ``t`` (monotonic s):
        (frames committed, what was wrong in it, frames that came late)."""
        # the name this UDP address last sent (the reference clients keep a source until
        # the next one), else the address itself
        key, name = self.names.get(address, (address, address))
        named = False             # a source message of this packet names its sender
        ip = address.rsplit(":", 1)[0]
        commits, late = 0, 0
        errors: list[TuioError] = []
        heard: set[str] = set()   # senders a bundle of this packet committed (or came late) for
        for addr, args in messages:
            profile = ADDRESSES.get(addr)
            if profile is None:
                continue
            try:
                if not args or not isinstance(args[0], str):
                    raise TuioError("wrong_arguments", f"{addr} without a command string")
                cmd, rest = args[0], args[1:]
                if cmd == "source":
                    if len(rest) != 1 or not isinstance(rest[0], str) or not rest[0]:
                        raise TuioError("wrong_arguments", "source takes one name")
                    # a name from one machine: keyed with the sender's address, so cloned
                    # machines (one image, one host name) sending one default name
                    # (tabletop@HOSTNAME) stay apart instead of replacing each other's objects
                    name = rest[0][:MAX_SOURCE]
                    key, named = f"{name} from {ip}", True
                    self.names.pop(address, None)   # (re)inserted last: the newest is kept
                    self.names[address] = (key, name)
                    if len(self.names) > MAX_PENDING:
                        del self.names[next(iter(self.names))]
                    self._pending_frame(address, profile, key, name, t, named, errors)
                    continue
                if cmd not in ("alive", "set", "fseq"):
                    raise TuioError("unknown_command", f"{addr} {cmd[:40]!r} is not a TUIO "
                                                       "command")
                frame = self._pending_frame(address, profile, key, name, t, named, errors)
                if cmd == "alive":
                    ids = parse_alive(rest)
                    if frame.alive is not None:   # its fseq was lost: a new frame begins,
                        # so the lost one's sets are not also counted not_alive in this one
                        errors.append(TuioError("no_fseq", f"/tuio/{profile} alive again "
                                                           "before its frame's fseq"))
                        frame = self.pending[(address, profile)] = Pending(frame.key,
                                                                           frame.name, t)
                    frame.alive = ids
                elif cmd == "set":
                    e = parse_set(profile, rest)
                    if e.session not in frame.sets and len(frame.sets) >= MAX_ALIVE:
                        raise TuioError("too_many", f"more than {MAX_ALIVE} sets in one frame")
                    frame.sets[e.session] = e
                else:
                    fseq = parse_fseq(rest)
                    del self.pending[(address, profile)]
                    sender = self.sender(frame.key, frame.name)
                    if self._commit(sender, profile, frame.alive, frame.sets, fseq, t):
                        commits += 1
                        self._check_alive(sender.profiles[profile], profile, frame, errors)
                    else:
                        late += 1
                    heard.add(frame.key)
            except TuioError as exc:
                errors.append(exc)
        # heard: only a sender whose bundle committed or came late (it is alive, its frames
        # reordered). A packet refused whole (no fseq, every message wrong) made its sender
        # heard, so its last pucks stayed on the bus while it sent nothing valid.
        for k in heard:
            if k in self.senders:
                self.senders[k].heard_t = t
        return commits, errors, late

    def _pending_frame(self, address: str, profile: str, key: str, name: str, t: float,
                       named: bool, errors: list[TuioError]) -> Pending:
        """The frame ``address`` is staging for ``profile``: a new one when there is none or
        it was begun ``restart_s`` ago (counted ``no_fseq``), named by this packet's
        ``source`` when it has one. At most ``MAX_PENDING`` frames wait: a new one replaces
        the one begun longest ago."""
        slot = (address, profile)
        frame = self.pending.get(slot)
        if frame is not None and t - frame.t > self.restart_s:
            del self.pending[slot]
            if frame.alive is not None or frame.sets:   # (a source alone stages nothing)
                errors.append(TuioError("no_fseq", f"/tuio/{profile} frame without fseq for "
                                                   f"{self.restart_s:g} s: ignored"))
            frame = None
        if frame is None:
            if len(self.pending) >= MAX_PENDING:
                oldest = min(self.pending, key=lambda k: self.pending[k].t)
                del self.pending[oldest]
                errors.append(TuioError("no_fseq", f"more than {MAX_PENDING} frames without "
                                                   "fseq: the oldest ignored"))
            frame = self.pending[slot] = Pending(key, name, t)
        elif named:
            frame.key, frame.name = key, name
        return frame

    def _commit(self, sender: Sender, profile: str, alive: list[int] | None,
                sets: dict[int, Entity], fseq: int, t: float) -> bool:
        st = sender.profiles.setdefault(profile, ProfileState())
        if fseq > 0:
            restarted = t - sender.heard_t > self.restart_s
            if fseq >= st.fseq or st.fseq - fseq > LATE_GAP or restarted:
                st.fseq = fseq
            else:
                return False
        if alive is not None:
            st.alive = alive
        old = st.committed
        st.committed = {s: sets.get(s) or old[s] for s in st.alive if s in sets or s in old}
        st.t = t
        sender.commits += 1
        return True

    @staticmethod
    def _check_alive(st: ProfileState, profile: str, frame: Pending,
                     errors: list[TuioError]) -> None:
        """Count a committed frame's sets of sessions its ``alive`` does not list (``not_alive``):
        TUIO keeps only the entities ``alive`` names, so these sets reach nothing; counting
        them tells a sender that sends ``set`` and ``fseq`` without ``alive`` (an easy slip in
        a script) why nothing of it is on the bus."""
        if frame.sets:
            alive = set(st.alive)
            lost = [s for s in frame.sets if s not in alive]
            if lost:
                more = f" and {len(lost) - 1} more" if len(lost) > 1 else ""
                errors.append(TuioError("not_alive", f"/tuio/{profile} set of session {lost[0]}"
                                                     f"{more} that alive does not list: ignored"))

    def entities(self, profile: str, quiet_s: float, t: float) -> list[tuple[str, Entity]]:
        """(sender key, entity) of every sender heard from within ``quiet_s`` of ``t``."""
        out = []
        for s in self.senders.values():
            st = s.profiles.get(profile)
            if st is not None and t - s.heard_t <= quiet_s:
                out.extend((s.key, e) for e in st.committed.values())
        return out


# ---------------------------------------------------------------------- units
def to_table(e: Entity, table: tuple[float, float]) -> tuple[float, float, float, float, float,
                                                             float]:
    """(x, y, angle, vx, vy, omega) in table metres, radians counter-clockwise, per second."""
    w, h = table
    return (e.x * w, (1.0 - e.y) * h, wrap_angle(-e.angle), e.vx * w, -e.vy * h,
            -e.rotation * 2.0 * math.pi)


def from_table(x: float, y: float, angle: float, vx: float, vy: float, omega: float,
               table: tuple[float, float]) -> tuple[float, float, float, float, float, float]:
    """The inverse of :func:`to_table`: TUIO (x, y, a in [0, 2pi), X, Y, A in turns/s)."""
    w, h = table
    return (x / w, 1.0 - y / h, (-angle) % (2.0 * math.pi), vx / w, -vy / h,
            -omega / (2.0 * math.pi))


# ---------------------------------------------------------------------- sending
def set_args(profile: str, session: int, class_id: int, values: Sequence[float]) -> tuple:
    """Arguments of one ``set`` message from TUIO values (x, y, a, X, Y, A); accelerations 0."""
    x, y, a, vx, vy, va = (float(v) for v in values)
    if profile == "2Dobj":
        return ("set", int(session), int(class_id), x, y, a, vx, vy, va, 0.0, 0.0)
    if profile == "2Dcur":
        return ("set", int(session), x, y, vx, vy, 0.0)
    return ("set", int(session), x, y, a, 0.0, 0.0, 0.0, vx, vy, va, 0.0, 0.0)


def profile_bundles(profile: str, source: str, alive: Sequence[int], sets: Sequence[tuple],
                    fseq: int, limit: int = PACKET_LIMIT) -> list[bytes]:
    """One profile's frame as bundles of at most ``limit`` bytes, as reference servers send it:
    each bundle is source, alive (all ids), as many sets as fit, fseq."""
    address = f"/tuio/{profile}"
    head = [encode_message(address, ("source", source))] if source else []
    head.append(encode_message(address, ("alive", *[int(s) for s in alive])))
    tail = encode_message(address, ("fseq", int(fseq)))
    base = 16 + sum(len(m) + 4 for m in head) + len(tail) + 4
    bundles, current, size = [], [], base
    for args in sets:
        m = encode_message(address, args)
        if current and size + len(m) + 4 > limit:
            bundles.append(encode_bundle(head + current + [tail]))
            current, size = [], base
        current.append(m)
        size += len(m) + 4
    bundles.append(encode_bundle(head + current + [tail]))
    return bundles
