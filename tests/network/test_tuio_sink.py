"""The ``tuio`` sink: its packets, parsed by python-osc, are TUIO 1.1 as reference servers send
it, and match the frame; an ``osc`` source reading it reproduces the pucks."""

import math

import pytest

from tabletop.frames import CharacterState, Frame, Puck, Touch
from tabletop.plugins.tuio import TuioSink
from tracking.osc_input import OscInput

from tests.network.helpers import Receiver, wait_for

TABLE = (1.2, 0.8)


@pytest.fixture
def receiver():
    r = Receiver()
    yield r
    r.close()


def frame(seq, t, pucks=(), touches=(), characters=()):
    return Frame(seq, t, pucks=tuple(pucks), touches=tuple(touches),
                 characters=tuple(characters))


def by_command(packet):
    """{command: [params...]} of one TUIO bundle, with the profile address checked."""
    out = {}
    for address, params in packet:
        out.setdefault(params[0], []).append((address, params[1:]))
    return out


def test_each_frame_is_one_bundle_per_profile_matching_the_frame(receiver):
    sink = TuioSink("tuio", ("127.0.0.1", receiver.port), TABLE, characters={"lover": 40},
                    source="tabletop@test", changes_only=True)
    pucks = [Puck(1, 0.3, 0.2, 0.5, vx=0.12, vy=-0.08, omega=1.0), Puck(2, 1.0, 0.7, -2.0)]
    chars = [CharacterState("lover", 0.6, 0.4, 3.0), CharacterState("unlisted", 0.1, 0.1, 0.0)]
    sink.consume(frame(0, 10.0, pucks, [Touch(9, 0.6, 0.4, 0.3, 0.0)], chars))
    assert wait_for(lambda: len(receiver.packets) == 2, 5.0)
    obj, cur = (by_command(p) for p in receiver.packets)
    assert list(obj) == ["source", "alive", "set", "fseq"]        # the reference order
    assert {a for c in obj.values() for a, _ in c} == {"/tuio/2Dobj"}
    assert obj["source"][0][1] == ["tabletop@test"]
    alive = obj["alive"][0][1]
    assert len(alive) == 3 and len(set(alive)) == 3
    sets = {s[1]: s for _, s in obj["set"]}                         # by class id
    assert set(sets) == {1, 2, 40}
    s, c, x, y, a, vx, vy, va, m, r = sets[1]
    assert s in alive
    assert (x, y) == pytest.approx((0.3 / 1.2, 1 - 0.2 / 0.8), abs=1e-7)
    assert a == pytest.approx(2 * math.pi - 0.5, abs=1e-6)          # clockwise, 0..2pi
    assert (vx, vy) == pytest.approx((0.1, 0.1), abs=1e-7)
    assert va == pytest.approx(-1.0 / (2 * math.pi), abs=1e-7)      # turns per second
    assert sets[40][2:5] == pytest.approx([0.5, 0.5, 2 * math.pi - 3.0], abs=1e-6)
    fseq = obj["fseq"][0][1][0]
    assert fseq > 0
    assert list(cur) == ["source", "alive", "set", "fseq"]
    (_, (cs, cx, cy, cvx, cvy, cm)), = cur["set"]
    assert cur["alive"][0][1] == [cs]
    assert (cx, cy, cvx) == pytest.approx((0.5, 0.5, 0.25), abs=1e-7)
    assert cur["fseq"][0][1] == [fseq]

    # Next frame: puck 1 moved, puck 2 still, the character gone: stable ids, rising fseq,
    # only the changed object is set again, the one that left is not alive.
    pucks[0] = Puck(1, 0.31, 0.2, 0.5)
    sink.consume(frame(1, 10.02, pucks, [], []))
    assert wait_for(lambda: len(receiver.packets) == 4, 5.0)
    obj2 = by_command(receiver.packets[2])
    assert obj2["alive"][0][1] == [sets[1][0], sets[2][0]]
    assert [p[1] for _, p in obj2["set"]] == [1]
    assert obj2["fseq"][0][1][0] == fseq + 1
    assert by_command(receiver.packets[3])["alive"][0][1] == []

    # About once a second the full state is sent again; a puck that returns gets a new id.
    sink.consume(frame(2, 11.1, pucks + [Puck(7, 0.5, 0.5, 0.0)], [], chars))
    assert wait_for(lambda: len(receiver.packets) == 6, 5.0)
    obj3 = by_command(receiver.packets[4])
    assert sorted(p[1] for _, p in obj3["set"]) == [1, 2, 7, 40]
    new_ids = set(obj3["alive"][0][1]) - set(alive)
    assert len(new_ids) == 2 and min(new_ids) > max(alive)          # never reused
    sink.close()


def test_by_default_every_frame_sets_every_puck(receiver):
    sink = TuioSink("tuio", ("127.0.0.1", receiver.port), TABLE, touches=False)
    for k in range(3):
        sink.consume(frame(k, 10.0 + k / 60, [Puck(1, 0.3, 0.2, 0.5), Puck(2, 1.0, 0.7, -2.0)]))
    assert wait_for(lambda: len(receiver.packets) == 3, 5.0)
    for packet in receiver.packets:
        assert sorted(p[1] for _, p in by_command(packet)["set"]) == [1, 2]


def test_a_large_frame_is_split_into_bundles_under_4096_bytes_and_read_back(receiver):
    src = OscInput("osc", port=0, table=TABLE)
    src.open()
    assert src.wait_listening()
    sink = TuioSink("tuio", ("127.0.0.1", src.bound_port), TABLE)
    pucks = [Puck(i, 0.01 * i, 0.005 * i, 0.01 * i) for i in range(120)]
    try:
        sink.consume(frame(0, 1.0, pucks))
        assert wait_for(lambda: src.latest() is not None and len(src.latest().pucks) == 120, 5.0)
        got = {m.id: m for m in src.latest().pucks}
        for p in pucks:
            assert (got[p.id].x, got[p.id].y) == pytest.approx((p.x, p.y), abs=1e-6)
        assert src.packets >= 3 and src.bad.counts() == {}
        probe = TuioSink("probe", ("127.0.0.1", receiver.port), TABLE)
        sizes = [len(b) for b in probe.bundles(frame(0, 1.0, pucks))]
        assert len(sizes) >= 3 and max(sizes) <= 4096
    finally:
        src.close()
        sink.close()


def test_fseq_passes_the_int32_limit_and_a_receiver_follows_on(receiver):
    """fseq is an int32 rising every frame: after 2**31 - 1 frames (414 days at 60 Hz) the
    sink starts again at 1, which an ``osc`` source takes for a restarted sender. It raised
    struct.error on every frame from then on, and nothing was sent."""
    src = OscInput("osc", port=0, table=TABLE)
    src.open()
    assert src.wait_listening()
    sink = TuioSink("tuio", ("127.0.0.1", src.bound_port), TABLE)
    probe = TuioSink("probe", ("127.0.0.1", receiver.port), TABLE)
    sink.fseq = probe.fseq = 2**31 - 3
    try:
        for k in range(5):              # fseq 2**31 - 2, 2**31 - 1, 1, 2, 3
            x = 0.1 + 0.2 * k
            f = frame(k, 1.0 + k / 60, [Puck(4, x, 0.4, 0.0)], [Touch(2, x, 0.3)])
            sink.consume(f)
            probe.consume(f)
            assert wait_for(lambda: src.packets == 2 * (k + 1), 5.0)
            (p,) = src.latest().pucks   # each frame commits, none dropped as late
            assert p.x == pytest.approx(x, abs=1e-6)
        assert wait_for(lambda: len(receiver.packets) == 10, 5.0)
        fseqs = [by_command(pk)["fseq"][0][1][0] for pk in receiver.packets]
        assert fseqs == [f for f in (2**31 - 2, 2**31 - 1, 1, 2, 3) for _ in range(2)]
        assert src.bad.counts() == {} and sink.sent == 10
    finally:
        src.close()
        sink.close()
        probe.close()


def test_a_receiver_that_is_not_there_costs_nothing(caplog):
    sink = TuioSink("tuio", ("127.0.0.1", 9), TABLE)       # discard port, nobody listening
    for k in range(50):
        sink.consume(frame(k, k / 60, [Puck(1, 0.5, 0.5, 0.0)]))
    sink.close()
    unresolvable = TuioSink("tuio", ("no-such-host.invalid", 3333), TABLE)
    assert unresolvable.destination.wait(15.0) is None
    for k in range(50):
        unresolvable.consume(frame(k, k / 60, [Puck(1, 0.5, 0.5, 0.0)]))
    assert unresolvable.unresolved == 100    # dropped, never raised
    assert unresolvable.sent == 0            # and not counted as sent (it said 100)
    said = [r.getMessage() for r in caplog.records if "no-such-host" in r.getMessage()]
    assert len(said) == 1 and "cannot resolve" in said[0], said   # said once, not per send
    unresolvable.close()


SILENT_NAME_SERVER = r"""
import socket, sys, threading, time
sys.path.insert(0, sys.argv[1])
udp = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
udp.bind(("127.0.0.1", 53))            # a name server that hears every question, answers none
threading.Thread(target=lambda: [udp.recv(4096) for _ in iter(int, 1)], daemon=True).start()
from tabletop.frames import Frame, Puck
from tabletop.kiosk.health import Heartbeat
from tabletop.plugins.tuio import TuioSink
sink = TuioSink("out", ("stage.gallery", 3333), (1.2, 0.8))
beat = Heartbeat("monitor.gallery", 9000)
end, n = time.monotonic() + 1.0, 0
while time.monotonic() < end:          # frames as fast as the loop could make them, for 1 s
    sink.consume(Frame(n, n / 60, pucks=(Puck(1, 0.5, 0.5, 0.0),)))
    beat.send("north", 1.0, 60.0, 0, "{}")
    n += 1
print(n)
"""


def test_a_name_server_that_never_answers_does_not_hold_the_frame_loop(tmp_path):
    """A gallery whose name server does not answer: looking the sink's or the heartbeat's host
    name up in the frame loop held it 10 s per look-up (glibc: 5 s timeout, two tries); the
    installation drew 266 frames in 20 s. Run with a real resolver asking a real, silent name
    server on loopback, in a private network and mount namespace (skipped where there is none).
    """
    import shutil
    import subprocess
    import sys
    from pathlib import Path
    if not (shutil.which("unshare") and shutil.which("ip") and shutil.which("mount")):
        pytest.skip("needs unshare, ip and mount")
    resolv = tmp_path / "resolv.conf"
    resolv.write_text("nameserver 127.0.0.1\n")
    inner = tmp_path / "inner.py"
    inner.write_text(SILENT_NAME_SERVER)
    root = Path(__file__).resolve().parents[2]
    shell = (f"mount --bind {resolv} /etc/resolv.conf && ip link set lo up && "
             f"exec {sys.executable} {inner} {root}")
    try:
        out = subprocess.run(["unshare", "-rmn", "sh", "-c", shell], capture_output=True,
                             text=True, timeout=60)
    except subprocess.TimeoutExpired:
        pytest.fail("the frames waited for the name server")
    if out.returncode != 0 and "unshare" in out.stderr:
        pytest.skip(f"no private namespaces here: {out.stderr.strip()}")
    assert out.returncode == 0, out.stderr
    frames = int(out.stdout.split()[-1])
    assert frames > 100, frames   # measured: 1 before (10 s in the first look-up), 13,475 after


def test_a_listed_character_no_engine_shows_is_named_once(caplog):
    sink = TuioSink("tuio", ("127.0.0.1", 9), TABLE, characters={"lover": 100, "lovre": 101},
                    send=lambda data: None)
    lover = CharacterState("lover", 0.5, 0.4, 0.0)
    for k in range(60 * 15):                                  # 15 s of frames at 60 Hz
        sink.consume(frame(k, k / 60, characters=[lover]))
    said = [r.getMessage() for r in caplog.records if r.name == "tabletop.tuio"]
    assert len(said) == 1 and "lovre" in said[0] and "characters seen: lover" in said[0], said


def test_a_character_sent_with_a_pucks_class_id_is_named_once(receiver, caplog):
    """``characters: {lover: 2}`` beside puck 2: both go out as class id 2, which a receiving
    stage takes for two sightings of puck 2 (its tracker keeps one, the other is lost). Said
    once, with both, and still sent as configured."""
    sink = TuioSink("out", ("127.0.0.1", receiver.port), TABLE, characters={"lover": 2})
    lover = CharacterState("lover", 0.5, 0.4, 0.0)
    for k in range(3):
        sink.consume(frame(k, k / 60, pucks=[Puck(1, 0.2, 0.2, 0.0), Puck(2, 0.6, 0.3, 0.0)],
                           characters=[lover]))
    assert wait_for(lambda: len(receiver.packets) >= 6, 5.0)
    sets = by_command(receiver.packets[-2])["set"]
    assert sorted(params[1] for _a, params in sets) == [1, 2, 2]
    said = [r.getMessage() for r in caplog.records if r.name == "tabletop.tuio"]
    assert said == ["out: character lover is sent with class id 2, which puck 2 has too: a "
                    "receiver takes it for a second sighting of that puck; give it an id no "
                    "puck's marker has"], said
    sink.close()


def test_a_source_name_receivers_cannot_keep_is_refused_at_load():
    """A 70 kB source name made every datagram fail ('Message too long', one warning) for the
    whole run; receivers keep 200 characters of it."""
    import pytest

    from tabletop.config import validate_config
    from tabletop.schema import ConfigError

    src = [{"kind": "scripted"}]
    for name in ("x" * 201, ""):
        with pytest.raises(ConfigError) as info:
            validate_config({"sources": src, "sinks": [{"kind": "tuio", "source": name}]}, "c.yaml")
        assert str(info.value) == (f"c.yaml: sinks[0].source: {len(name)} characters; expected "
                                   "1 to 200 (a name such as tracker@table-7)")
    validate_config({"sources": src, "sinks": [{"kind": "tuio", "source": "t" * 200}]}, "c.yaml")
