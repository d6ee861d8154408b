"""OSC input over UDP: TUIO 1.1 pucks and touches and ``/mocap/NAME`` vectors, in its own thread.

A python-osc ``BlockingOSCUDPServer`` listens on one interface (loopback by default) in the
source's own thread: one packet at a time, in arrival order (the threading server starts a thread
per packet and loses most of a burst). Each datagram is checked against the allow-list, decoded
(``tracking.osc_codec``), and its TUIO messages applied to the receiving state
(``tracking.tuio.TuioClient``); ``/mocap/NAME f f ...`` becomes the stream NAME. Anything wrong is
counted per kind (``tracking.badinput``) and otherwise ignored: nothing from the network can
raise out of the thread, poison a frame or grow memory without bound.

``latest()`` returns the committed state as an Observation in table metres: objects as puck
measurements (class id = marker id) carrying the sender's velocities (X, Y, A mapped as
positions and angles are), cursors and blobs as touches (session id = touch id; a blob sharing
its session id with a cursor or object of its sender is that entity's outline, not a touch; a
session id another sender's touch already holds gives the touch a free id instead,
:mod:`tracking.touch_ids`).
TUIO is a state protocol and reference servers resend an unchanged state only once a second, so
while a sender is heard from (within ``quiet_s``) its objects are held present: their time is
their commit time, or ``now - HOLD_S`` if older, and so is the observation's time (it says
what the network holds as of then, so the frame clock moves on while the senders are quiet).
A held object carries no velocity (NaN): its reported pose stands still, so the tracker's
estimate from it fades to rest instead of a stale velocity carrying the puck off when it coasts.
An id that leaves ``alive`` leaves the bus at once (``Observation.removed``); a sender that goes
quiet stops being reported: the puck tracker coasts its pucks, then drops them, and its touches
and streams leave. If the port cannot be bound the thread retries with a
growing back-off and the health says why.
"""

from __future__ import annotations

import collections
import ipaddress
import logging
import math
import re
import socket
import threading
import time
from typing import TYPE_CHECKING, Any, Callable, Iterable

import numpy as np

from tabletop.frames import MAX_FEATURE, Observation, PuckMeasurement, SourceHealth, Touch
from tracking.badinput import BackgroundSource, BadInput
from tracking.osc_codec import OscError, decode_packet
from tracking.touch_ids import TouchIds
from tracking.tuio import ADDRESSES, MAX_ALIVE, TuioClient, to_table

if TYPE_CHECKING:
    from pythonosc.osc_server import BlockingOSCUDPServer

HOLD_S = 0.1               # a held (unchanged) state is reported at most this old
MAX_STREAMS = 64
MAX_STREAM_VALUES = 256
STREAM_NAME = re.compile(r"[A-Za-z0-9_.\-/]{1,64}\Z")  # /mocap/left/hand: "left/hand"
RECEIVE_BUFFER = 1 << 20   # bytes of kernel socket buffer asked for

log = logging.getLogger("tabletop.osc")


class OscInput(BackgroundSource):
    """A ``Source`` receiving TUIO and mocap OSC on ``host``:``port`` (see the module docstring).

    ``allow``: sender IP addresses accepted (empty: any sender that reaches the interface);
    ``table``: (width, height) metres; ``quiet_s``: a sender silent this long is gone;
    ``stall_s``: health turns bad when nothing was received this long; ``max_packet``: larger
    datagrams are refused (bytes). ``on_packet(t_received)`` is called after each applied packet
    (benchmarks time delivery with it).
    """

    def __init__(self, name: str, host: str = "127.0.0.1", port: int = 3333,
                 allow: Iterable[str] = (), table: tuple[float, float] = (1.2, 0.8),
                 quiet_s: float = 1.5, stall_s: float = 5.0, max_packet: int = 16384,
                 retry_min_s: float = 0.5, retry_max_s: float = 8.0,
                 clock: Callable[[], float] = time.monotonic) -> None:
        self.name, self.host, self.port = name, host, int(port)
        self.allow = frozenset(plain_address(a) for a in allow)
        self.table, self.quiet_s, self.stall_s = table, quiet_s, stall_s
        self.max_packet, self.clock = max_packet, clock
        self.retry_min_s, self.retry_max_s = retry_min_s, retry_max_s
        self.bad = BadInput(name, clock=clock)
        self.client = TuioClient()
        self._touch_ids = TouchIds()   # senders each count their sessions from 0 or 1
        self.on_packet: Callable[[float], None] | None = None
        self._streams: dict[str, tuple[np.ndarray, float]] = {}
        self._removed: set[int] = set()
        self._lock = threading.Lock()
        self._init_thread()
        self._listening = threading.Event()
        self._message = "starting"
        self._heard_t = -math.inf
        self._seq = 0
        self.packets = 0
        self.bound_port: int | None = None

    # ------------------------------------------------------------------ Source protocol
    def wait_listening(self, timeout: float = 5.0) -> bool:
        """Block until the socket is bound, at most ``timeout`` seconds; True if it is (tests and
        benchmarks)."""
        return self._listening.wait(timeout)

    def latest(self) -> Observation | None:
        now = self.clock()
        with self._lock:
            pucks, touches = [], []
            for key, e in self.client.entities("2Dobj", self.quiet_s, now):
                x, y, a, vx, vy, w = to_table(e, self.table)
                commit_t = self._commit_t(key, "2Dobj")
                t = max(commit_t, now - HOLD_S)
                if t > commit_t:  # held: the pose stands still, the sent velocity is stale
                    vx = vy = w = math.nan
                pucks.append(PuckMeasurement(e.class_id, x, y, a, min(t, now), vx=vx, vy=vy,
                                             omega=w))
            found = []
            for profile in ("2Dcur", "2Dblb"):
                for key, e in self.client.entities(profile, self.quiet_s, now):
                    if profile == "2Dblb" and self._described(key, e.session):
                        continue
                    found.append((key, e))
            ids = self._touch_ids.assign([(key, e.session) for key, e in found])
            for i, (_key, e) in zip(ids, found):
                x, y, _a, vx, vy, _w = to_table(e, self.table)
                touches.append(Touch(i, x, y, vx, vy))
            streams = {k: v for k, (v, ts) in self._streams.items() if now - ts <= self.quiet_s}
            present = {p.id for p in pucks}
            removed = tuple(sorted(self._removed - present))
            self._removed.clear()
            if not (pucks or touches or streams or removed) and self._seq == 0:
                return None
            self._seq += 1
            t = max(min(self._heard_t, now), now - HOLD_S)
            return Observation(self.name, t, self._seq, pucks=tuple(pucks),
                               touches=tuple(touches), streams=streams, removed=removed,
                               held=t > self._heard_t)

    def health(self) -> SourceHealth:
        now = self.clock()
        with self._lock:
            age = now - self._heard_t
            message = self._message
            live = [s for s in self.client.senders.values() if now - s.heard_t <= self.quiet_s]
            sent = collections.Counter(s.name for s in live)
            # a name two machines send is shown with each one's address ("... from IP")
            senders = sorted(s.name[:40] + (s.key[len(s.name):] if sent[s.name] > 1 else "")
                             for s in live)
        ok = self._listening.is_set()
        if ok:
            if math.isinf(age):
                message += "; nothing received yet"
            elif age > self.stall_s:
                ok, message = False, f"{message}; nothing received for {age:.0f} s"
            else:
                names = ", ".join(senders[:3])
                more = f" and {len(senders) - 3} more" if len(senders) > 3 else ""
                message += f"; TUIO from {names}{more}" if senders else "; no TUIO sender"
        return self.bad.health(ok, message, age)

    # ------------------------------------------------------------------ receiving
    def _described(self, key: str, session: int) -> bool:
        """Whether a blob of sender ``key`` is the outline of one of its cursors or objects:
        TUIO 1.1 gives a blob that describes a cursor or an object that entity's session id
        (a sender numbers all its profiles from one counter), so it is no finger of its own."""
        profiles = self.client.senders[key].profiles
        return any(session in profiles[p].committed for p in ("2Dcur", "2Dobj") if p in profiles)

    def _commit_t(self, key: str, profile: str) -> float:
        st = self.client.senders[key].profiles.get(profile)
        return st.t if st is not None else -math.inf

    def handle(self, data: bytes, address: tuple[str, int]) -> None:
        """Apply one datagram from ``address`` (ip, port); never raises."""
        t = self.clock()
        try:
            self._handle(data, address, t)
        except Exception as exc:  # a bug must not end the receiving thread
            self.bad.count("internal_error", f"{type(exc).__name__}: {exc}")

    def _handle(self, data: bytes, address: tuple[str, int], t: float) -> None:
        if len(data) > self.max_packet:
            self.bad.count("oversized", f"{len(data)} bytes from {address[0]}")
            return
        try:
            packet = decode_packet(data)
        except OscError as exc:
            self.bad.count("malformed", f"from {address[0]}: {exc}")
            return
        if packet.depth > 1:
            self.bad.count("nested_bundle", f"from {address[0]}: flattened")
        tuio, mocap = [], []
        for addr, args in packet.messages:
            if addr in ADDRESSES:
                tuio.append((addr, args))
            elif addr.startswith("/mocap/"):
                mocap.append((addr[7:], args))
            else:
                self.bad.count("unknown_address", f"{addr[:80]!r} from {address[0]}"
                               f"{unknown_hint(addr)}")
        with self._lock:
            before = {k: {e.class_id for e in s.profiles["2Dobj"].committed.values()}
                      for k, s in self.client.senders.items() if "2Dobj" in s.profiles}
            commits, errors, late = self.client.apply(tuio, f"{address[0]}:{address[1]}", t)
            if commits:
                self._note_removed(before)
            streams = sum(self._stream(name, args, t, address[0]) for name, args in mocap)
            # heard: a sender whose input applied (late fseqs too: it is alive). A packet that
            # applied nothing (another OSC program's message sent to this port) made the source
            # "heard", then stalled stall_s later: a kiosk that never had a TUIO sender showed
            # "one moment" for good, its camera working, after one stray packet.
            if commits or late or streams:
                self._heard_t = t
            self.packets += 1
        for exc in errors:
            self.bad.count(exc.kind, f"from {address[0]}: {exc}")
        if late:
            self.bad.count("late_fseq", f"from {address[0]}", late)
        if self.on_packet is not None:
            self.on_packet(t)

    def _note_removed(self, before: dict[str, set[int]]) -> None:
        for key, ids in before.items():
            s = self.client.senders.get(key)
            st = s.profiles.get("2Dobj") if s is not None else None
            now_ids = {e.class_id for e in st.committed.values()} if st is not None else set()
            if len(self._removed) < MAX_ALIVE:
                self._removed |= ids - now_ids

    def _stream(self, name: str, args: tuple, t: float, sender: str) -> bool:
        """Store the stream ``name`` sent by ``sender`` (an IP address); False when refused
        (counted, naming the sender as every other refusal does)."""
        where = f"from {sender}"
        if not STREAM_NAME.match(name):
            self.bad.count("unknown_address", f"bad stream name {name[:80]!r} {where}")
            return False
        if not args or len(args) > MAX_STREAM_VALUES:
            self.bad.count("wrong_arguments", f"/mocap/{name} with {len(args)} values {where}")
            return False
        if any(isinstance(a, bool) or not isinstance(a, (int, float)) for a in args):
            self.bad.count("wrong_arguments", f"/mocap/{name} with a non-number {where}")
            return False
        v = np.array(args, dtype=float)
        if not np.all(np.isfinite(v)):
            self.bad.count("non_finite", f"/mocap/{name} {where}")
            return False
        if np.abs(v).max() > MAX_FEATURE:   # OSC doubles: a followed stream became NaN
            self.bad.count("out_of_range", f"/mocap/{name} with a value beyond {MAX_FEATURE:g} "
                                           f"{where}")
            return False
        if name not in self._streams and len(self._streams) >= MAX_STREAMS:
            oldest = min(self._streams, key=lambda k: self._streams[k][1])
            del self._streams[oldest]  # the newest input always gets in
            self.bad.count("too_many", f"more than {MAX_STREAMS} streams: {oldest} forgotten")
        self._streams[name] = (v, t)
        return True

    # ------------------------------------------------------------------ the thread
    def _run(self) -> None:
        delay = self.retry_min_s
        failing = False
        while not self._stop.is_set():
            try:
                server = make_server(self.host, self.port, self)
            except Exception as exc:  # OSError: address in use, no such interface, ...
                reason = getattr(exc, "strerror", None) or exc
                msg = f"cannot listen on {self.host}:{self.port}: {reason}"
                with self._lock:
                    self._message = f"{msg}; retrying in {delay:.1f} s"
                if not failing:  # said once, then in the health until it listens
                    log.warning("%s: %s; retrying until it can", self.name, msg)
                failing = True
                self._stop.wait(delay)
                delay = min(2.0 * delay, self.retry_max_s)
                continue
            if failing:
                log.info("%s: listening on %s:%s", self.name, self.host,
                         server.server_address[1])
            self.bound_port = server.server_address[1]
            with self._lock:
                self._message = f"listening on {self.host}:{self.bound_port}"
            self._listening.set()
            try:
                while not self._stop.is_set():
                    server.handle_request()  # one datagram, or none within server.timeout
            finally:
                self._listening.clear()
                server.server_close()
        with self._lock:
            self._message = "closed"


def unknown_hint(addr: str) -> str:
    """What an address this source does not read is likely to be, for its log line: a
    TUIO 2.0 tracker or another TUIO 1.1 profile was said only as an unknown address."""
    if addr.startswith("/tuio2/"):
        return ": TUIO 2.0, which is not read; set the sender to TUIO 1.1"
    if addr.startswith("/tuio/"):
        return ": a TUIO 1.1 profile not read (only /tuio/2Dobj, /tuio/2Dcur, /tuio/2Dblb)"
    return ""


def plain_address(address: str) -> str:
    """A sender's IP address as it is written in ``allow``: an IPv4 sender reaching a socket
    that listens on every IPv6 and IPv4 interface (``host: "::"``) arrives as
    ``::ffff:192.168.1.10``, which no IPv4 entry of the allow-list would match."""
    try:
        ip = ipaddress.ip_address(address)
    except ValueError:
        return address
    mapped = getattr(ip, "ipv4_mapped", None)
    return str(mapped if mapped is not None else ip)


def make_server(host: str, port: int, sink: OscInput) -> BlockingOSCUDPServer:
    """A python-osc ``BlockingOSCUDPServer`` on (host, port) that hands every datagram from an
    allowed sender to ``sink.handle`` (its dispatcher is not used)."""
    from pythonosc.dispatcher import Dispatcher
    from pythonosc.osc_server import BlockingOSCUDPServer

    class Server(BlockingOSCUDPServer):
        max_packet_size = 65536  # see oversized datagrams whole, to count them

        def server_bind(self) -> None:
            self.socket.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, RECEIVE_BUFFER)
            super().server_bind()

        def get_request(self) -> tuple[Any, tuple[Any, ...]]:
            """The datagram and its sender, the sender's address plain (once per packet)."""
            request, client_address = super().get_request()
            return request, (plain_address(client_address[0]), *client_address[1:])

        def verify_request(self, request: Any, client_address: Any) -> bool:
            sender = client_address[0]
            if sink.allow and sender not in sink.allow:
                sink.bad.count("not_allowed", f"packet from {sender}")
                return False
            return True

        def finish_request(self, request: Any, client_address: Any) -> None:
            sink.handle(request[0], (client_address[0], client_address[1]))

        def handle_error(self, request: Any, client_address: Any) -> None:
            sink.bad.count("internal_error", f"from {client_address}")

    server = Server((host, port), Dispatcher())
    server.timeout = 0.1  # handle_request returns at least this often, to see close()
    return server
