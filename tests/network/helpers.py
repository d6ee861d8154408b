"""A TUIO 1.1 sender built with python-osc the way the reference server (TUIO11_CPP) sends, and
small helpers for tests on real loopback sockets."""

from __future__ import annotations

import socket
from typing import Sequence

from pythonosc.osc_bundle import OscBundle
from pythonosc.osc_bundle_builder import IMMEDIATELY, OscBundleBuilder
from pythonosc.osc_message import OscMessage
from pythonosc.osc_message_builder import OscMessageBuilder
from pythonosc.udp_client import SimpleUDPClient

from tracking.osc_input import OscInput

from tracking.scenes import wait_for  # noqa: F401  (re-exported for the tests here)

TABLE = (1.2, 0.8)
"""The table of the ``osc`` sources under test (metres)."""


def sent(src: OscInput, n: int) -> bool:
    """Wait until ``n`` packets were applied."""
    return wait_for(lambda: src.packets >= n, 5.0)


def ipv6_loopback() -> bool:
    """Whether this machine has the IPv6 loopback address ::1 (some containers do not)."""
    try:
        with socket.socket(socket.AF_INET6, socket.SOCK_DGRAM) as s:
            s.bind(("::1", 0))
        return True
    except OSError:
        return False


def free_udp_port(family: int = socket.AF_INET) -> int:
    """A UDP port on 127.0.0.1 (``::1`` for AF_INET6) that is free right now (bound to 0,
    read, released)."""
    with socket.socket(family, socket.SOCK_DGRAM) as s:
        s.bind(("::1" if family == socket.AF_INET6 else "127.0.0.1", 0))
        return s.getsockname()[1]


def message(address: str, *args) -> OscMessage:
    """A message built by python-osc (types from the Python values: int -> i, float -> f)."""
    b = OscMessageBuilder(address)
    for a in args:
        b.add_arg(a)
    return b.build()


def bundle(*contents: OscMessage | OscBundle) -> OscBundle:
    """A bundle (timetag "immediately") built by python-osc."""
    b = OscBundleBuilder(IMMEDIATELY)
    for c in contents:
        b.add_content(c)
    return b.build()


class RefSender:
    """Sends TUIO 1.1 bundles with python-osc: source, alive, set..., fseq, one bundle per profile.

    Objects are (session, class id, x, y, angle) or (session, class id, x, y, angle, X, Y, A) in
    TUIO units (velocities per second, rotation speed in turns per second); cursors
    (session, x, y)."""

    def __init__(self, port: int, source: str | None = None, host: str = "127.0.0.1") -> None:
        self.client = SimpleUDPClient(host, port)
        self.source = source
        self.fseq = 0

    def profile_bundle(self, profile: str, alive: Sequence[int], sets: Sequence[tuple],
                       fseq: int) -> OscBundle:
        addr = f"/tuio/{profile}"
        msgs = [message(addr, "source", self.source)] if self.source else []
        msgs.append(message(addr, "alive", *alive))
        msgs += [message(addr, "set", *s) for s in sets]
        msgs.append(message(addr, "fseq", fseq))
        return bundle(*msgs)

    def objects(self, objects: Sequence[tuple], fseq: int | None = None,
                alive: Sequence[int] | None = None) -> None:
        if fseq is None:
            self.fseq += 1
            fseq = self.fseq
        sets = [(o[0], o[1], *(float(v) for v in (tuple(o[2:]) + (0.0,) * 3)[:6]), 0.0, 0.0)
                for o in objects]
        ids = [o[0] for o in objects] if alive is None else alive
        self.send(self.profile_bundle("2Dobj", ids, sets, fseq))

    def cursors(self, cursors: Sequence[tuple], fseq: int | None = None) -> None:
        if fseq is None:
            self.fseq += 1
            fseq = self.fseq
        sets = [(s, float(x), float(y), 0.0, 0.0, 0.0) for s, x, y in cursors]
        self.send(self.profile_bundle("2Dcur", [c[0] for c in cursors], sets, fseq))

    def send(self, packet: OscMessage | OscBundle) -> None:
        self.client.send(packet)


class Receiver:
    """A python-osc ``BlockingOSCUDPServer`` on a free loopback port, in its own thread, keeping
    every datagram it receives as python-osc parsed it: a list of (address, params)."""

    def __init__(self) -> None:
        import threading

        from pythonosc.dispatcher import Dispatcher
        from pythonosc.osc_packet import OscPacket
        from pythonosc.osc_server import BlockingOSCUDPServer

        self.packets: list[list[tuple[str, list]]] = []
        self.sizes: list[int] = []
        outer = self

        class Keep(Dispatcher):
            def call_handlers_for_packet(self, data, client_address):
                outer.sizes.append(len(data))
                outer.packets.append([(m.message.address, list(m.message.params))
                                      for m in OscPacket(data).messages])
                return []

        self.server = BlockingOSCUDPServer(("127.0.0.1", 0), Keep())
        self.port = self.server.server_address[1]
        self.thread = threading.Thread(target=self.server.serve_forever, args=(0.05,),
                                       daemon=True)
        self.thread.start()

    def close(self) -> None:
        self.server.shutdown()
        self.server.server_close()
