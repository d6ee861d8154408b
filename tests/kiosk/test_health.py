"""Health of a table: sd_notify datagrams, the OSC heartbeat, the status file (``tabletop
status``, which reads the heartbeats: test_status_command.py; the status a kiosk run leaves:
test_health_status.py)."""

import json
import socket
import threading
import time
from pathlib import Path

import pytest
from pythonosc.dispatcher import Dispatcher
from pythonosc.osc_server import BlockingOSCUDPServer

from tabletop.cli import main as cli
from tabletop.frames import Frame, SourceHealth
from tabletop.kiosk.health import Heartbeat, HealthReporter, WatchdogPing
from tabletop.kiosk.notify import Notifier
from tabletop.loop import Loop, LoopStats
from tabletop.replay_inputs import FrameInputs
from tracking.scenes import wait_for

STATUS_FIELDS = {"name", "host", "pid", "supervisor_pid", "version", "time", "uptime_s", "fps",
                 "ticks", "mode", "unhealthy_sources", "sources", "errors", "restarts"}


class Clock:
    def __init__(self, t=100.0):
        self.t = t

    def __call__(self):
        return self.t


def notify_socket(tmp_path: Path) -> socket.socket:
    s = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
    s.bind(str(tmp_path / "notify.sock"))
    s.settimeout(2.0)
    return s


def test_frame_loop_sends_ready_once_then_watchdog_pings(tmp_path):
    sock = notify_socket(tmp_path)
    clock = Clock()
    ping = WatchdogPing(Notifier(str(tmp_path / "notify.sock")), every_s=0.25, clock=clock)
    for i in range(32):                       # 2 s of ticks: READY, then a ping per 0.25 s
        ping(Frame(seq=i, t=clock.t))
        clock.t += 0.0625
    got = []
    sock.settimeout(0.2)
    try:
        while True:
            got.append(sock.recv(4096).decode())
    except socket.timeout:
        pass
    assert got[0].startswith("READY=1\n") and all(m == "WATCHDOG=1" for m in got[1:])
    assert len(got) - 1 == 7                  # at 0.25, 0.5, ... 1.75 s
    ping.close()
    assert sock.recv(4096) == b"STOPPING=1"


def test_abstract_socket_names_and_no_socket_are_handled():
    assert Notifier("").send("READY=1") is False
    name = f"@tabletop-test-{time.time_ns()}"
    s = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
    s.bind(b"\0" + name[1:].encode())
    s.settimeout(2.0)
    assert Notifier(name).send("WATCHDOG=1")
    assert s.recv(100) == b"WATCHDOG=1"


class OscListener:
    """A python-osc server on a free loopback port collecting heartbeats."""

    def __init__(self):
        self.got = []
        d = Dispatcher()
        d.map("/tabletop/heartbeat", lambda addr, *v: self.got.append(v))
        self.server = BlockingOSCUDPServer(("127.0.0.1", 0), d)
        self.port = self.server.server_address[1]
        self.thread = threading.Thread(target=self.server.serve_forever, args=(0.05,), daemon=True)
        self.thread.start()

    def close(self):
        self.server.shutdown()
        self.server.server_close()


def test_heartbeat_reaches_a_python_osc_server_and_the_status_file_parses(tmp_path):
    osc = OscListener()
    stats = LoopStats()
    clock = Clock()
    for k in range(31):                      # a second of ticks at 30 Hz
        stats.tick_times.append(k / 30.0)
    stats.errors["engine x"] += 2
    status_file = tmp_path / "state" / "status.json"
    rep = HealthReporter("table-7", stats, every_s=1.0, status_file=status_file,
                         heartbeat=Heartbeat("127.0.0.1", osc.port), clock=clock,
                         extra=lambda: {"config_error": None}, started=40.0)
    health = (SourceHealth("camera", False, "no frame for 3.0 s", 3.0),
              SourceHealth("osc", True, "ok", 0.01))
    for i in range(20):                      # 2.5 s of frames: heartbeats at 0, 1 and 2 s
        rep(Frame(seq=i, t=clock.t, health=health, status="attract"))
        clock.t += 0.125
    assert wait_for(lambda: len(osc.got) == 3, 5.0)
    rep.close()
    osc.close()
    name, uptime, fps, unhealthy, text = osc.got[-1]
    # DESIGN.md: name (string), uptime s (float), fps (float), unhealthy sources (int), status
    assert [type(v) for v in osc.got[-1]] == [str, float, float, int, str]
    assert name == "table-7" and unhealthy == 1
    assert uptime == pytest.approx(62.0, abs=1e-4) and fps == pytest.approx(30.0, rel=1e-3)
    status = json.loads(text)
    assert STATUS_FIELDS <= set(status)
    assert status["mode"] == "attract" and status["errors"] == 2
    assert status["sources"][0] == {"name": "camera", "ok": False,
                                    "message": "no frame for 3.0 s", "age_s": 3.0}
    on_disk = json.loads(status_file.read_text())
    assert on_disk == status
    assert not [p for p in status_file.parent.iterdir() if p.name != "status.json"]


class StepClock:
    """A clock read ``step`` s later at every reading."""

    def __init__(self, step: float) -> None:
        self.t, self.step = 100.0, step

    def __call__(self) -> float:
        self.t += self.step
        return self.t


def test_the_first_heartbeat_says_a_rate_not_0_fps(tmp_path):
    """The reporter runs in the loop's first tick, before any tick has ended: it waits for a
    rate (a second of ticks) rather than say 0.0 fps, which reads as a loop that stalled; then
    a heartbeat every ``every_s``."""
    osc = OscListener()
    clock = StepClock(0.002)
    frames = (Frame(seq=i, t=i / 60.0) for i in range(200))
    loop = Loop(FrameInputs(frames, honour_times=False), [], [], clock=clock, paced=False)
    status_file = tmp_path / "status.json"
    rep = HealthReporter("table-7", loop.stats, every_s=0.1, status_file=status_file,
                         heartbeat=Heartbeat("127.0.0.1", osc.port), clock=clock)
    loop.hooks.append(rep)
    first = []
    loop.hooks.append(lambda frame: first.append(rep.last) if rep.last and not first else None)
    loop.run()
    rep.close()
    assert wait_for(lambda: len(osc.got) >= 4, 5.0)
    osc.close()
    fps = [v[2] for v in osc.got]
    assert min(fps) > 0.0
    assert first[0]["uptime_s"] >= LoopStats.RATE_MIN_S
    assert first[0]["fps"] == pytest.approx(fps[0], abs=0.01)
    assert json.loads(status_file.read_text())["fps"] > 0.0


def test_the_log_file_rotates(tmp_path):
    import logging

    from tabletop.kiosk.health import setup_log_file
    handler = setup_log_file(tmp_path / "logs" / "tabletop.log", max_bytes=10_000, backups=2)
    try:
        log = logging.getLogger("tabletop")
        for i in range(600):
            log.info("line %d %s", i, "x" * 60)
    finally:
        logging.getLogger("tabletop").removeHandler(handler)
        handler.close()
    files = sorted(p.name for p in (tmp_path / "logs").iterdir() if p.name[0] != ".")
    assert files == ["tabletop.log", "tabletop.log.1", "tabletop.log.2"]
    assert all((tmp_path / "logs" / f).stat().st_size <= 10_000 for f in files)
    assert "line 599" in (tmp_path / "logs" / "tabletop.log").read_text()


LOG_WRITER = """
import logging, sys
from pathlib import Path
from tabletop.kiosk.health import setup_log_file
setup_log_file(Path(sys.argv[1]), max_bytes=10_000, backups=3)
log = logging.getLogger("tabletop")
for line in sys.stdin:   # one log line per line read, as the test says when
    log.info("%s %s", line.strip(), "x" * 60)
"""


def test_processes_sharing_the_log_file_all_write_to_the_current_file(tmp_path):
    """The supervisor and its installation log into one file: a rotation by one never leaves
    the other writing into a renamed file that a later rotation deletes (every supervisor line
    went nowhere once the installation's log had rotated ``log_backups`` times)."""
    import subprocess
    import sys

    path = tmp_path / "logs" / "tabletop.log"
    path.parent.mkdir()
    start = [sys.executable, "-c", LOG_WRITER, str(path)]
    supervisor = subprocess.Popen(start, stdin=subprocess.PIPE, text=True)
    try:
        supervisor.stdin.write("supervisor first\n")
        supervisor.stdin.flush()
        assert wait_for(lambda: path.exists() and "supervisor first" in path.read_text(), 30.0)
        installation = "".join(f"installation {i}\n" for i in range(1500))  # ~20 rotations
        subprocess.run(start, input=installation, text=True, check=True, timeout=60)
        supervisor.stdin.write("supervisor last\n")
        supervisor.stdin.close()
        assert supervisor.wait(30) == 0
    finally:
        supervisor.kill()
    files = sorted(p.name for p in path.parent.iterdir() if p.name[0] != ".")  # not the lock
    assert files == ["tabletop.log", "tabletop.log.1", "tabletop.log.2", "tabletop.log.3"]
    assert all((path.parent / f).stat().st_size <= 10_000 for f in files)
    text = path.read_text()
    assert "installation 1499" in text and text.rstrip().endswith("supervisor last " + "x" * 60)
    kept = "".join((path.parent / f).read_text() for f in reversed(files))
    numbers = [int(w.split()[5]) for w in kept.splitlines() if " installation " in w]
    assert numbers == list(range(numbers[0], 1500))   # nothing lost within what is kept


def test_a_status_file_that_cannot_be_written_is_logged_once_then_recovers(tmp_path, caplog):
    """A kiosk runs for weeks: a status folder it cannot use (a full or read-only disk) is one
    warning, not one a second, and the file is written again once the folder can be used."""
    from tabletop.kiosk.health import LatestWriter
    blocker = tmp_path / "blocked"
    blocker.write_text("a file where the status folder should be")
    w = LatestWriter(blocker / "status.json")
    with caplog.at_level("INFO", logger="tabletop"):
        for i in range(5):
            w.put(f'{{"n": {i}}}')
            assert wait_for(lambda: w.failed == i + 1, 5.0)
        blocker.unlink()
        w.put('{"n": 5}')
        assert wait_for(lambda: w.written == 1, 5.0)
    w.close()
    assert json.loads((blocker / "status.json").read_text()) == {"n": 5}
    said = [r.getMessage() for r in caplog.records if "status file" in r.getMessage()]
    assert len(said) == 2 and "not written" in said[0] and "written again" in said[1]


@pytest.mark.parametrize("supervised", [False, True])
def test_a_kiosk_log_that_cannot_be_made_names_its_key(tmp_path, capfd, supervised):
    blocker = tmp_path / "blocked"
    blocker.write_text("a file where the log folder should be")
    cfg = tmp_path / "config.yaml"
    cfg.write_text("sources: [{kind: scripted, name: s}]\nview: {enabled: false}\n"
                   f"kiosk: {{log_file: {blocker / 'logs' / 'k.log'}, "
                   "heartbeat: {enabled: false}}\n")
    argv = ["run", "--config", str(cfg), "--headless", "--seconds", "0.2", "--kiosk"]
    assert cli(argv + ([] if supervised else ["--no-supervisor"])) == 2
    err = capfd.readouterr().err.splitlines()
    assert len(err) == 1 and err[0].startswith(f"tabletop run: error: {cfg}: kiosk.log_file: ")


@pytest.mark.parametrize("key", ["status_file", "crash_log"])
def test_a_status_file_or_crash_log_naming_a_folder_names_its_key(tmp_path, capfd, key):
    """A status file naming a folder was one warning and never written (a crash log naming
    one, an error at each crash): refused at load, naming the key."""
    (tmp_path / "state").mkdir()
    cfg = tmp_path / "config.yaml"
    cfg.write_text("sources: [{kind: scripted, name: s}]\nview: {enabled: false}\n"
                   f"kiosk: {{{key}: state, heartbeat: {{enabled: false}}}}\n")
    assert cli(["run", "--config", str(cfg), "--headless", "--seconds", "0.2", "--kiosk",
                "--no-supervisor"]) == 2
    err = capfd.readouterr().err.splitlines()
    assert err == [f"tabletop run: error: {cfg}: kiosk.{key}: {tmp_path / 'state'} is a folder; "
                   "expected a file name"]


def test_mode_is_one_moment_whenever_the_table_shows_it():
    """A camera not plugged in at boot never worked, so the kiosk's grace rule does not mark the
    frames; the view still shows "One moment" (every source down) and the status says so too,
    not "live"."""
    rep = HealthReporter("table-7", None, clock=Clock())
    never = (SourceHealth("overhead", False, "cannot open camera 0; reconnecting in 2.0 s"),)
    ok = (SourceHealth("overhead", True, "ok", 0.01),)
    half = never + ok
    assert rep.status(Frame(seq=1, t=1.0, health=never))["mode"] == "one_moment"
    assert rep.status(Frame(seq=2, t=2.0, health=never, status="attract"))["mode"] == "one_moment"
    assert rep.status(Frame(seq=3, t=3.0, health=half))["mode"] == "live"
    assert rep.status(Frame(seq=4, t=4.0, health=ok, status="attract"))["mode"] == "attract"
    assert rep.status(Frame(seq=5, t=5.0))["mode"] == "live"      # no sources at all


def test_the_log_says_when_and_why_the_table_shows_one_moment(caplog):
    """The visitors' screen says only "One moment"; the operator's log says when it began, the
    sources' own words and when it ended (an osc source whose tracker stopped logged nothing:
    the table was calm and the log silent). A flapping source: one line a minute at most."""
    clock = Clock()
    stats = LoopStats()
    stats.tick_times.extend((0.0, 1.0))   # a loop that has run: a rate to report
    rep = HealthReporter("table-7", stats, every_s=1.0, clock=clock)
    ok = (SourceHealth("tracker", True, "listening on 127.0.0.1:3333; TUIO from t", 0.01),)
    down = (SourceHealth("tracker", False, "listening on 127.0.0.1:3333; nothing received "
                                           "for 5 s", 5.0),)

    def run(health, seconds):
        for _ in range(int(seconds * 4)):
            rep(Frame(seq=0, t=clock.t, health=health))
            clock.t += 0.25
    with caplog.at_level("INFO", logger="tabletop"):
        run(down, 1.5)              # a source still starting: no line
        run(ok, 5)
        run(down, 23)
        run(ok, 5)
        for _ in range(3):          # flapping: 10 s down, 5 s up, three times within a minute
            run(down, 10)
            run(ok, 5)
        clock.t += 60
        run(down, 3)
    said = [(r.levelname, r.getMessage()) for r in caplog.records]
    assert said == [
        ("WARNING", 'the table shows "one moment" (for 2 s): source tracker: listening on '
                    "127.0.0.1:3333; nothing received for 5 s"),
        ("INFO", 'the table is live again after 23 s of "one moment"'),
        ("WARNING", 'the table shows "one moment" (for 2 s, 3 more times since the last such '
                    "line): source tracker: listening on 127.0.0.1:3333; nothing received for "
                    "5 s")]


def test_a_camera_still_starting_is_not_reported_down(tmp_path):
    """At start-up the camera opens and its first frame is on its way: the table has not lost
    anything, so the first heartbeats say mode "live" with 0 unhealthy sources (they said
    "one_moment", 1 unhealthy: "no frame yet"). A start that brings no frame within the
    camera's ``stall_s`` is down, and a camera absent at boot is down at once."""
    import cv2
    import numpy as np

    from tracking.camera import CameraSettings, CameraSource

    folder = tmp_path / "frames"
    folder.mkdir()
    for k in range(3):
        cv2.imwrite(str(folder / f"{k}.png"), np.full((48, 64, 3), 40 * k, np.uint8))
    first_frame = threading.Event()
    processing = threading.Event()

    def process(image, t, n):           # the first frame takes its time (a detector warming up)
        processing.set()
        first_frame.wait(10.0)

    settings = CameraSettings(device=str(folder), fps=30.0, stall_s=1.0, retry_min_s=0.05)
    cam = CameraSource("overhead", settings, process)
    rep = HealthReporter("table-7", None)
    cam.open()
    try:
        assert processing.wait(5.0)
        h = cam.health()
        status = rep.status(Frame(seq=1, t=0.0, health=(h,)))
        assert h.ok and "first frame" in h.message, h
        assert status["mode"] == "live" and status["unhealthy_sources"] == 0, status
        assert wait_for(lambda: not cam.health().ok, 5.0)          # stall_s 1 s without a frame
        assert "no frame" in cam.health().message
        first_frame.set()
        assert wait_for(lambda: cam.health().ok, 5.0)
    finally:
        first_frame.set()
        cam.close()
    absent = CameraSource("overhead", CameraSettings(device=str(tmp_path / "none"), stall_s=5.0,
                                                     retry_min_s=0.05))
    absent.open()
    try:
        assert wait_for(lambda: "none" in absent.health().message, 5.0)
        h = absent.health()
        assert not h.ok
        assert rep.status(Frame(seq=2, t=0.0, health=(h,)))["mode"] == "one_moment"
    finally:
        absent.close()


def test_a_heartbeat_that_cannot_be_sent_is_said_once(caplog):
    """A heartbeat host that does not resolve loses every heartbeat: the log says so in one
    warning while it lasts (the monitor hears nothing, so a debug line would leave no
    trace)."""
    hb = Heartbeat("no-such-host.invalid", 9000)
    try:
        with caplog.at_level("DEBUG", logger="tabletop"):
            assert hb.destination.wait(15.0) is None   # looked up away from the frame loop
            for k in range(5):
                hb.send("north", float(k), 60.0, 0, "{}")
    finally:
        hb.close()
    said = [r for r in caplog.records if "heartbeat" in r.getMessage()]
    assert hb.sent == 0
    assert len(said) == 1 and said[0].levelname == "WARNING", [r.getMessage() for r in said]
    assert "cannot resolve no-such-host.invalid" in said[0].getMessage()


def test_the_heartbeat_never_blocks_the_loop_and_a_failed_send_is_said_once(caplog):
    """The heartbeat sends from the frame loop: its socket is non-blocking, as the ``tuio``
    sink's (a blocking one waited there for a full send buffer). A send the system refuses (a
    status too long for one datagram: EMSGSIZE) is counted and said once, never raised."""
    rx = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    rx.bind(("127.0.0.1", 0))
    rx.settimeout(5.0)
    hb = Heartbeat("127.0.0.1", rx.getsockname()[1])
    try:
        hb.send("north", 1.0, 60.0, 0, "{}")
        assert b"/tabletop/heartbeat" in rx.recv(65536)
        assert hb.destination._sock.gettimeout() == 0.0   # non-blocking
        with caplog.at_level("INFO", logger="tabletop"):
            for k in range(3):
                hb.send("north", float(k), 60.0, 0, "x" * 70_000)
            hb.send("north", 4.0, 60.0, 0, "{}")
        assert b"/tabletop/heartbeat" in rx.recv(65536)
    finally:
        hb.close()
        rx.close()
    said = [r.getMessage() for r in caplog.records if "heartbeat" in r.getMessage()]
    assert hb.sent == 2 and len(said) == 2, said
    assert "not sent" in said[0] and "sent again after 3 failed" in said[1]
