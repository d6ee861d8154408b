"""A config edit's rebuild pauses the frame loop: the supervisor waits for it as for a start
(``RELOADING=1`` ... ``READY=1``) instead of killing it as a stall after ``stall_s``; a rebuild
that never ends is still killed, after ``startup_s``."""

import socket
import sys
import textwrap
import threading
import time

import yaml

from tabletop.config import load_config
from tabletop.kiosk.notify import Notifier
from tabletop.kiosk.runner import Runner
from tabletop.kiosk.supervisor import Policy, Supervisor
from tests.kiosk.test_live_config import config, rebuilt, running, write
from tracking.scenes import wait_for

# a child speaking the notify protocol as the installation does: pings, a rebuild of PAUSE_S
# without a frame, pings again, then it ends on purpose
CHILD = textwrap.dedent("""
    import os, socket, sys, time
    s = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
    def send(m):
        s.sendto(m.encode(), os.environ["NOTIFY_SOCKET"])
    def frames(seconds):
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            send("WATCHDOG=1")
            time.sleep(0.05)
    send("READY=1")
    frames(0.3)
    send("RELOADING=1")
    time.sleep(float(sys.argv[1]))
    send("READY=1")
    frames(0.3)
""")


def supervise(tmp_path, pause_s: float, startup_s: float) -> Supervisor:
    sup = Supervisor([sys.executable, "-c", CHILD, str(pause_s)],
                     Policy(stall_s=0.4, backoff_s=(5.0, 5.0), startup_s=startup_s),
                     tmp_path / "crashes.log", echo=False, spares=0)
    th = threading.Thread(target=sup.run)
    th.start()
    end = time.monotonic() + 20.0     # until it ends (its child ended on purpose) or restarts
    while th.is_alive() and sup.starts < 2 and time.monotonic() < end:
        time.sleep(0.02)
    sup.stop.set()
    th.join(30)
    return sup


def test_the_supervisor_waits_for_a_rebuild_as_for_a_start(tmp_path):
    sup = supervise(tmp_path, pause_s=1.2, startup_s=10.0)     # 3 x stall_s without a frame
    assert [e for e, _ in sup.events] == ["ready"] and sup.starts == 1
    assert not (tmp_path / "crashes.log").exists()


def test_a_rebuild_that_never_ends_is_killed_after_startup_s(tmp_path):
    sup = supervise(tmp_path, pause_s=30.0, startup_s=1.0)
    assert [e for e, _ in sup.events][:2] == ["ready", "stall"]
    log = (tmp_path / "crashes.log").read_text()
    assert "not rebuilt (a config edit's rebuild began" in log, log


def test_an_applied_edit_says_reloading_then_ready(tmp_path):
    """The installation's side: RELOADING=1 as its loop stops for an edit, READY=1 at the
    rebuilt loop's first frame."""
    sock = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
    sock.bind(str(tmp_path / "notify.sock"))
    sock.settimeout(0.05)
    path = tmp_path / "config.yaml"
    path.write_text(yaml.safe_dump(config([10, 20, 30])))
    runner = Runner(path, load_config(path), headless=True, kiosk=True)
    runner.notifier = Notifier(str(tmp_path / "notify.sock"))
    got: list[str] = []

    def heard(what: str) -> bool:
        try:
            got.extend(sock.recv(4096).decode().splitlines())
        except socket.timeout:
            pass
        return what in got

    with running(runner):
        first = runner.inst
        assert wait_for(lambda: heard("READY=1"), 15)
        write(path, yaml.safe_dump(config([200, 100, 50])))
        assert wait_for(rebuilt(runner, first), 15)
        end = time.monotonic() + 15
        while time.monotonic() < end and got.count("READY=1") < 2:
            heard("READY=1")
    assert "RELOADING=1" in got, got
    after = got[got.index("RELOADING=1"):]
    assert "READY=1" in after and got.count("READY=1") == 2, got
