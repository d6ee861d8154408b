"""Thousands of malformed packets and serial lines (a seeded generator) against a running loop:
it keeps ticking (a good sender's steps drawn between them), counts them per kind, keeps its
memory bounded, and valid input afterwards still applies."""

import math
import os
import random
import socket
import struct
import threading

from tabletop.loop import LiveInputs, Loop
from tabletop.plugins.tracking import Tracker
from tracking.osc_codec import encode_bundle, encode_message
from tracking.osc_input import MAX_STREAMS, OscInput
from tracking.serial_input import MAX_ITEMS, SerialInput
from tracking.tuio import MAX_ALIVE, profile_bundles

from tests.network.helpers import wait_for

TABLE = (1.2, 0.8)
RATE = 60.0


class Keep:
    """A sink keeping the newest frame and checking every frame is clean."""

    name = "keep"

    def __init__(self) -> None:
        self.frame = None
        self.poisoned = 0

    def consume(self, frame) -> None:
        for p in frame.pucks:
            if not all(math.isfinite(v) for v in (p.x, p.y, p.angle, p.vx, p.vy, p.omega)):
                self.poisoned += 1
        for v in frame.streams.values():
            if not all(math.isfinite(x) for x in v):
                self.poisoned += 1
        self.frame = frame

    def close(self) -> None:
        pass


def valid_bundle(rng: random.Random) -> bytes:
    n = rng.randint(0, 6)
    sets = [("set", s, rng.randint(0, 50), rng.random(), rng.random(), rng.random() * 6.28,
             0.0, 0.0, 0.0, 0.0, 0.0) for s in range(n)]
    return profile_bundles("2Dobj", f"fuzz{rng.randint(0, 3)}", [s[1] for s in sets], sets,
                           rng.randint(-1, 1000))[0]


def bad_packet(rng: random.Random) -> bytes:
    """One malformed or hostile datagram of a random kind."""
    kind = rng.randrange(12)
    good = valid_bundle(rng)
    if kind == 0:
        return bytes(rng.getrandbits(8) for _ in range(rng.randint(0, 200)))
    if kind == 1:
        return good[:rng.randint(0, len(good) - 1)]                     # truncated
    if kind == 2:
        b = bytearray(good)
        for _ in range(rng.randint(1, 8)):
            b[rng.randrange(len(b))] = rng.getrandbits(8)                  # corrupted
        return bytes(b)
    if kind == 3:                                                          # wrong types/counts
        args = [rng.choice(["x", 1, 2.5, b"\x00", True]) for _ in range(rng.randint(0, 12))]
        return encode_message(rng.choice(["/tuio/2Dobj", "/tuio/2Dcur", "/tuio/2Dblb"]),
                              [rng.choice(["set", "alive", "fseq", "source", "bogus"]), *args])
    if kind == 4:                                                          # nested bundles
        p = good
        for _ in range(rng.randint(1, 20)):
            p = encode_bundle([p])
        return p
    if kind == 5:                                                          # NaN and infinities
        v = rng.choice([math.nan, math.inf, -math.inf])
        return encode_bundle([encode_message("/tuio/2Dobj", ("alive", 1)),
                              encode_message("/tuio/2Dobj", ("set", 1, 3, v, 0.5, 0.0, 0.0, 0.0,
                                                             0.0, 0.0, 0.0)),
                              encode_message("/tuio/2Dobj", ("fseq", 5)),
                              encode_message("/mocap/arm", (1.0, v))])
    if kind == 6:                                                          # unknown addresses
        return encode_message(rng.choice(["/foo", "/tuio/25Dobj", "/mocap/", "/mocap/a b"]),
                              (1.0,))
    if kind == 7:                                                          # oversized
        return encode_message("/mocap/big", tuple(0.0 for _ in range(5000)))
    if kind == 8:                                                          # huge alive
        return encode_bundle([encode_message("/tuio/2Dcur", ("alive", *range(MAX_ALIVE + 10))),
                              encode_message("/tuio/2Dcur", ("fseq", 1))])
    if kind == 9:                                                          # lying sizes
        return good[:16] + struct.pack(">i", 10_000) + good[20:]
    if kind == 10:                                                         # many stream names
        return encode_message(f"/mocap/s{rng.randint(0, 10_000)}", (1.0,))
    return encode_bundle([encode_message("/tuio/2Dobj", ("alive",))])   # no fseq


def test_a_flood_of_bad_packets_hurts_nothing():
    rng = random.Random(20261201)
    src = OscInput("osc", port=0, table=TABLE)
    keep = Keep()
    loop = Loop(LiveInputs([src], Tracker()), [], [keep], rate_hz=RATE)
    thread = threading.Thread(target=loop.run, daemon=True)
    thread.start()
    assert src.wait_listening()
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    good = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)   # a sender of its own
    n, chunk = 3000, 50
    try:
        for k in range(n // chunk):
            for _ in range(chunk):
                sock.sendto(bad_packet(rng), ("127.0.0.1", src.bound_port))
            # then a good puck's step: the loop must tick and draw it before the flood goes
            # on (a few ticks' worth of packets queued at a time, within what the kernel
            # buffers for one socket), however slowly a loaded machine runs either
            good.sendto(profile_bundles("2Dobj", "steady@test", [1], [
                ("set", 1, 99, k / 64, 0.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)], k + 1)[0],
                ("127.0.0.1", src.bound_port))
            assert wait_for(lambda: keep.frame is not None and keep.frame.puck(99) is not None
                            and keep.frame.puck(99).raw_x == k / 64 * TABLE[0], 20.0), k
        # every packet was heard and either applied or refused whole and counted: none lost
        heard = lambda: src.packets + sum(src.bad.counts().get(kind, 0)   # noqa: E731
                                          for kind in ("malformed", "oversized"))
        assert wait_for(lambda: heard() >= n + n // chunk, 20.0), (heard(), n + n // chunk)
        assert heard() == n + n // chunk
        counts = src.bad.counts()
        assert thread.is_alive()
        for kind in ("malformed", "nested_bundle", "wrong_arguments", "non_finite",
                     "unknown_address", "oversized", "too_many", "no_fseq"):
            assert counts.get(kind, 0) > 0, (kind, counts)
        assert "internal_error" not in counts
        assert keep.poisoned == 0
        assert len(src.client.senders) <= src.client.max_senders
        assert len(src._streams) <= MAX_STREAMS
        assert all(len(st.committed) <= MAX_ALIVE for s in src.client.senders.values()
                   for st in s.profiles.values())
        # A valid packet after the flood is applied.
        sock.sendto(profile_bundles("2Dobj", "after@test", [1], [
            ("set", 1, 77, 0.25, 0.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)], 1)[0],
            ("127.0.0.1", src.bound_port))
        assert wait_for(lambda: keep.frame is not None and keep.frame.puck(77) is not None, 5.0)
        p = keep.frame.puck(77)
        assert (p.x, p.y) == (0.3, 0.4)
    finally:
        loop.stop.set()
        thread.join(5.0)
        sock.close()
        good.close()


def bad_line(rng: random.Random) -> bytes:
    kind = rng.randrange(8)
    if kind == 0:
        return bytes(rng.getrandbits(8) for _ in range(rng.randint(0, 80))).replace(b"\n", b"")
    if kind == 1:
        return b"puck 1 " + b"9" * rng.randint(1100, 3000)                # over-long
    if kind == 2:
        return f"puck {rng.randint(0, 9)} {rng.choice(['nan', 'inf', '-inf'])} 0 0".encode()
    if kind == 3:
        return b"touch 1 0.5"                                              # too few fields
    if kind == 4:
        return f"stream s{rng.randint(0, 999)} 1".encode()                 # many names
    if kind == 5:
        return f"puck {rng.randint(0, 100_000)} 0.5 0.5 0".encode()        # many pucks
    if kind == 6:
        return b"fly away"
    return b"puck 1 1e300 0 0"


def test_a_flood_of_bad_serial_lines_hurts_nothing():
    rng = random.Random(7)
    master, slave = os.openpty()
    src = SerialInput("mcu", os.ttyname(slave), timeout_s=30.0)
    src.open()
    try:
        assert wait_for(lambda: src.health().ok, 5.0)
        data = b"\n".join(bad_line(rng) for _ in range(3000)) + b"\n"
        for i in range(0, len(data), 4096):
            os.write(master, data[i:i + 4096])
        os.write(master, b"x" * 5000)                     # a line without its newline...
        os.write(master, b"\npuck 77 0.3 0.4 0.5\n")      # ...ended, then a valid one
        assert wait_for(lambda: any(p.id == 77 for p in (src.latest().pucks)), 10.0)
        p = next(p for p in src.latest().pucks if p.id == 77)
        assert (p.x, p.y, p.angle) == (0.3, 0.4, 0.5)
        counts = src.bad.counts()
        for kind in ("overlong", "non_finite", "wrong_arguments", "unknown_command",
                     "out_of_range", "too_many"):
            assert counts.get(kind, 0) > 0, (kind, counts)
        assert len(src.state.pucks) <= MAX_ITEMS and len(src.state.streams) <= 64
        assert src.health().ok
    finally:
        src.close()
        os.close(master)
        os.close(slave)
