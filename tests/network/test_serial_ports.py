"""The ``serial`` source's port: a pseudo-terminal that vanishes, is missing or held, goes
silent; pyserial's ``loop://`` and ``socket://`` URLs; the port as a config names it."""

import os
import socket

import pytest

from tracking.serial_input import SerialInput

from tests.network.helpers import ipv6_loopback, wait_for
from tests.network.serial_pty import a_pty, open_pty, tracked_pty


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
    with caplog.at_level("INFO", logger="tabletop.serial"), a_pty() as (master, _, name):
        src.open()
        try:
            assert wait_for(lambda: src._retries.failures >= 10, 5.0)
            src.port = name                                # plugged in
            assert wait_for(lambda: src.health().ok, 5.0)
            os.write(master, b"puck 1 0.1 0.1 0\n")
            assert wait_for(lambda: src.lines == 1, 5.0)
        finally:
            src.close()
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
    with a_pty() as (_, _, name):   # a device, or one not plugged in yet, and a known URL
        for port in (name, "/dev/ttyACM9", "loop://", "socket://localhost:7"):
            cfg = validate_config({"sources": [{"kind": "serial", "port": port}]}, "cfg.yaml")
            assert cfg["sources"][0]["port"] == port


def test_an_open_port_that_goes_silent_is_unhealthy_until_a_valid_line_comes():
    """A board that hung with its port still open: the health said "open" for hours while no
    position arrived. Silent (no valid line) for over ``stall_s`` of the source's clock it is
    unhealthy with the reason; garbage does not count; a comment brings it back, a puck too."""
    now = [100.0]
    with a_pty() as (master, _, name):
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

    with a_pty() as (_, _, name):
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


def test_a_relative_port_is_relative_to_the_config_file(tmp_path, monkeypatch):
    """README: paths are relative to the config file. A device link beside the config
    (``port: board``, as socat or a udev rule makes one) was opened from the working folder:
    a kiosk started elsewhere retried "No such file or directory" for ever."""
    from tabletop.config import load_config

    with a_pty() as (master, _, name):
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
