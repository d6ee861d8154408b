"""``tabletop status``: every table's heartbeat on a port, one line each (or ``--json``); bad
heartbeats, bad addresses and durations said in one line; exit status 1 when no table came."""

import json
import re
import socket
import subprocess
import sys
import threading

import pytest

from tabletop.cli import main as cli
from tabletop.kiosk.health import Heartbeat
from tests import children
from tests.network.helpers import free_udp_port, ipv6_loopback
from tracking.scenes import wait_for


def listening(seconds: str, *options: str,
              where: str = "127.0.0.1:{port}") -> tuple[int, threading.Thread, dict]:
    """``tabletop status`` on a free loopback port for ``seconds``, in a thread, once it listens:
    (port, the thread, {"rc": its exit status once joined})."""
    port = free_udp_port(socket.AF_INET6 if where.startswith("[") else socket.AF_INET)
    out: dict = {}
    th = threading.Thread(target=lambda: out.update(
        rc=cli(["status", where.format(port=port), "--seconds", seconds, *options])))
    th.start()
    assert wait_for(lambda: port_taken(port), 5.0)        # the command is listening
    return port, th, out


def test_status_command_prints_every_table(tmp_path, capsys):
    port, th, out = listening("3")
    for name in ("north", "south"):
        hb = Heartbeat("127.0.0.1", port)
        hb.send(name, 12.5, 59.8, 0, json.dumps({"mode": "live", "restarts": 2}))
        hb.close()
    th.join()
    lines = capsys.readouterr().out.splitlines()
    assert out["rc"] == 0 and len(lines) == 2
    assert lines[0].startswith("north") and "59.8 fps" in lines[0] and "restarts 2" in lines[0]
    assert lines[1].startswith("south")


def test_the_seconds_waited_read_in_tenths_below_ten_whole_from_ten():
    from tabletop.commands.status import waited
    assert [waited(s) for s in (0.3, 0.04, 9.94, 9.97, 10.0, 10.4, 61.6)] == \
        ["0.3", "0.0", "9.9", "10", "10", "10", "62"]


def test_status_command_says_when_no_heartbeat_came(capsys):
    # it printed nothing at all: a wrong address looked like a quiet gallery; and it exits 1,
    # so that a monitoring script's `tabletop status ... || alert` alerts (it exited 0)
    port = free_udp_port()
    assert cli(["status", f"127.0.0.1:{port}", "--seconds", "0.3"]) == 1
    cap = capsys.readouterr()
    assert cap.out == "" and "Traceback" not in cap.err
    assert cap.err.splitlines() == [cap.err.strip()]
    assert re.search(rf"no heartbeat came to 127\.0\.0\.1:{port} in \d+\.\d s ", cap.err), cap.err
    assert "kiosk.heartbeat" in cap.err


def test_status_command_with_only_bad_heartbeats_exits_1(capsys):
    # another program's datagrams on the port are no table: said on stderr, and no table came
    from pythonosc.udp_client import SimpleUDPClient
    port, th, out = listening("1")
    bad = SimpleUDPClient("127.0.0.1", port)
    bad.send_message("/tabletop/heartbeat", ["t1", "abc", 1.0, 0, "{}"])      # uptime a word
    th.join()
    cap = capsys.readouterr()
    assert out["rc"] == 1 and cap.out == "" and cap.err.count("bad heartbeat") == 1


def test_absurd_but_finite_heartbeat_fields_are_bad_heartbeats_naming_the_field(capsys):
    """Numbers no table sends (they were printed as they came: "3e+38 fps", "-2 unhealthy",
    "1.5 unhealthy") are a bad heartbeat, one line each naming the field; a table's heartbeat
    after them is printed."""
    from pythonosc.udp_client import SimpleUDPClient
    port, th, out = listening("3")
    bad = SimpleUDPClient("127.0.0.1", port)
    sent = [(["t1", 1.0, 3e38, 0, "{}"], "fps 3e+38 is out of range 0..1500"),
            (["t2", 1.0, 60.0, -2, "{}"], "unhealthy sources -2 is out of range 0..10000"),
            (["t3", 1.0, 60.0, 1.5, "{}"], "unhealthy sources 1.5 is not a whole number"),
            (["t4", -7.0, 60.0, 0, "{}"], "uptime -7 is out of range"),
            (["t5", 1.0, -1.0, 0, "{}"], "fps -1 is out of range 0..1500")]
    for values, _ in sent:
        bad.send_message("/tabletop/heartbeat", values)
    hb = Heartbeat("127.0.0.1", port)
    hb.send("north", 3.0, 60.0, 1, json.dumps({"mode": "live"}))
    hb.close()
    th.join()
    cap = capsys.readouterr()
    assert out["rc"] == 0 and "Traceback" not in cap.err
    err = cap.err.splitlines()
    assert len(err) == len(sent), err
    for line, (_, why) in zip(err, sent):
        assert "bad heartbeat (" + why in line, (line, why)
    assert len(cap.out.splitlines()) == 1 and "60.0 fps  1 unhealthy  live" in cap.out


def test_status_lines_keep_their_columns():
    # (the whole line went through one_line, which collapsed the padding of every column)
    from tabletop.commands.status import format_heartbeat
    a = format_heartbeat("10.0.0.7:50000", "north", 12.5, 59.8, 0, '{"mode": "live"}')
    b = format_heartbeat("10.0.0.12:50123", "gallery-south\nb", 3600.0, 6.0, 1,
                         json.dumps({"mode": "one\nmoment", "restarts": 2}))
    assert a.index(" up ") == b.index(" up ") == 38 and a.index(" fps") == b.index(" fps")
    assert b.startswith("gallery-south b ") and b.endswith("one moment  restarts 2")
    # what anything on the network sends is cut, not printed whole (5000 characters filled
    # the terminal)
    c = format_heartbeat("10.0.0.9:1", "x" * 5000, 1.0, 60.0, 0, json.dumps({"mode": "m" * 900}))
    assert c.startswith("x" * 61 + "... 10.0.0.9:1") and c.endswith("m" * 61 + "...")


def test_status_command_survives_bad_heartbeats(capsys):
    """Another program sending wrong heartbeats to the port gets one line each on stderr, and
    the tables after it are still printed (no traceback, the listener keeps listening)."""
    from pythonosc.udp_client import SimpleUDPClient
    port, th, out = listening("3")
    bad = SimpleUDPClient("127.0.0.1", port)
    bad.send_message("/tabletop/heartbeat", ["t1", "abc", 1.0, 0, "{}"])      # uptime a word
    bad.send_message("/tabletop/heartbeat", ["t2", 1.0, 2.0, 0, 7])           # status a number
    bad.send_message("/tabletop/heartbeat", ["t3", 1.0, 2.0, 0])              # too few
    bad.send_message("/tabletop/heartbeat", ["t4", 1.0, 2.0, 0.5, "{}"])      # half a source
    bad.send_message("/tabletop/heartbeat", ["t5", -1.0, 2.0, 0, "{}"])       # uptime < 0
    hb = Heartbeat("127.0.0.1", port)
    hb.send("north\nfake", 3.0, 60.0, 0, "[1, 2]")  # JSON that is no status: shown as "?"
    hb.close()
    th.join()
    cap = capsys.readouterr()
    assert out["rc"] == 0 and "Traceback" not in cap.err
    assert len(cap.err.splitlines()) == 5 and cap.err.count("bad heartbeat") == 5, cap.err
    assert "(unhealthy sources 0.5 is not a whole number)" in cap.err
    assert "(uptime -1 is out of range 0..3.15576e+09)" in cap.err
    lines = cap.out.splitlines()
    assert len(lines) == 1 and lines[0].startswith("north fake") and lines[0].endswith("?")


def _no_osc(port: int) -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as stray:
        for i in range(200):
            stray.sendto(b"DMX %d" % i, ("127.0.0.1", port))
    return 0


def _four_values(port: int) -> int:
    from pythonosc.udp_client import SimpleUDPClient
    bad = SimpleUDPClient("127.0.0.1", port)
    for i in range(200):
        bad.send_message("/tabletop/heartbeat", ["t1", float(i), 60.0, 0])
    return bad._sock.getsockname()[1]


@pytest.mark.parametrize("flood, words", [
    (_no_osc, "refused: message at byte 0 does not start with an address"),
    (_four_values, "127.0.0.1:{port}: bad heartbeat (4 values, expected 5)")])
def test_a_flood_of_what_no_table_sends_is_said_once_and_tables_still_shown(capsys, flood,
                                                                             words):
    """Another program sending 200 datagrams at once to the port, no OSC at all or heartbeats
    of 4 values (another version): one line for them, not one each (60 a second filled the
    terminal; 300 bad heartbeats in 1.5 s were 300 lines), and a table's heartbeat still
    shown. How many were held back is said as the command ends (it never was: the 199 after
    the first line went unsaid, with nothing to tell a flood from one stray datagram)."""
    port, th, out = listening("2")
    sender = flood(port)
    hb = Heartbeat("127.0.0.1", port)
    hb.send("north", 3.0, 60.0, 0, json.dumps({"mode": "live"}))
    hb.close()
    th.join()
    cap = capsys.readouterr()
    assert out["rc"] == 0 and len(cap.out.splitlines()) == 1, cap.out
    err = cap.err.splitlines()
    assert len(err) == 2 and words.format(port=sender) in err[0], cap.err
    held = re.fullmatch(r"tabletop status: (\d+) more like the lines above not said \(the same "
                        r"fault from the same sender is said once, then after 10 s, 20 s, "
                        r"\.\.\.\)", err[1])
    assert held and 150 <= int(held[1]) <= 199, err[1]   # (loopback UDP may drop a few)


@pytest.mark.parametrize("address", ["nowhere", "h:99999", "h:x", "h:", ":9000", "::1",
                                     "::1:9000", "[::1]", "[::1]9000", "[nowhere]:9000",
                                     "[127.0.0.1]:9000", "[::1]:0", "h:+90", "h:1e3"])
def test_status_command_refuses_a_bad_address(address, capsys):
    """One message for every malformed address (an unbracketed IPv6 address too: ``::1:9000``
    could be [::1]:9000 or [::]:19000), naming the form, the ports and the brackets."""
    assert cli(["status", address, "--seconds", "1"]) == 2
    err = capsys.readouterr().err
    assert f"address {address!r}: expected HOST:PORT (port 1..65535; an IPv6 address in " \
           "brackets), e.g. 0.0.0.0:9000 or [::1]:9000" in err
    assert "Traceback" not in err and len(err.splitlines()) == 1


@pytest.mark.skipif(not ipv6_loopback(), reason="this machine has no IPv6 loopback (::1)")
def test_status_command_listens_on_an_ipv6_address_in_brackets(capsys):
    """``tabletop status [::1]:9000`` was refused ("port ... must be 1..65535" or a socket
    error for the host "[::1]"): a table's heartbeat sent to ::1 is printed, its sender in
    brackets, and a silent address is named as it was given."""
    port, th, out = listening("2", where="[::1]:{port}")
    hb = Heartbeat("::1", port)
    hb.send("north", 12.5, 59.8, 0, json.dumps({"mode": "live"}))
    hb.close()
    th.join()
    cap = capsys.readouterr()
    (line,) = cap.out.splitlines()
    assert out["rc"] == 0 and line.startswith("north            [::1]:") and "59.8 fps" in line
    silent = free_udp_port(socket.AF_INET6)
    assert cli(["status", f"[::1]:{silent}", "--seconds", "0.2"]) == 1
    err = capsys.readouterr().err
    assert re.search(rf"no heartbeat came to \[::1\]:{silent} in \d+\.\d s ", err), err


@pytest.mark.skipif(not ipv6_loopback(), reason="this machine has no IPv6 loopback (::1)")
def test_an_ipv4_table_heard_on_every_interface_is_named_by_its_ipv4_address(capsys):
    """``tabletop status [::]:9000`` (every IPv6 and IPv4 interface) hears IPv4 tables as
    ::ffff:A.B.C.D; the line names the table as the IPv4 address it sends from, in its column
    (it showed [::ffff:127.0.0.1]:PORT, wider than the column)."""
    port, th, out = listening("2", where="[::]:{port}")
    hb = Heartbeat("127.0.0.1", port)
    hb.send("north", 12.5, 59.8, 0, json.dumps({"mode": "live"}))
    hb.close()
    th.join()
    (line,) = capsys.readouterr().out.splitlines()
    assert out["rc"] == 0
    assert re.match(r"north            127\.0\.0\.1:\d+ +up", line), line


@pytest.mark.parametrize("seconds", ["1e300", "nan", "-1", "0"])
def test_status_command_refuses_a_bad_duration(seconds, capsys):
    """--seconds 1e300 overflowed the stop timer in its thread (a traceback, then listening
    for ever): refused in one line like run's --seconds."""
    assert cli(["status", f"127.0.0.1:{free_udp_port()}", "--seconds", seconds]) == 2
    err = capsys.readouterr().err
    assert "--seconds" in err and "Traceback" not in err and len(err.splitlines()) == 1


def port_taken(port: int) -> bool:
    """Whether a UDP socket is bound to ``port``, read from the kernel's socket table (binding
    the port to find out would race the command binding it)."""
    for name in ("/proc/net/udp", "/proc/net/udp6"):
        with open(name) as table:
            next(table)
            if any(int(line.split()[1].split(":")[1], 16) == port for line in table):
                return True
    return False


def status_process(*options: str, text: bool = True) -> tuple[subprocess.Popen, int]:
    """``python -m tabletop status 127.0.0.1:PORT OPTIONS`` on a free port, returned with the
    port once the command has bound it (stdout and stderr piped)."""
    port = free_udp_port()
    proc = children.popen([sys.executable, "-m", "tabletop", "status", f"127.0.0.1:{port}",
                           *options], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=text)
    if not wait_for(lambda: port_taken(port), 60.0):
        proc.kill()
        proc.communicate()
        raise AssertionError(f"status never bound port {port}")
    return proc, port


def test_status_json_prints_only_json_objects(tmp_path, capsys):
    """An outside script reads ``tabletop status --json`` line by line with json.loads: a
    datagram on the port whose status is not a JSON object was printed as it came ("{not
    json"), breaking the script. It is a bad heartbeat now (one line on stderr)."""
    port, th, out = listening("2", "--json")
    hb = Heartbeat("127.0.0.1", port)
    for status in ("{not json", "[1, 2]", '{"fps": NaN}', '{\n  "mode": "live"\n}'):
        hb.send("north", 1.0, 60.0, 0, status)
    hb.close()
    th.join()
    captured = capsys.readouterr()
    lines = captured.out.splitlines()
    assert out["rc"] == 0 and [json.loads(x) for x in lines] == [{"mode": "live"}], lines
    # (three of one kind from one sender at once: said once, as a flood of them is)
    assert captured.err.count("bad heartbeat (status is not a JSON object)") == 1, captured.err
    assert captured.err.splitlines()[-1].startswith(   # the two held back counted, as it ends
        "tabletop status: 2 more like the lines above not said"), captured.err


def test_ctrl_c_ends_a_timed_status_at_once():
    """``status HOST:PORT --seconds 120`` stopped with Ctrl-C after a heartbeat: it ends at once
    with the heartbeat's line and status 0, no traceback (a --seconds timer that is not a
    daemon thread would keep the process for the rest of the 120 s, and a second Ctrl-C would
    print a traceback from threading's shutdown)."""
    import signal
    proc, port = status_process("--seconds", "120")
    try:
        hb = Heartbeat("127.0.0.1", port)
        hb.send("north", 12.5, 59.8, 0, json.dumps({"mode": "live"}))
        hb.close()
        first = proc.stdout.readline()       # the line of that heartbeat: it was served
        assert first.startswith("north"), first
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=60)   # ends at the interrupt, not after --seconds
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 0 and out == "" and err == "", err


def test_a_reader_that_closes_the_status_early_ends_it_quietly_with_141():
    """``tabletop status HOST:PORT --json | head -1``: after its first line the reader is gone;
    the command ends at the next heartbeat with status 141 and nothing on stderr (no traceback
    for each later heartbeat's BrokenPipeError, no listening on for ever)."""
    proc, port = status_process("--json", text=False)
    hb = Heartbeat("127.0.0.1", port)
    try:
        hb.send("north", 1.0, 60.0, 0, json.dumps({"mode": "live"}))
        first = proc.stdout.readline()
        assert json.loads(first) == {"mode": "live"}, first
        proc.stdout.close()                   # head -1 has its line and is gone
        beat = 1
        while proc.poll() is None and beat < 300:   # one heartbeat more is enough
            hb.send("north", 1.0 + beat, 60.0, 0, json.dumps({"mode": "live"}))
            beat += 1
            wait_for(lambda: proc.poll() is not None, 0.1)
    finally:
        hb.close()
        if proc.poll() is None:
            proc.kill()
            proc.wait(10)
    err = proc.stderr.read().decode()
    assert proc.returncode == 141 and err == "", err[-2000:]


def test_a_packet_the_osc_decoder_refuses_is_one_line_and_status_goes_on(capsys):
    """A stray sender's packet with a string that is no UTF-8 (python-osc raises
    UnicodeDecodeError while decoding it): one line on stderr naming the sender, and the
    heartbeat after it is still shown; it ended the command (status 1, an internal error)."""
    def pad(b: bytes) -> bytes:
        return b + b"\0" * (4 - len(b) % 4)
    port, th, out = listening("2")
    stray = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    stray.sendto(pad(b"/tabletop/heartbeat") + pad(b",s") + pad(b"\xff\xfe"), ("127.0.0.1", port))
    stray.close()
    hb = Heartbeat("127.0.0.1", port)
    hb.send("north", 3.0, 60.0, 0, json.dumps({"mode": "live"}))
    hb.close()
    th.join()
    cap = capsys.readouterr()
    assert out["rc"] == 0 and "Traceback" not in cap.err, cap.err
    assert len(cap.err.splitlines()) == 1 and "refused" in cap.err and "127.0.0.1" in cap.err
    assert len(cap.out.splitlines()) == 1 and cap.out.startswith("north")


def test_a_heartbeat_of_any_size_and_timetag_is_shown_and_status_ends_on_time():
    """Datagrams of tables and of stray senders, as they come: a table's heartbeat of 12 kB
    (many sources with their messages) is shown, as is one in a bundle tagged for 2036 (shown
    at once, not held until then: ``--seconds`` still ends the command on time); a stray
    datagram with a type tag OSC does not have is one line naming its sender, and so is a
    datagram that is no OSC at all."""
    from tracking.osc_codec import encode_bundle, encode_message
    proc, port = status_process("--seconds", "3")
    try:
        big = json.dumps({"mode": "live", "sources": [{"name": f"s{i}", "message": "m" * 200}
                                                      for i in range(50)]})
        hb = Heartbeat("127.0.0.1", port)
        hb.send("big", 1.0, 60.0, 50, big)
        hb.close()
        later = encode_message("/tabletop/heartbeat", ["later", 2.0, 60.0, 0, '{"mode": "x"}'])
        stray = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        stray.sendto(encode_bundle([later], timetag=0xFFFFFFF0 << 32), ("127.0.0.1", port))
        odd = encode_message("/tabletop/heartbeat", ["odd"]).replace(b",s\0\0", b",Z\0\0")
        stray.sendto(odd, ("127.0.0.1", port))
        stray.sendto(b"\xff" * 40, ("127.0.0.1", port))
        stray.close()
        out, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait(10)
    assert len(big) > 8192 and proc.returncode == 0, err
    assert [line.split()[0] for line in out.splitlines()] == ["big", "later"], out
    lines = err.splitlines()
    assert len(lines) == 2 and all(line.startswith("tabletop status: a packet from 127.0.0.1:")
                                   for line in lines), err
    assert "unknown type tag 'Z'" in lines[0] and "WARNING" not in err
