"""The kiosk supervisor's stops with real processes: SIGTERM, SIGHUP, its own kill (its
installation ends too) and ``--seconds`` ending while a restart starts: each a clean end."""

import json
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

from tabletop.kiosk.supervisor import Policy, Supervisor
from tests import children
from tests.kiosk.test_supervisor import drill_config


def test_run_kiosk_notifies_systemd_and_stops_cleanly_on_sigterm(tmp_path):
    """As systemd runs it: READY=1 once the first frame is drawn, WATCHDOG=1 pings relayed from
    the frame loop, STOPPING=1 on SIGTERM, exit status 0, with a warm spare beside it. One
    spare, not the default two: the second, preparing beside the first start and ended unused
    (SIGKILL at any stop), was 0.5-0.9 of the test's 3.4-4.0 CPU s."""
    cfg = drill_config(tmp_path, [])
    cfg.write_text(cfg.read_text().replace("kiosk:", "kiosk:\n  spares: 1", 1))
    sock = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
    sock.bind(str(tmp_path / "systemd.sock"))
    sock.settimeout(0.1)
    env = dict(os.environ, SDL_VIDEODRIVER="dummy", NOTIFY_SOCKET=str(tmp_path / "systemd.sock"))
    env.pop("TABLETOP_SUPERVISED", None)
    p = children.popen([sys.executable, "-m", "tabletop", "run", "--config", str(cfg),
                        "--kiosk"], env=env, stderr=subprocess.PIPE, text=True)
    got = []
    # READY, then four pings, waited for as long as the kiosk runs (the cap only ends a kiosk
    # that hangs): its installation was ready 21 s after its start given a sixth of the
    # machine, 26 s given a ninth, and no READY came in the 30 s it had at load 14-16
    end = time.monotonic() + 300
    while time.monotonic() < end and got.count("WATCHDOG=1") < 4 and p.poll() is None:
        try:
            got.append(sock.recv(4096).decode())
        except socket.timeout:
            pass
    p.send_signal(signal.SIGTERM)
    _, err = p.communicate(timeout=120)
    try:
        while True:
            got.append(sock.recv(4096).decode())
    except socket.timeout:
        pass
    assert got[0] == "READY=1" and got.count("READY=1") == 1 and got[-1] == "STOPPING=1"
    assert got.count("WATCHDOG=1") >= 4
    assert p.returncode == 0, err
    assert "installation ready" in err and "Traceback" not in err
    log = (tmp_path / "logs" / "tabletop.log").read_text()
    assert "supervisor: started the installation" in log and "ran " in log
    assert not (tmp_path / "logs" / "crashes.log").exists()


def _running(pid: int) -> bool:
    """Is ``pid`` a live process (not gone, not a zombie no one reaped)?"""
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except (OSError, IndexError):
        return False
    return state != "Z"


def test_an_installation_whose_supervisor_is_killed_ends_cleanly(tmp_path):
    """``kill -9`` of the supervisor: its installation notices within a second, says so in the
    kiosk log, closes its recording (every line complete) and leaves its status "stopped".
    It ran on for good, unsupervised, holding its ports and camera against the next start."""
    from tabletop.recorder import read_frames
    cfg = drill_config(tmp_path, [])
    cfg.write_text(cfg.read_text().replace("kiosk:", "kiosk:\n  spares: 0", 1)
                   + "recorder: {enabled: true, folder: sessions}\n")
    sup = subprocess.Popen([sys.executable, "-m", "tabletop", "run", "--config", str(cfg),
                            "--kiosk", "--headless"], stdout=subprocess.DEVNULL,
                           stderr=subprocess.DEVNULL)
    status_file = tmp_path / "status.json"
    child = None
    try:
        end = time.monotonic() + 60
        while time.monotonic() < end and child is None:
            time.sleep(0.1)
            if status_file.exists():
                child = json.loads(status_file.read_text())["pid"]
        assert child is not None and child != sup.pid
        sup.kill()
        sup.wait(10)
        end = time.monotonic() + 20
        while time.monotonic() < end and _running(child):
            time.sleep(0.1)
        assert not _running(child), "the installation ran on without its supervisor"
    finally:
        if sup.poll() is None:
            sup.kill()
        if child is not None and _running(child):
            os.kill(child, signal.SIGKILL)
    log = (tmp_path / "logs" / "tabletop.log").read_text()
    assert f"the kiosk supervisor (pid {sup.pid}) is gone" in log
    assert json.loads(status_file.read_text())["mode"] == "stopped"
    (recording,) = (tmp_path / "sessions").iterdir()
    assert recording.read_bytes().endswith(b"\n") and len(list(read_frames(recording))) > 10


def _children(pid: int) -> list[int]:
    """The live processes whose parent is ``pid`` (from /proc)."""
    out = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                fields = (entry / "stat").read_text().rsplit(")", 1)[1].split()
            except (OSError, IndexError):
                continue
            if int(fields[1]) == pid and fields[0] != "Z":
                out.append(int(entry.name))
    return out


def test_a_supervisor_killed_as_its_installation_starts_ends_the_installation(tmp_path):
    """``kill -9`` of the supervisor the moment its installation's process exists (before its
    imports): the installation ends, though it is handed to another parent before it looks at
    its own (running on for good, its inherited lock would refuse every later kiosk start on
    the folder)."""
    cfg = drill_config(tmp_path, [])
    cfg.write_text(cfg.read_text().replace("kiosk:", "kiosk:\n  spares: 0", 1))
    env = dict(os.environ, SDL_VIDEODRIVER="dummy")
    env.pop("TABLETOP_SUPERVISED", None)
    sup = subprocess.Popen([sys.executable, "-m", "tabletop", "run", "--config", str(cfg),
                            "--kiosk", "--headless"], stdout=subprocess.DEVNULL,
                           stderr=subprocess.DEVNULL, env=env, start_new_session=True)
    kids: list[int] = []
    try:
        end = time.monotonic() + 60
        while time.monotonic() < end and not kids and sup.poll() is None:
            kids = _children(sup.pid)
            time.sleep(0.005)
        assert kids, "the supervisor started no installation"
        sup.kill()
        sup.wait(10)
        end = time.monotonic() + 30
        while time.monotonic() < end and any(_running(k) for k in kids):
            time.sleep(0.1)
        assert not any(_running(k) for k in kids), "the installation ran on without its supervisor"
    finally:
        if sup.poll() is None:
            sup.kill()
        for k in kids:
            if _running(k):
                os.kill(k, signal.SIGKILL)
    log = (tmp_path / "logs" / "tabletop.log").read_text()
    assert f"the kiosk supervisor (pid {sup.pid}) is gone" in log
    # the next kiosk start on the folder is not refused: the folder's lock, the first thing a
    # start takes (tabletop.commands.run), is free (a whole kiosk run of a second, as here
    # before, was 2.2-2.4 CPU s; a start refused by a held lock: test_kiosk_lock)
    from tests.kiosk.test_kiosk_lock import refusal
    nxt = refusal(tmp_path)
    assert nxt.stdout.startswith("fd ") and nxt.stdout.split()[1].isdigit(), \
        nxt.stdout + nxt.stderr


def test_run_kiosk_stops_cleanly_on_sighup_to_its_supervisor(tmp_path):
    """A closed terminal or ``kill -HUP`` of the kiosk's supervisor ends the kiosk as SIGTERM
    does (README: SIGHUP ends a run cleanly): the supervisor stops its installation, which
    records the stop in its status file, and exits 0. The supervisor died of the signal and
    its installation logged the supervisor gone. Without warm spares: a spare is ended with
    SIGKILL at any stop (the systemd test above has one), and two made this test 6.5-7.5 CPU s
    (its processes' and pytest's own), 3.7-3.8 without."""
    cfg = drill_config(tmp_path, [])
    cfg.write_text(cfg.read_text().replace("kiosk:", "kiosk:\n  spares: 0", 1))
    env = dict(os.environ, SDL_VIDEODRIVER="dummy")
    env.pop("TABLETOP_SUPERVISED", None)
    env.pop("NOTIFY_SOCKET", None)
    p = children.popen([sys.executable, "-m", "tabletop", "run", "--config", str(cfg),
                        "--kiosk", "--headless"], env=env, stderr=subprocess.PIPE, text=True)
    lines = []
    for line in p.stderr:
        lines.append(line)
        if "installation ready" in line:
            break
    p.send_signal(signal.SIGHUP)
    _, err = p.communicate(timeout=30)
    err = "".join(lines) + err
    assert p.returncode == 0, err
    assert "Traceback" not in err and "supervisor (pid" not in err
    assert json.loads((tmp_path / "status.json").read_text())["mode"] == "stopped"
    assert "is gone" not in (tmp_path / "logs" / "tabletop.log").read_text()


# A stand-in installation: the first start is ready, then crashes; the restarted one is still
# starting (importing, as ``tabletop run`` does for its first second) when it is stopped, and
# says "interrupted" on SIGTERM there as ``tabletop run`` does (tabletop.cli). Once it said it
# is starting it makes the file sys.argv[1].
STARTING_CHILD = """
import os, signal, socket, sys, time
if os.environ["TABLETOP_RESTARTS"] == "0":
    s = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
    s.sendto(b"READY=1", os.environ["NOTIFY_SOCKET"])
    time.sleep(0.3)
    sys.exit(1)
def stopped(*_):
    print("tabletop run: interrupted", file=sys.stderr, flush=True)
    os._exit(130)
signal.signal(signal.SIGTERM, stopped)
print("tabletop: starting", file=sys.stderr, flush=True)
open(sys.argv[1], "w").close()
time.sleep(30)
"""


def test_seconds_ending_while_a_restart_starts_end_the_kiosk_as_a_timed_run(tmp_path, capfd):
    """``--seconds`` ending while a restarted installation is still starting is the kiosk's
    timed end, not an interruption: status 0 and no "interrupted" line from the child it
    stopped. The supervisor's clock jumps past the 600 s once the restarted child said it is
    starting (its file appears), however long a loaded machine took to start it."""
    started = tmp_path / "restarted-child-starting"

    def clock() -> float:
        return time.monotonic() + (1000.0 if started.exists() else 0.0)

    sup = Supervisor([sys.executable, "-c", STARTING_CHILD, str(started)],
                     Policy(stall_s=5.0, backoff_s=(0.1, 2.0), startup_s=1e6),
                     tmp_path / "crashes.log", spares=0, seconds=600.0, clock=clock)
    assert sup.run() == 0
    assert sup.starts == 2 and sup.crashes == 1
    err = capfd.readouterr().err
    assert "tabletop: starting" in err, err          # the restarted child's start is echoed
    assert "interrupted" not in err, err
