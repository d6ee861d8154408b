"""The ``osc`` source's TUIO frames on a real loopback socket: values refused whole (too large
for table metres, bad mocap), packets that apply nothing or are refused, frames sent as single
messages, and unfinished or lost frames counted without holding memory."""

import math
import socket
import time

from tabletop.loop import LiveInputs
from tabletop.plugins.tracking import Tracker
from tracking.osc_input import OscInput

from tests.network.helpers import TABLE, RefSender, bundle, message, sent, wait_for


def test_velocities_too_large_for_table_metres_are_refused(source):
    """A double velocity near the largest float is finite in TUIO units but infinite once
    mapped to metres: such a set is refused (counted ``out_of_range``), so no infinite speed
    reaches a frame (the recorder cannot write an infinite speed: 'Out of range float
    values')."""
    import json

    from pythonosc.osc_message_builder import OscMessageBuilder

    from tabletop.session import frame_to_dict

    def doubles(address: str, head: list, values: list) -> OscMessageBuilder:
        b = OscMessageBuilder(address)
        for a in head:
            b.add_arg(a)
        for v in values:
            b.add_arg(v, "d")
        return b.build()

    ref = RefSender(source.bound_port)
    big = 1.7e308
    for n, (profile, head, values) in enumerate((
            ("2Dcur", ["set", 3], [0.5, 0.5, big, -big, 0.0]),
            ("2Dobj", ["set", 1, 5], [0.5, 0.5, 0.0, 0.0, 0.0, big, 0.0, 0.0]),
            ("2Dblb", ["set", 4], [0.5, 0.5, 0.0, 0.1, 0.1, 0.01, -big, 0.0, 0.0, 0.0, 0.0]))):
        address = f"/tuio/{profile}"
        ref.send(bundle(message(address, "alive", head[1]), doubles(address, head, values),
                        message(address, "fseq", n + 1)))
    assert wait_for(lambda: source.bad.total() == 3, 5.0)
    assert source.bad.counts() == {"out_of_range": 3}
    frame = LiveInputs([source], Tracker()).next(0, 0.0)
    assert frame.touches == () and frame.pucks == ()
    ref.cursors([(3, 0.5, 0.75)])
    assert sent(source, 4)
    frame = LiveInputs([source], Tracker()).next(1, 0.0)
    assert [c.id for c in frame.touches] == [3]
    json.dumps(frame_to_dict(frame), allow_nan=False)


def test_packets_that_apply_nothing_never_make_the_source_stall():
    """Another OSC program's messages (and TUIO messages refused whole) sent to the port, the
    source never having had a sender: counted, and the source stays healthy ("nothing received
    yet") however long after; they made it "heard" and then unhealthy ``stall_s`` later, so a
    kiosk (whose camera worked) showed "one moment" for good. A real sender heard, then quiet,
    still stalls."""
    now = [0.0]
    src = OscInput("osc", port=0, table=TABLE, stall_s=5.0, clock=lambda: now[0])
    src.open()
    try:
        assert src.wait_listening()
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
            for m in (message("/lights/dim", 0.5), message("/tuio/2Dobj", "set", 1),
                      message("/mocap/arm", "x"), bundle(message("/tuio/2Dcur", "alive", 3))):
                s.sendto(m.dgram, ("127.0.0.1", src.bound_port))
        assert wait_for(lambda: src.packets == 4, 5.0)
        now[0] = 60.0
        h = src.health()
        assert h.ok and "nothing received yet" in h.message and "ignored:" in h.message, h
        RefSender(src.bound_port).objects([(1, 5, 0.5, 0.5, 0.0)])
        assert wait_for(lambda: src.latest() is not None and src.latest().pucks, 5.0)
        now[0] = 120.0
        h = src.health()
        assert not h.ok and "nothing received for 60 s" in h.message, h
    finally:
        src.close()


def test_a_packet_refused_whole_does_not_keep_its_sender_alive():
    """A sender that committed a puck, then sends only packets refused whole (bundles without
    fseq, sets with wrong arguments, a lone source): after ``quiet_s`` from its last commit it
    is gone (its puck leaves, the health names no sender), as if silent. Those packets kept it
    heard, so a broken tracker's last pucks stayed on the table for as long as it sent garbage."""
    now = [0.0]
    src = OscInput("osc", port=0, table=TABLE, quiet_s=1.5, clock=lambda: now[0])
    src.open()
    try:
        assert src.wait_listening()
        ref = RefSender(src.bound_port, source="tracker@10.0.0.5")
        ref.objects([(1, 5, 0.5, 0.5, 0.0)])
        assert sent(src, 1)
        assert [p.id for p in src.latest().pucks] == [5]
        now[0] = 1.0
        a = "/tuio/2Dobj"
        refused = [bundle(message(a, "source", "tracker@10.0.0.5"), message(a, "alive", 1),
                          message(a, "set", 1, 5, 0.6, 0.5)),           # wrong arguments, no fseq
                   bundle(message(a, "source", "tracker@10.0.0.5")),    # nothing to apply
                   bundle(message(a, "source", "tracker@10.0.0.5"), message(a, "fseq", "x"))]
        for packet in refused:
            ref.send(packet)
        assert sent(src, 4)
        assert src.bad.counts().get("wrong_arguments", 0) >= 2, src.bad.counts()
        now[0] = 2.0        # 2 s after the commit, 1 s after the refused packets
        assert src.latest().pucks == ()
        assert "TUIO from" not in src.health().message, src.health()
        ref.objects([(1, 5, 0.5, 0.5, 0.0)])                          # a valid frame: back
        assert sent(src, 5)
        assert [p.id for p in src.latest().pucks] == [5]
        assert "TUIO from tracker@10.0.0.5" in src.health().message
    finally:
        src.close()


def test_every_refused_mocap_message_names_its_sender(source, caplog):
    """Each kind of refused ``/mocap/NAME`` message is logged with the address it came from,
    as every other refusal is ("from 127.0.0.1"): a technician with several senders on the
    network could not tell which one sent them."""
    import logging
    from pythonosc.osc_message_builder import OscMessageBuilder
    caplog.set_level(logging.WARNING, logger="tabletop.input")
    huge = OscMessageBuilder("/mocap/arm")
    huge.add_arg(1e300, arg_type="d")                   # a double: beyond any feature
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        for m in (message("/mocap/bad name!", 1.0), message("/mocap/arm"),
                  message("/mocap/arm", math.inf), huge.build()):
            s.sendto(m.dgram, ("127.0.0.1", source.bound_port))
    assert sent(source, 4)
    counts = source.bad.counts()
    assert set(counts) == {"unknown_address", "wrong_arguments", "non_finite", "out_of_range"}
    lines = [r.getMessage() for r in caplog.records if "/mocap/" in r.getMessage()
             or "stream name" in r.getMessage()]
    assert len(lines) == 4, lines
    assert all("from 127.0.0.1" in line for line in lines), lines


def test_a_frame_sent_as_single_messages_commits_as_a_bundled_one(source):
    """The reference clients read message by message and keep what is staged until the
    profile's fseq, so a script that sends each TUIO message as its own datagram (python-osc's
    ``send_message``) is read as one that bundles them: its pucks, touches and source name."""
    from pythonosc.udp_client import SimpleUDPClient

    client = SimpleUDPClient("127.0.0.1", source.bound_port)
    frames = [[("/tuio/2Dobj", ["source", "script@here"]), ("/tuio/2Dobj", ["alive", 7]),
               ("/tuio/2Dobj", ["set", 7, 5, 0.25, 0.25, 0.5, 0.0, 0.0, 0.0, 0.0, 0.0]),
               ("/tuio/2Dobj", ["fseq", 1]),
               ("/tuio/2Dcur", ["alive", 3]),
               ("/tuio/2Dcur", ["set", 3, 0.75, 0.5, 0.0, 0.0, 0.0]),
               ("/tuio/2Dcur", ["fseq", 1])],
              [("/tuio/2Dobj", ["alive", 7]),                       # no source this time
               ("/tuio/2Dobj", ["set", 7, 5, 0.5, 0.25, 0.5, 0.0, 0.0, 0.0, 0.0, 0.0]),
               ("/tuio/2Dobj", ["fseq", 2])]]
    n = 0
    for frame in frames:
        for address, args in frame:
            client.send_message(address, args)
            n += 1
    assert sent(source, n)
    obs = source.latest()
    assert [(p.id, round(p.x, 6), round(p.y, 6), round(p.angle, 6)) for p in obs.pucks] == [
        (5, 0.6, 0.6, -0.5)]
    assert [(c.id, round(c.x, 6), round(c.y, 6)) for c in obs.touches] == [(3, 0.9, 0.4)]
    assert source.bad.counts() == {}
    assert "TUIO from script@here" in source.health().message
    client.send_message("/tuio/2Dobj", ["alive"])                    # the puck is lifted
    client.send_message("/tuio/2Dobj", ["fseq", 3])
    assert sent(source, n + 2)
    assert source.latest().pucks == ()


def test_an_unfinished_frame_is_counted_and_does_not_hold_memory(source):
    """A frame whose fseq never comes is counted when the next one begins (a second alive)
    or when it waited ``restart_s``; at most MAX_PENDING such frames are held."""
    from tracking.tuio import MAX_PENDING

    ref = RefSender(source.bound_port)
    ref.send(bundle(message("/tuio/2Dobj", "alive", 1)))
    ref.send(bundle(message("/tuio/2Dobj", "alive", 1),
                    message("/tuio/2Dobj", "set", 1, 4, 0.5, 0.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
                    message("/tuio/2Dobj", "fseq", 1)))
    assert sent(source, 2)
    assert [p.id for p in source.latest().pucks] == [4]
    # (counted by the receiving thread just after the packet is applied)
    assert wait_for(lambda: source.bad.counts() == {"no_fseq": 1}, 5.0), source.bad.counts()
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        for k in range(MAX_PENDING + 20):      # from as many UDP ports
            with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as one:
                one.sendto(bundle(message("/tuio/2Dcur", "alive", k)).dgram,
                           ("127.0.0.1", source.bound_port))
        s.sendto(b"", ("127.0.0.1", source.bound_port))
    assert sent(source, 2 + MAX_PENDING + 20)
    assert len(source.client.pending) <= MAX_PENDING


def test_a_lost_fseq_is_counted_once_and_its_sets_go_with_its_frame(source, caplog):
    """A frame whose ``fseq`` datagram was lost, then a frame whose ``alive`` drops one of its
    sessions: counted once, as ``no_fseq``; the lost frame's sets start nothing in the next
    one (its session 2, not listed by the new alive, is no ``not_alive``)."""
    caplog.set_level("WARNING", logger="tabletop.input")
    ref = RefSender(source.bound_port)
    ref.send(bundle(message("/tuio/2Dobj", "alive", 1, 2),
                    message("/tuio/2Dobj", "set", 1, 4, 0.5, 0.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
                    message("/tuio/2Dobj", "set", 2, 5, 0.2, 0.2, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)))
    ref.send(bundle(message("/tuio/2Dobj", "alive", 1),
                    message("/tuio/2Dobj", "set", 1, 4, 0.6, 0.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
                    message("/tuio/2Dobj", "fseq", 2)))
    assert sent(source, 2)
    assert [p.id for p in source.latest().pucks] == [4]
    # (counted by the receiving thread just after the packet is applied)
    assert wait_for(lambda: source.bad.counts().get("no_fseq") == 1, 5.0), source.bad.counts()
    ref.send(bundle(message("/tuio/2Dobj", "alive", 1),     # a good frame after them: once it
                    message("/tuio/2Dobj", "fseq", 3)))     # is applied, theirs were counted
    assert sent(source, 3)
    assert source.bad.counts() == {"no_fseq": 1}
    assert not any("alive does not list" in r.getMessage() for r in caplog.records)


def test_a_set_that_alive_does_not_list_is_counted(source, caplog):
    """TUIO keeps only what ``alive`` lists: a script sending ``set`` and ``fseq`` without
    ``alive`` got nothing on the bus, and nothing in the log or the health said why."""
    caplog.set_level("WARNING", logger="tabletop.input")
    ref = RefSender(source.bound_port)
    ref.send(bundle(message("/tuio/2Dcur", "set", 3, 0.5, 0.5, 0.0, 0.0, 0.0),
                    message("/tuio/2Dcur", "fseq", 1)))
    # (counted and logged by the receiving thread just after the packet is applied)
    assert wait_for(lambda: any("set of session 3 that alive does not list" in r.getMessage()
                                for r in caplog.records), 5.0)
    assert source.latest() is None
    assert source.bad.counts() == {"not_alive": 1}
    assert "1 not alive" in source.health().message
    ref.cursors([(3, 0.5, 0.5)])                     # with alive: the touch is there
    assert sent(source, 2)
    assert [c.id for c in source.latest().touches] == [3]
    assert source.bad.counts() == {"not_alive": 1}


def test_a_source_name_sent_alone_and_then_nothing_is_no_unfinished_frame(source):
    """A ``source`` message stages nothing: a sender that names itself and sends its first
    frame after a pause is read whole, with its name, and nothing is counted."""
    ref = RefSender(source.bound_port)
    source.client.restart_s = 0.2
    ref.send(message("/tuio/2Dobj", "source", "slow@here"))
    assert sent(source, 1)
    time.sleep(0.3)
    ref.objects([(1, 5, 0.5, 0.5, 0.0)])
    assert sent(source, 2)
    assert [p.id for p in source.latest().pucks] == [5]
    assert source.bad.counts() == {}
    assert "TUIO from slow@here" in source.health().message


def test_class_ids_that_are_no_marker_id_are_refused_and_the_bundle_still_read(source, caplog):
    """The class id of ``/tuio/2Dobj`` is the marker id (a puck id): a negative one, or one
    beyond the largest marker id, is refused (counted ``out_of_range``, one log line naming the
    sender and the id while it repeats), and the other sets of its bundle still make pucks."""
    import logging

    from tabletop.frames import MAX_MARKER_ID

    ref = RefSender(source.bound_port)
    with caplog.at_level(logging.WARNING, logger="tabletop.input"):
        for _ in range(3):
            ref.objects([(9, -5, 0.5, 0.5, 0.0), (10, MAX_MARKER_ID + 1, 0.3, 0.5, 0.0),
                         (11, 3, 0.7, 0.5, 0.0), (12, MAX_MARKER_ID, 0.2, 0.5, 0.0)])
        assert sent(source, 3)
    assert source.bad.counts() == {"out_of_range": 6}
    lines = [r.getMessage() for r in caplog.records]
    assert len(lines) == 1 and "from 127.0.0.1" in lines[0] and "class id -5" in lines[0], lines
    frame = LiveInputs([source], Tracker()).next(0, 0.0)
    assert sorted(p.id for p in frame.pucks) == [3, MAX_MARKER_ID]
