"""The ``serial`` source through real pseudo-terminals, pyserial's ``loop://`` and ``socket://``."""

import math
import os
import socket
from contextlib import contextmanager

import pytest

from tabletop.loop import LiveInputs
from tabletop.plugins.tracking import Tracker
from tracking.pucks import TrackerSettings
from tracking.serial_input import (MAX_LINE, Command, LineError, LineSplitter, SerialInput,
                                   parse_line)

from tests.network.helpers import ipv6_loopback, wait_for


@pytest.mark.parametrize("line, command", [
    (b"puck 3 0.5 0.25 -1.5", Command("puck", 3, values=(0.5, 0.25, -1.5))),
    (b"touch 12  0.1\t0.2\r", Command("touch", 12, values=(0.1, 0.2))),
    (b"lift 12", Command("lift", 12)),
    (b"stream hand 1 2.5 -3e-2", Command("stream", name="hand", values=(1.0, 2.5, -0.03))),
    (b"# a comment", None),
    (b"lift 4   # the finger left", Command("lift", 4)),
    (b"puck 2 0.5 0.25 7.0", Command("puck", 2, values=(0.5, 0.25, 7.0 - 2 * math.pi))),
    (b"", None),
    (b"touch 1 +.5 -3.", Command("touch", 1, values=(0.5, -3.0))),
    (b"stream hand 1E2 -0.25e+1 7", Command("stream", name="hand", values=(100.0, -2.5, 7.0))),
])
def test_lines_parse(line, command):
    assert parse_line(line) == command


@pytest.mark.parametrize("line, kind", [
    (b"puck 3 0.5 0.25", "wrong_arguments"),
    (b"puck x 0.5 0.25 0", "wrong_arguments"),
    (b"puck 3 0.5 nan 0", "non_finite"),
    (b"touch 1 inf 0", "non_finite"),
    (b"touch 1 1e9 0", "out_of_range"),
    (b"stream 1", "wrong_arguments"),
    (b"stream b@d 1", "wrong_arguments"),
    (b"stream hand 1 -1e200", "out_of_range"),   # a followed stream became NaN
    (b"jump 1 2", "unknown_command"),
    (b"\x00\x01\x02", "garbage"),
    (b"puck \xff 1 2 3", "garbage"),
    (b"puck 3 1_0 0 0", "wrong_arguments"),    # float() reads 10
    (b"touch 1 0x1 0", "wrong_arguments"),
    (b"touch 1 1e 0", "wrong_arguments"),
    (b"stream hand 1 1__2", "wrong_arguments"),
    (b"stream hand 1 0_.5", "wrong_arguments"),
    (b"touch 1 -nan 0", "non_finite"),
    (b"touch 1 +Infinity 0", "non_finite"),
])
def test_bad_lines_name_their_kind(line, kind):
    with pytest.raises(LineError) as info:
        parse_line(line)
    assert info.value.kind == kind


def test_the_splitter_holds_at_most_one_line_and_skips_overlong_ones():
    s = LineSplitter()
    assert s.feed(b"puck 1 0 0 0\r\npartial") == [b"puck 1 0 0 0\r"]
    assert s.feed(b" line\n") == [b"partial line"]
    for _ in range(500):                           # a line without a newline, for minutes
        assert s.feed(b"x" * 100) == []
        assert len(s._buf) <= MAX_LINE + 1          # the line and the \r of a \r\n
    assert s.overlong == 1
    assert s.feed(b"tail of it\nlift 1\n") == [b"lift 1"]
    assert s.feed(b"y" * (MAX_LINE + 1) + b"\nlift 2\n") == [b"lift 2"]
    assert s.overlong == 2


@pytest.mark.parametrize("ending", [b"\n", b"\r\n"])
def test_a_line_of_exactly_max_line_bytes_passes_with_either_ending(ending):
    """DESIGN: at most 1024 bytes a line, ended by \\n or \\r\\n (an Arduino's println
    sends \\r\\n): the ending does not count, whole or fed byte by byte."""
    line = b"stream hand " + b"0.5 " * ((MAX_LINE - 12) // 4)
    line = line + b"1" * (MAX_LINE - len(line))
    assert len(line) == MAX_LINE and parse_line(line.rstrip(b"\r")) is not None
    for chunks in ([line + ending], [bytes([b]) for b in line + ending]):
        s = LineSplitter()
        got = [out for c in chunks for out in s.feed(c)]
        assert got == [line + ending[:-1]] and s.overlong == 0
    s = LineSplitter()                                   # one byte more is too long
    assert s.feed(b"x" + line + ending + b"lift 1\n") == [b"lift 1"] and s.overlong == 1


def open_pty():
    master, slave = os.openpty()
    return master, slave, os.ttyname(slave)


@contextmanager
def tracked_pty(timeout_s: float):
    """A serial source on a fresh pseudo-terminal, open and healthy, with the tracker's inputs:
    yields (the terminal's master end, the source, the inputs)."""
    master, slave, name = open_pty()
    src = SerialInput("mcu", name, timeout_s=timeout_s)
    inputs = LiveInputs([src], Tracker(TrackerSettings(smooth=False)))
    src.open()
    try:
        assert wait_for(lambda: src.health().ok, 5.0)
        yield master, src, inputs
    finally:
        src.close()
        os.close(master)
        os.close(slave)


def test_lines_through_a_pty_become_pucks_touches_and_streams():
    with tracked_pty(0.3) as (master, src, inputs):
        os.write(master, b"puck 4 0.5 0.25 1.0\ntouch 2 0.1 0.2\r\nstream hand 1 2 3\n"
                         b"# note\nnonsense here\n")
        assert wait_for(lambda: src.lines == 3, 5.0)
        f = inputs.next(0, 0.0)
        assert [(p.id, p.x, p.y, p.angle) for p in f.pucks] == [(4, 0.5, 0.25, 1.0)]
        assert [(c.id, c.x, c.y) for c in f.touches] == [(2, 0.1, 0.2)]
        assert f.streams["hand"].tolist() == [1.0, 2.0, 3.0]
        assert src.bad.counts() == {"unknown_command": 1}
        assert "1 unknown command" in src.health().message
        os.write(master, b"lift 2\n")
        assert wait_for(lambda: src.lines == 4, 5.0)
        assert inputs.next(1, 0.0).touches == ()
        # Not repeated for timeout_s: the puck leaves the bus (not coasting), the stream too.
        assert wait_for(lambda: inputs.next(2, 0.0).pucks == (), 5.0)
        assert dict(inputs.next(3, 0.0).streams) == {}


def test_lines_padded_with_nul_bytes_are_read_and_a_nul_inside_a_line_is_garbage():
    """A board writing its whole fixed buffer (``Serial.write(buf, sizeof buf)``): NULs after
    each newline start the next line, and before a ``\r\n``. Both lines were refused as bad
    numbers / unknown commands; a NUL inside a line is still refused."""
    with tracked_pty(5.0) as (master, src, inputs):
        os.write(master, b"puck 4 0.5 0.25 1.0\n" + b"\0" * 12
                 + b"touch 2 0.1 0.2\0\0\0\r\n" + b"\0" * 16
                 + b"pu\0ck 5 0.5 0.25 1.0\n" + b"puck 6 0.5\0 0.25 1.0\n")
        assert wait_for(lambda: sum(src.bad.counts().values()) == 2, 5.0)
        f = inputs.next(0, 0.0)
        assert [(p.id, p.x, p.y, p.angle) for p in f.pucks] == [(4, 0.5, 0.25, 1.0)]
        assert [(c.id, c.x, c.y) for c in f.touches] == [(2, 0.1, 0.2)]
        assert src.bad.counts() == {"garbage": 1, "wrong_arguments": 1}


def test_numbers_in_other_spellings_are_malformed_lines_counted_and_logged_once(caplog):
    """Numbers are plain decimal or float spellings (DESIGN): a board's ``1_0`` (Python's
    float() reads 10) puts no puck at x = 10 m; such lines are counted and said once, as
    other malformed lines are."""
    caplog.set_level("WARNING", logger="tabletop")
    with tracked_pty(5.0) as (master, src, inputs):
        os.write(master, b"puck 4 0_1 0.25 1.0\npuck 5 0.5 0.25 1_0\ntouch 2 0.1 0.2\n")
        assert wait_for(lambda: src.lines == 1 and src.bad.total() == 2, 5.0)
        f = inputs.next(0, 0.0)
        assert f.pucks == () and [c.id for c in f.touches] == [2]
        assert src.bad.counts() == {"wrong_arguments": 2}
    said = [r.getMessage() for r in caplog.records if "ignored" in r.getMessage()]
    assert said == ["mcu: ignored wrong arguments input (1 so far): puck 4 value '0_1' is not "
                    "a number: b'puck 4 0_1 0.25 1.0'"], said


def test_what_is_not_repeated_for_timeout_s_leaves_the_bus_and_what_is_repeated_stays():
    """DESIGN: a puck or touch not repeated for ``timeout_s`` leaves the bus. It leaves, not
    coasts (the tracker here would coast a lost puck for 30 s), and a touch leaves without a
    ``lift``; a puck and a touch repeated all along stay past ``timeout_s``."""
    import time
    master, slave, name = open_pty()
    src = SerialInput("mcu", name, timeout_s=0.3)
    inputs = LiveInputs([src], Tracker(TrackerSettings(smooth=False, coast_s=30.0)))
    src.open()
    try:
        assert wait_for(lambda: src.health().ok, 5.0)
        os.write(master, b"puck 4 0.5 0.25 1.0\ntouch 2 0.1 0.2\n")
        start, seq, frames = time.monotonic(), 0, []
        while time.monotonic() - start < 10.0:
            os.write(master, b"puck 5 0.9 0.5 0\r\ntouch 6 0.3 0.3\r\n")
            time.sleep(0.03)
            f = inputs.next(seq, 0.0)
            seq += 1
            frames.append(f)
            if time.monotonic() - start > 1.0 and 4 not in {p.id for p in f.pucks} \
                    and 2 not in {c.id for c in f.touches}:
                break
        assert any(4 in {p.id for p in f.pucks} for f in frames)
        assert any(2 in {c.id for c in f.touches} for f in frames)
        last = frames[-1]
        assert [p.id for p in last.pucks] == [5] and [c.id for c in last.touches] == [6]
        assert all(p.state == "seen" for f in frames for p in f.pucks)   # never coasting
        assert src.bad.counts() == {}
    finally:
        src.close()
        os.close(master)
        os.close(slave)


def test_huge_puck_angles_through_a_pty_leave_the_tracker_running():
    """An angle is any finite number of radians: 1e308 and then -1e308 (a board sending
    garbage that parses) are wrapped, not an infinite turn that stopped the installation."""
    with tracked_pty(5.0) as (master, src, inputs):
        for seq, angle in enumerate((b"1e308", b"-1e308", b"3.0")):
            os.write(master, b"puck 4 0.5 0.25 " + angle + b"\n")
            assert wait_for(lambda: src.lines == seq + 1, 5.0)
            (p,) = inputs.next(seq, 0.0).pucks
            assert -math.pi < p.angle <= math.pi
        assert p.angle == 3.0


def test_a_vanished_pty_is_reopened():
    master, slave, name = open_pty()
    src = SerialInput("mcu", name, retry_min_s=0.05, retry_max_s=0.2)
    src.open()
    try:
        assert wait_for(lambda: src.health().ok, 5.0)   # pyserial flushes input on opening
        os.write(master, b"puck 1 0.1 0.1 0\n")
        assert wait_for(lambda: src.lines == 1, 5.0)
        os.close(master)                                   # unplugged
        os.close(slave)
        assert wait_for(lambda: not src.health().ok, 5.0)
        assert "reconnecting" in src.health().message
        master, slave, new_name = open_pty()               # plugged in again
        src.port = new_name                                # (a pty may get another number)
        assert wait_for(lambda: src.health().ok, 5.0)
        os.write(master, b"puck 1 0.7 0.2 0\n")
        assert wait_for(lambda: src.lines == 2, 5.0)
        assert src.latest().pucks[0].x == 0.7
        assert src.reconnects >= 1
    finally:
        src.close()
        os.close(master)
        os.close(slave)


def test_pyserial_loop_url():
    src = SerialInput("loop", "loop://")
    src.open()
    try:
        assert wait_for(lambda: src.port_object is not None, 5.0)
        src.port_object.write(b"touch 5 0.3 0.4\nstream s 7\n")
        assert wait_for(lambda: src.lines == 2, 5.0)
        obs = src.latest()
        assert [(c.id, c.x, c.y) for c in obs.touches] == [(5, 0.3, 0.4)]
        assert obs.streams["s"].tolist() == [7.0]
    finally:
        src.close()


def test_pyserial_socket_url_reconnects():
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen()
    port = server.getsockname()[1]
    src = SerialInput("net", f"socket://127.0.0.1:{port}", retry_min_s=0.05, retry_max_s=0.2)
    src.open()
    try:
        for k in range(2):                                 # serve, drop, serve again
            conn, _ = server.accept()
            assert wait_for(lambda: src.port_object is not None and src.reconnects == k, 5.0)
            conn.sendall(f"puck 9 0.{k + 1} 0.5 0\n".encode())
            assert wait_for(lambda: src.lines == k + 1, 5.0)
            assert src.latest().pucks[0].x == pytest.approx(0.1 * (k + 1))
            conn.close()
        assert src.reconnects >= 1
    finally:
        src.close()
        server.close()


def test_a_missing_device_is_reported_and_retried():
    src = SerialInput("mcu", "/dev/does-not-exist", retry_min_s=0.05, retry_max_s=0.1)
    src.open()
    try:
        assert wait_for(lambda: "cannot open /dev/does-not-exist" in src.health().message, 5.0)
        assert not src.health().ok and src.latest() is None
        # said once, not pyserial's "[Errno 2] could not open port /dev/...: [Errno 2] No such
        # file or directory: '/dev/...'"
        assert src.health().message.startswith("cannot open /dev/does-not-exist: No such file "
                                               "or directory; reconnecting in")
    finally:
        src.close()


def test_a_device_another_source_reads_is_not_opened_until_it_is_free():
    """Two runs reading one device each got part of its lines, torn ("upuck 1 ...", "pck 1
    ..."): a second source on a device the first holds waits, saying why, and takes the device
    once the first lets it go; every line reaches the source reading."""
    with tracked_pty(5.0) as (master, first, inputs):
        second = SerialInput("mcu2", first.port, retry_min_s=0.05, retry_max_s=0.1)
        second.open()
        try:
            assert wait_for(lambda: "another program holds it" in second.health().message, 5.0)
            assert not second.health().ok
            os.write(master, b"".join(b"puck %d 0.5 0.25 1.0\n" % i for i in range(200)))
            assert wait_for(lambda: first.lines == 200, 5.0)
            assert first.bad.counts() == {} and second.lines == 0
            first.close()
            assert wait_for(lambda: second.health().ok, 5.0)
            os.write(master, b"puck 7 0.1 0.1 0\n")
            assert wait_for(lambda: second.lines == 1, 5.0)
        finally:
            second.close()


def test_a_device_down_for_long_is_said_once_and_its_return_once(caplog):
    # a kiosk's serial device unplugged for days: every retry was a log line (8 s apart at
    # most); now the reason once (again every 10 minutes), and the return once
    src = SerialInput("mcu", "/dev/does-not-exist", retry_min_s=0.01, retry_max_s=0.02)
    with caplog.at_level("INFO", logger="tabletop.serial"):
        src.open()
        try:
            assert wait_for(lambda: src._retries.failures >= 10, 5.0)
            master, slave, name = open_pty()               # plugged in
            src.port = name
            assert wait_for(lambda: src.health().ok, 5.0)
            os.write(master, b"puck 1 0.1 0.1 0\n")
            assert wait_for(lambda: src.lines == 1, 5.0)
        finally:
            src.close()
            os.close(master)
            os.close(slave)
    said = [r.getMessage() for r in caplog.records]
    assert len(said) == 2, said                       # measured: 10+ lines before
    assert "cannot open /dev/does-not-exist" in said[0] and "back after" in said[1]


def test_a_port_that_can_never_open_is_refused_at_load(tmp_path):
    """A regular file, a folder, an empty name or a URL of a protocol pyserial lacks started
    and was retried for ever ("cannot open ...: Inappropriate ioctl for device")."""
    from tabletop.config import validate_config
    from tabletop.schema import ConfigError

    (tmp_path / "notes.txt").write_text("puck 1 0.5 0.5 0\n")
    cases = [(str(tmp_path / "notes.txt"), f"{str(tmp_path / 'notes.txt')!r} is a file, not a "
              "serial device (such as /dev/ttyACM0) or a pyserial URL"),
             (str(tmp_path), f"{str(tmp_path)!r} is a folder, not a serial device"),
             ("", "expected a serial device such as /dev/ttyACM0, or a pyserial URL such as "
                  "loop:// or socket://HOST:PORT, got ''"),
             ("bogus://x", "'bogus://x': pyserial has no URL protocol 'bogus' (known: alt, "
                           "cp2110, hwgrep, loop, rfc2217, socket, spy)")]
    for port, words in cases:
        with pytest.raises(ConfigError) as info:
            validate_config({"sources": [{"kind": "serial", "port": port}]}, "cfg.yaml")
        assert str(info.value).startswith(f"cfg.yaml: sources[0].port: {words}"), info.value
    master, slave, name = open_pty()
    try:   # a device, or one not plugged in yet, and a known URL are taken
        for port in (name, "/dev/ttyACM9", "loop://", "socket://localhost:7"):
            cfg = validate_config({"sources": [{"kind": "serial", "port": port}]}, "cfg.yaml")
            assert cfg["sources"][0]["port"] == port
    finally:
        os.close(master)
        os.close(slave)


def test_an_open_port_that_goes_silent_is_unhealthy_until_a_valid_line_comes():
    """A board that hung with its port still open: the health said "open" for hours while no
    position arrived. Silent (no valid line) for over ``stall_s`` of the source's clock it is
    unhealthy with the reason; garbage does not count; a comment brings it back, a puck too."""
    now = [100.0]
    master, slave, name = open_pty()
    src = SerialInput("mcu", name, stall_s=5.0, clock=lambda: now[0])
    src.open()
    try:
        assert wait_for(lambda: src.health().ok, 5.0)
        now[0] = 106.0                                     # opened, never a line
        h = src.health()
        assert not h.ok and h.message == f"{name} open; no valid line for 6 s"
        os.write(master, b"puck 1 0.1 0.1 0\n")
        assert wait_for(lambda: src.lines == 1, 5.0)
        assert src.health().ok
        now[0] = 110.9                                     # 4.9 s: within the limit
        assert src.health().ok
        now[0] = 4000.0                                    # an hour later
        h = src.health()
        assert not h.ok and h.message.startswith(f"{name} open; no valid line for 3894 s")
        os.write(master, b"nonsense here\n")               # garbage is no sign of life
        assert wait_for(lambda: src.bad.total() == 1, 5.0)
        h = src.health()
        assert not h.ok and h.message == (f"{name} open; no valid line for 3894 s "
                                          "(ignored: 1 unknown command)")
        os.write(master, b"# idle\n")                      # a device with nothing to report
        assert wait_for(lambda: src.health().ok, 5.0)
        now[0] = 4010.0
        assert not src.health().ok
        os.write(master, b"puck 1 0.2 0.1 0\n")
        assert wait_for(lambda: src.health().ok, 5.0) and src.lines == 2
    finally:
        src.close()
        os.close(master)
        os.close(slave)


def test_a_socket_url_takes_an_ipv6_address_in_brackets_and_refuses_a_malformed_one():
    """``socket://HOST:PORT`` reads HOST:PORT as ``tabletop status`` does: ``[::1]:7000`` is
    taken, and a malformed one (``::1:7000``, a port out of range) is refused at load in one
    line, where it was retried for ever ("Port could not be cast to integer value")."""
    from tabletop.config import validate_config
    from tabletop.schema import ConfigError

    for url in ("socket://[::1]:7000", "socket://localhost:7?logging=debug",
                "rfc2217://[fe80::1%lo]:2217", "socket://host:7000/", "socket://host:7000#x",
                "rfc2217://host:2217/"):
        cfg = validate_config({"sources": [{"kind": "serial", "port": url}]}, "cfg.yaml")
        assert cfg["sources"][0]["port"] == url
    for url in ("socket://::1:7000", "socket://host:70000", "socket://[host]:7", "socket://h",
                "rfc2217://:2217", "socket://h:\u00b2"):
        where = url.split("://", 1)[1]
        with pytest.raises(ConfigError) as info:
            validate_config({"sources": [{"kind": "serial", "port": url}]}, "cfg.yaml")
        assert str(info.value) == (
            f"cfg.yaml: sources[0].port: {url.split(':')[0]}:// URL {where!r}: expected "
            "HOST:PORT (port 1..65535; an IPv6 address in brackets), e.g. 0.0.0.0:9000 or "
            "[::1]:9000"), info.value


@pytest.mark.skipif(not ipv6_loopback(), reason="this machine has no IPv6 loopback (::1)")
def test_pyserial_socket_url_on_ipv6_loopback():
    server = socket.socket(socket.AF_INET6)
    server.bind(("::1", 0))
    server.listen()
    server.settimeout(10)
    port = server.getsockname()[1]
    src = SerialInput("net", f"socket://[::1]:{port}")
    src.open()
    try:
        conn, _ = server.accept()   # pyserial's open ends by dropping what came before it
        assert wait_for(lambda: src.port_object is not None, 5.0)
        conn.sendall(b"puck 9 0.3 0.5 0\n")
        assert wait_for(lambda: src.lines == 1, 5.0)
        assert src.latest().pucks[0].x == 0.3 and src.health().ok
        conn.close()
    finally:
        src.close()
        server.close()


def test_a_device_silent_on_an_empty_table_stays_healthy_unless_stall_s_is_set():
    """DESIGN's serial contract asks for no lines while nothing is on the table: by default
    (``stall_s`` null) an open port that says nothing for an hour stays healthy; the config's
    ``stall_s`` turns the silence check on."""
    from tabletop.config import validate_config

    master, slave, name = open_pty()
    try:
        src_cfg = validate_config({"sources": [{"kind": "serial", "port": name}]},
                                  "cfg.yaml")["sources"][0]
        assert src_cfg["stall_s"] is None
        set_cfg = validate_config({"sources": [{"kind": "serial", "port": name, "stall_s": 5}]},
                                  "cfg.yaml")["sources"][0]
        assert set_cfg["stall_s"] == 5.0
        now = [100.0]
        src = SerialInput("mcu", name, stall_s=src_cfg["stall_s"], clock=lambda: now[0])
        src.open()
        try:
            assert wait_for(lambda: src.health().ok, 5.0)
            now[0] = 3700.0                                # an hour without a line
            assert src.health().ok
        finally:
            src.close()
    finally:
        os.close(master)
        os.close(slave)


def test_a_relative_port_is_relative_to_the_config_file(tmp_path, monkeypatch):
    """README: paths are relative to the config file. A device link beside the config
    (``port: board``, as socat or a udev rule makes one) was opened from the working folder:
    a kiosk started elsewhere retried "No such file or directory" for ever."""
    from tabletop.config import load_config

    master, slave, name = open_pty()
    table = tmp_path / "table"
    table.mkdir()
    (table / "board").symlink_to(name)
    (table / "cfg.yaml").write_text("sources:\n  - {kind: serial, name: mcu, port: board}\n"
                                    "engines: []\n")
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    port = load_config(table / "cfg.yaml")["sources"][0]["port"]
    assert port == str(table / "board")
    src = SerialInput("mcu", port, timeout_s=5.0)
    src.open()
    try:
        assert wait_for(lambda: src.health().ok, 5.0), src.health().message
        os.write(master, b"puck 4 0.5 0.25 1.0\r\n")
        assert wait_for(lambda: src.lines == 1, 5.0)
    finally:
        src.close()
        os.close(master)
        os.close(slave)


def test_lines_ending_in_a_bare_cr_are_said_as_such(caplog):
    """Firmware ending its lines with ``\\r`` alone ran every line into the next: the only word
    was "line over 1024 bytes". The line now asks about the ending; an overlong line of
    ``\\n``-ended input does not."""
    caplog.set_level("WARNING", logger="tabletop")
    noise = bytes(b for b in range(256) if b != 10) * 5   # line noise with a \r: not asked
    for ending, asked in ((b"\r", True), (b"\n", False), (noise, False)):
        src = SerialInput(f"cr{asked}{len(ending)}", "loop://")
        src.open()
        try:
            assert wait_for(lambda: src.port_object is not None, 5.0)
            data = b"".join(b"puck 1 0.5 0.4 %d" % i + ending for i in range(100))
            if ending == noise:
                data = noise + b"\n"
            src.port_object.write(data if asked else b"x" * (MAX_LINE + 10) + b"\n" + data)
            assert wait_for(lambda: src.bad.counts().get("overlong", 0) >= 1, 5.0)
            assert wait_for(lambda: src.lines == (100 if ending == b"\n" else 0), 5.0)
        finally:
            src.close()
        said = [r.getMessage() for r in caplog.records
                if f"cr{asked}{len(ending)}: ignored overlong" in r.getMessage()]
        assert len(said) == 1 and ("lines ending in \\r alone? end them with \\n or \\r\\n"
                                   in said[0]) == asked, said
