"""The ``osc`` source on a real loopback socket, fed by a python-osc sender that sends as the TUIO
reference server does (one bundle per profile: source, alive, set..., fseq)."""

import math
import socket
import time

import pytest

from tabletop.loop import LiveInputs
from tabletop.plugins.tracking import Tracker
from tracking.osc_input import HOLD_S, OscInput
from tracking.pucks import TrackerSettings

from tests.network.helpers import TABLE, RefSender, bundle, ipv6_loopback, message, sent, wait_for


def pucks_by_id(src):
    return {p.id: p for p in src.latest().pucks}


def test_objects_and_cursors_map_to_table_metres(source):
    ref = RefSender(source.bound_port)
    ref.objects([(10, 5, 0.25, 0.25, 0.5), (11, 9, 0.9, 0.1, 6.0)])
    ref.cursors([(3, 0.5, 0.75)])
    blob = message("/tuio/2Dblb", "set", 4, 0.1, 0.2, 0.0, 0.05, 0.05, 0.01, 0.0, 0.0, 0.0, 0.0,
                   0.0)
    ref.send(bundle(message("/tuio/2Dblb", "alive", 4), blob, message("/tuio/2Dblb", "fseq", 1)))
    assert sent(source, 3)
    obs = source.latest()
    p = {m.id: m for m in obs.pucks}
    assert set(p) == {5, 9}
    assert p[5].x == pytest.approx(0.3, abs=1e-6) and p[5].y == pytest.approx(0.6, abs=1e-6)
    assert p[5].angle == pytest.approx(-0.5, abs=1e-6)  # clockwise on screen -> ccw on the table
    assert p[9].x == pytest.approx(1.08, abs=1e-6) and p[9].y == pytest.approx(0.72, abs=1e-6)
    assert p[9].angle == pytest.approx(2 * math.pi - 6.0, abs=1e-6)  # wrapped to (-pi, pi]
    t = {c.id: c for c in obs.touches}
    assert set(t) == {3, 4}  # the session id is the touch id
    assert (t[3].x, t[3].y) == pytest.approx((0.6, 0.2), abs=1e-6)
    assert (t[4].x, t[4].y) == pytest.approx((0.12, 0.64), abs=1e-6)
    assert source.bad.counts() == {}
    assert source.health().ok


def test_late_fseq_is_dropped_and_equal_fseq_commits(source):
    ref = RefSender(source.bound_port)
    ref.objects([(1, 5, 0.1, 0.5, 0.0)], fseq=10)
    ref.objects([(1, 5, 0.9, 0.5, 0.0)], fseq=9)      # late: dropped
    assert sent(source, 2)
    assert pucks_by_id(source)[5].x == pytest.approx(0.12, abs=1e-6)
    assert source.bad.counts() == {"late_fseq": 1}
    ref.objects([(1, 5, 0.2, 0.5, 0.0)], fseq=10)     # a split frame's second bundle
    assert sent(source, 3)
    assert pucks_by_id(source)[5].x == pytest.approx(0.24, abs=1e-6)
    ref.objects([(1, 5, 0.3, 0.5, 0.0)], fseq=-1)     # a redundant resend always commits
    assert sent(source, 4)
    assert pucks_by_id(source)[5].x == pytest.approx(0.36, abs=1e-6)


def test_restarted_sender_is_accepted(source):
    ref = RefSender(source.bound_port, source="tracker@10.0.0.5")
    ref.objects([(40, 5, 0.1, 0.5, 0.0)], fseq=500)
    ref.objects([(1, 5, 0.7, 0.5, 0.0)], fseq=1)     # 499 frames back: the sender restarted
    assert sent(source, 2)
    assert pucks_by_id(source)[5].x == pytest.approx(0.84, abs=1e-6)
    ref.objects([(1, 5, 0.2, 0.5, 0.0)], fseq=450)
    ref.objects([(1, 5, 0.8, 0.5, 0.0)], fseq=400)   # 50 back: late, not a restart
    assert sent(source, 4)
    assert pucks_by_id(source)[5].x == pytest.approx(0.24, abs=1e-6)
    source.client.restart_s = 0.2                     # a sender silent that long restarted
    time.sleep(0.3)
    ref.objects([(1, 5, 0.5, 0.5, 0.0)], fseq=420)
    assert sent(source, 5)
    assert pucks_by_id(source)[5].x == pytest.approx(0.6, abs=1e-6)


def test_an_id_missing_from_alive_leaves_the_bus_at_once(source):
    inputs = LiveInputs([source], Tracker(TrackerSettings(smooth=False)))
    ref = RefSender(source.bound_port)
    ref.objects([(1, 5, 0.2, 0.5, 0.0), (2, 6, 0.6, 0.5, 0.0)])
    ref.cursors([(7, 0.5, 0.5), (8, 0.6, 0.6)])
    assert sent(source, 2)
    f = inputs.next(0, 0.0)
    assert [p.id for p in f.pucks] == [5, 6] and all(p.state == "seen" for p in f.pucks)
    assert sorted(c.id for c in f.touches) == [7, 8]
    ref.objects([(1, 5, 0.21, 0.5, 0.0)])            # session 2 no longer alive
    ref.cursors([(8, 0.6, 0.6)])
    assert sent(source, 4)
    f = inputs.next(1, 0.0)
    assert [p.id for p in f.pucks] == [5]            # gone, not coasting
    assert [c.id for c in f.touches] == [8]


def test_senders_with_different_sources_do_not_mix(source):
    a = RefSender(source.bound_port, source="tableA@10.0.0.1")
    b = RefSender(source.bound_port, source="tableB@10.0.0.2")
    a.objects([(1, 5, 0.1, 0.5, 0.0)], fseq=1000)
    b.objects([(1, 6, 0.9, 0.5, 0.0)], fseq=1)       # same session id, far lower fseq
    assert sent(source, 2)
    p = pucks_by_id(source)
    assert set(p) == {5, 6}
    assert p[6].x == pytest.approx(1.08, abs=1e-6)
    assert "TUIO from tableA@10.0.0.1, tableB@10.0.0.2" in source.health().message
    a.objects([], fseq=1001)                          # A's alive is empty: only A's object goes
    assert sent(source, 3)
    assert set(pucks_by_id(source)) == {6}
    assert len(source.client.senders) == 2


def test_machines_sending_one_source_name_do_not_mix(source):
    """Cloned machines (one image, one host name) send one default name, tabletop@HOSTNAME:
    kept apart by their IP addresses, each machine's pucks stay (each bundle replaced the
    other's alive list, and one machine's pucks flickered away at every packet)."""
    a = RefSender(source.bound_port, source="tabletop@raspberrypi")          # from 127.0.0.1
    b = RefSender(0, source="tabletop@raspberrypi")
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as other:
        other.bind(("127.0.0.2", 0))                                          # another machine
        for fseq in range(1, 4):
            a.objects([(1, 5, 0.2, 0.5, 0.0)], fseq=fseq)
            other.sendto(b.profile_bundle("2Dobj", [1], [
                (1, 6, 0.8, 0.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)], 1000 + fseq).dgram,
                ("127.0.0.1", source.bound_port))
            assert sent(source, 2 * fseq)
            assert set(pucks_by_id(source)) == {5, 6}
    assert source.bad.counts() == {}
    assert ("TUIO from tabletop@raspberrypi from 127.0.0.1, tabletop@raspberrypi from "
            "127.0.0.2" in source.health().message)


def test_a_quiet_sender_coasts_then_leaves():
    src = OscInput("osc", port=0, table=TABLE, quiet_s=0.2)
    src.open()
    try:
        assert src.wait_listening()
        tracker = Tracker(TrackerSettings(smooth=False, coast_s=0.5))
        inputs = LiveInputs([src], tracker)
        ref = RefSender(src.bound_port)
        ref.objects([(1, 5, 0.5, 0.5, 0.0)])
        ref.cursors([(2, 0.5, 0.5)])
        ref.send(message("/mocap/hand", 1.0))
        assert sent(src, 3)
        f = inputs.next(0, 0.0)
        assert [p.state for p in f.pucks] == ["seen"] and len(f.touches) == 1
        assert wait_for(lambda: [p.state for p in inputs.next(1, 0.0).pucks] == ["coasting"], 2.0)

        def bare() -> bool:   # touches and streams do not coast: gone while the puck coasts
            f = inputs.next(1, 0.0)   # (the stream was heard a moment after the puck's bundle)
            return [p.state for p in f.pucks] == ["coasting"] and f.touches == () \
                and dict(f.streams) == {}
        assert wait_for(bare, 0.3)
        assert wait_for(lambda: inputs.next(2, 0.0).pucks == (), 2.0)
    finally:
        src.close()


def test_mocap_vectors_become_named_streams(source):
    ref = RefSender(source.bound_port)
    ref.send(message("/mocap/hand", 0.25, -1.5, 3.0))
    ref.send(message("/mocap/left/elbow", 1, 2))      # ints are numbers too
    ref.send(message("/mocap/bad", "x", 1.0))         # not a vector of numbers
    ref.send(message("/mocap/nan", float("nan")))
    assert sent(source, 4)
    streams = source.latest().streams
    assert set(streams) == {"hand", "left/elbow"}
    assert streams["hand"].tolist() == [0.25, -1.5, 3.0]
    assert source.bad.counts() == {"wrong_arguments": 1, "non_finite": 1}


def test_mocap_doubles_too_large_to_follow_are_refused(source):
    """An OSC double of 1e160 in a followed stream made the follower's probabilities NaN (and
    the follow command stopped with an IndexError): refused as out_of_range."""
    from pythonosc.osc_message_builder import OscMessageBuilder
    ref = RefSender(source.bound_port)
    for v in (1e160, 1e99):
        b = OscMessageBuilder("/mocap/hand")
        b.add_arg(0.5, "d")
        b.add_arg(v, "d")
        ref.send(b.build())
    assert sent(source, 2)
    assert source.latest().streams["hand"].tolist() == [0.5, 1e99]
    assert source.bad.counts() == {"out_of_range": 1}


def test_a_sender_not_on_the_allow_list_changes_nothing():
    src = OscInput("osc", port=0, table=TABLE, allow=["127.0.0.2"])
    src.open()
    try:
        assert src.wait_listening()
        RefSender(src.bound_port).objects([(1, 5, 0.5, 0.5, 0.0)])  # from 127.0.0.1
        assert wait_for(lambda: src.bad.counts().get("not_allowed") == 1, 5.0)
        assert src.latest() is None and src.packets == 0
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
            s.bind(("127.0.0.2", 0))                  # the allowed address sends the same
            s.sendto(RefSender(0).profile_bundle("2Dobj", [1], [
                (1, 5, 0.5, 0.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)], 1).dgram,
                ("127.0.0.1", src.bound_port))
        assert sent(src, 1)
        assert [p.id for p in src.latest().pucks] == [5]
    finally:
        src.close()


@pytest.mark.skipif(not ipv6_loopback(), reason="no IPv6 on this machine")
def test_an_allowed_ipv4_sender_reaches_a_source_listening_on_every_ipv6_and_ipv4_interface():
    """host "::" takes IPv4 senders too, as ::ffff:127.0.0.1: the allow-list's 127.0.0.1 is
    that sender (every one was refused), and the health names it as the allow-list does."""
    src = OscInput("osc", host="::", port=0, table=TABLE, allow=["127.0.0.1"])
    src.open()
    try:
        assert src.wait_listening()
        RefSender(src.bound_port).cursors([(3, 0.5, 0.5)])           # from 127.0.0.1
        assert sent(src, 1)
        assert [c.id for c in src.latest().touches] == [3]
        assert src.bad.counts() == {}
        assert "TUIO from 127.0.0.1:" in src.health().message
    finally:
        src.close()


def test_a_busy_port_is_retried_and_reported(caplog):
    caplog.set_level("INFO", logger="tabletop.osc")
    first = OscInput("first", port=0, table=TABLE)
    first.open()
    assert first.wait_listening()
    second = OscInput("second", port=first.bound_port, table=TABLE, retry_min_s=0.05,
                      retry_max_s=0.1)
    second.open()
    try:
        assert wait_for(lambda: "cannot listen" in second.health().message, 5.0)
        assert not second.health().ok
        first.close()
        assert second.wait_listening(5.0)
        RefSender(second.bound_port).objects([(1, 5, 0.5, 0.5, 0.0)])
        assert sent(second, 1)
        said = [r.getMessage() for r in caplog.records if r.name == "tabletop.osc"]
        assert len([m for m in said if "cannot listen" in m]) == 1, said  # once, not per retry
        assert not any("ignored" in m for m in said) and any("listening on" in m for m in said)
    finally:
        first.close()
        second.close()


def test_class_ids_go_through_the_puck_id_map(source):
    inputs = LiveInputs([source], Tracker(TrackerSettings(smooth=False), id_map={17: 1}))
    ref = RefSender(source.bound_port)
    ref.objects([(1, 17, 0.5, 0.5, 0.0), (2, 6, 0.6, 0.5, 0.0)])
    assert sent(source, 1)
    assert [p.id for p in inputs.next(0, 0.0).pucks] == [1, 6]    # marker 17 is puck 1
    ref.objects([(2, 6, 0.6, 0.5, 0.0)])
    assert sent(source, 2)
    assert [p.id for p in inputs.next(1, 0.0).pucks] == [6]       # and it leaves as puck 1


def test_bad_packet_counts_show_in_the_overlay(source):
    from tabletop.view import overlay_lines

    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        for data in (b"\x00garbage", b"#bundle\x00\x00", b"/unknown\x00\x00\x00\x00,\x00\x00\x00"):
            s.sendto(data, ("127.0.0.1", source.bound_port))
    assert wait_for(lambda: source.bad.total() == 3, 5.0)
    frame = LiveInputs([source], Tracker()).next(0, 0.0)
    line, = [t for t in overlay_lines(frame, None) if t.startswith("source osc:")]
    assert "ignored: 2 malformed, 1 unknown address" in line


def test_sent_velocities_reach_the_frame_mapped_like_positions(source):
    """X, Y (TUIO units/s, y down) and A (turns/s, clockwise) of a 2Dobj set become the puck's
    vx = X * W, vy = -Y * H (m/s) and omega = -2 pi A (rad/s), as positions and angles map;
    the tracker does not replace them by its estimate from positions (which says 0 for a puck
    whose sender holds its position while reporting it moving)."""
    inputs = LiveInputs([source], Tracker(TrackerSettings(smooth=False)))
    ref = RefSender(source.bound_port)
    for k in range(3):
        ref.objects([(1, 5, 0.5, 0.5, 0.0, 0.25, -0.5, 0.125)])
        assert sent(source, k + 1)
        f = inputs.next(k, 0.0)
    m, = source.latest().pucks
    assert (m.vx, m.vy, m.omega) == pytest.approx((0.3, 0.4, -math.pi / 4), abs=1e-6)
    p, = f.pucks
    assert p.state == "seen"
    assert (p.vx, p.vy, p.omega) == pytest.approx((0.3, 0.4, -math.pi / 4), abs=1e-6)
    ref.objects([(1, 5, 0.5, 0.5, 0.0)])              # the sender says it stopped
    assert sent(source, 4)
    p, = inputs.next(3, 0.0).pucks
    assert (p.vx, p.vy, p.omega) == (0.0, 0.0, 0.0)
    ref.objects([(1, 5, 0.5, 0.5, 0.0, 0.25, -0.5, 0.125)])
    assert sent(source, 5)
    time.sleep(2 * HOLD_S)                            # then falls silent: its state is held
    m, = source.latest().pucks
    assert math.isnan(m.vx) and math.isnan(m.vy) and math.isnan(m.omega)


def test_a_held_tuio_state_is_not_counted_as_capture_to_render_latency():
    """While a sender's state is held (nothing new for over HOLD_S) the frame clock moves on at
    now - HOLD_S; those ticks carry no capture, yet each was recorded as 100 ms of
    capture-to-render latency (the overlay and the run's last line read ~100 ms median for a
    TUIO table at rest). Only ticks carrying a capture count."""
    from tabletop.loop import Loop, LoopStats
    src = OscInput("osc", port=0, table=TABLE)
    src.open()
    try:
        assert src.wait_listening()
        stats = LoopStats()
        loop = Loop(LiveInputs([src], Tracker()), [], [], rate_hz=60.0, stats=stats)
        RefSender(src.bound_port).objects([(1, 5, 0.5, 0.5, 0.0)])
        assert sent(src, 1)
        loop.run(seconds=1.0)                          # held after the first 0.1 s
        ages = list(stats.samples.get("capture_age", ()))
        # one capture, so one age at most (none if the first tick came after HOLD_S), however
        # few ticks a loaded machine runs past the HOLD_S
        assert len(ages) <= 1 and stats.ticks >= 2, (ages, stats.ticks)
    finally:
        src.close()



def test_a_tuio_2_tracker_or_another_profile_is_named_in_the_log(caplog):
    """A TUIO 2.0 tracker (``/tuio2/...``) and a 1.1 profile not read (``/tuio/3Dobj``) were
    logged only as "unknown address"; the line now says which, and what is read."""
    caplog.set_level("WARNING", logger="tabletop")
    said = {}
    for name, m in (("two", message("/tuio2/tok", 1, 0, 3, 0.5, 0.5, 0.0)),
                    ("three", message("/tuio/3Dobj", "alive", 1)),
                    ("other", message("/unknown", 1))):
        src = OscInput(name, port=0)
        src.open()
        try:
            assert src.wait_listening()
            with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
                s.sendto(m.dgram, ("127.0.0.1", src.bound_port))
            assert wait_for(lambda: src.bad.counts() == {"unknown_address": 1}, 5.0)
        finally:
            src.close()
        said[name], = [r.getMessage() for r in caplog.records if r.getMessage().startswith(
            f"{name}: ignored")]
    assert said["two"].endswith("'/tuio2/tok' from 127.0.0.1: TUIO 2.0, which is not read; "
                                "set the sender to TUIO 1.1"), said
    assert said["three"].endswith(": a TUIO 1.1 profile not read (only /tuio/2Dobj, "
                                  "/tuio/2Dcur, /tuio/2Dblb)"), said
    assert said["other"].endswith("'/unknown' from 127.0.0.1"), said
