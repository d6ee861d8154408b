"""The kiosk supervisor with real processes: a crash injected in an engine and a stall injected
in the frame loop are each noticed, logged and followed by a restarted installation (how it
and its installation stop: test_supervisor_stop.py)."""

import json
import os
import subprocess
import sys
import threading
import time
from pathlib import Path

import yaml

from tabletop.kiosk.supervisor import Policy, Supervisor

ROOT = Path(__file__).resolve().parents[2]
# a stand-in installation that imports only the standard library: its interpreter without
# ``site`` (the .pth files of the installed packages), 13 against 47 ms CPU a start; the
# crash-log drill starts 30 of them
BARE = (sys.executable, "-S")


def drill_config(tmp_path: Path, faults: list[dict]) -> Path:
    cfg = {
        "loop": {"rate_hz": 30},
        "sources": [{"kind": "scripted", "pucks": [1, 2]}],
        "engines": [{"kind": "puppet_master", "name": "lover",
                     "behavior": str(ROOT / "behaviors" / "library" / "lover"),
                     "main": {"puck": 1}},
                    {"kind": "fault", "name": "drill", "faults": faults}],
        "view": {"size": [320, 180], "headless": True},
        "kiosk": {"stall_s": 2.0, "backoff_s": [0.1, 2.0], "heartbeat": {"enabled": False}},
    }
    path = tmp_path / "config.yaml"
    path.write_text(yaml.safe_dump(cfg))
    return path


def test_crash_and_stall_are_logged_and_the_kiosk_comes_back(tmp_path):
    cfg = drill_config(tmp_path, [{"start": 0, "after_s": 0.5, "kind": "crash"},
                                  {"start": 1, "after_s": 0.5, "kind": "stall"}])
    crash_log = tmp_path / "logs" / "crashes.log"
    sup = Supervisor([sys.executable, "-m", "tabletop", "run", "--config", str(cfg), "--kiosk",
                      "--headless"], Policy(stall_s=2.0, backoff_s=(0.1, 2.0), startup_s=60),
                     crash_log, echo=False)
    result = {}
    th = threading.Thread(target=lambda: result.setdefault("rc", sup.run()))
    th.start()
    end = time.monotonic() + 60
    while time.monotonic() < end and [e for e, _ in sup.events].count("ready") < 3:
        time.sleep(0.05)
    status_file = tmp_path / "status.json"    # the first status comes with a rate (a second)
    while time.monotonic() < end and '"restarts":2' not in (
            status_file.read_text() if status_file.exists() else ""):
        time.sleep(0.05)
    sup.stop.set()
    th.join(30)
    kinds = [e for e, _ in sup.events]
    assert kinds == ["ready", "crash", "ready", "stall", "ready"], kinds
    assert result["rc"] == 0 and sup.starts == 3
    text = crash_log.read_text()
    entries = text.split("=== ")[1:]
    assert len(entries) == 2
    assert "killed by SIGABRT" in entries[0]
    assert "fault.py" in entries[0]                 # the Python stack of the crash
    assert "stalled: no frame for" in entries[1]
    # the third installation ran, wrote its status, and stopped cleanly on SIGTERM (its
    # status file says so)
    status = json.loads((tmp_path / "status.json").read_text())
    assert status["restarts"] == 2 and status["mode"] == "stopped"
    for e, t in sup.events:
        print(e, round(t - sup.events[0][1], 2))


def test_a_spare_builds_the_engines_before_its_go_and_notices_a_config_edit(tmp_path):
    from tabletop.kiosk import spare
    from tabletop.kiosk.runner import Runner

    path = drill_config(tmp_path, [])
    prepared = spare.prepare(path)
    assert prepared is not None and prepared.current()
    assert [e.name for e in prepared.engines] == ["lover", "drill"]
    runner = Runner(path, prepared.cfg, headless=True, prepared=prepared)
    inst = runner._build(prepared.cfg)
    assert inst.loop.engines[0] is prepared.engines[0]       # built once, before the go
    assert inst.loop.run(seconds=0.2) > 0
    path.write_text(path.read_text().replace("rate_hz: 30", "rate_hz: 40"))
    assert not prepared.current()                            # the go loads it again
    path.write_text("engines: [{kind: nothing}]\n")
    assert spare.prepare(path) is None                       # the run after the go reports it


def test_a_kiosk_whose_recording_fails_ends_after_its_seconds_with_status_3(tmp_path):
    """``tabletop run --kiosk --seconds S`` on a full disk: the child's recording stops, the
    table runs on, and the child ends after S seconds with status 3. The supervisor took that
    for a crash and started another child, which failed its recording again: it never ended.
    The disk is full as the kernel says it (EFBIG: the child's file size limit, 64 KB)."""
    cfg = drill_config(tmp_path, [])
    limited = ("import os, resource, sys; resource.setrlimit(resource.RLIMIT_FSIZE, "
               "(65536, 65536)); os.execv(sys.executable, [sys.executable] + sys.argv[1:])")
    sup = Supervisor([sys.executable, "-c", limited, "-m", "tabletop", "run", "--config",
                      str(cfg), "--kiosk", "--headless", "--seconds", "1",
                      "--record", str(tmp_path / "session.jsonl")],
                     Policy(stall_s=5.0, backoff_s=(0.1, 2.0), startup_s=60),
                     tmp_path / "crashes.log", echo=False, spares=0)
    result = {}
    th = threading.Thread(target=lambda: result.setdefault("rc", sup.run()))
    th.start()
    end = time.monotonic() + 90
    while time.monotonic() < end and th.is_alive() and sup.starts < 3:
        time.sleep(0.05)
    sup.stop.set()
    th.join(30)
    assert sup.starts == 1, [e for e, _ in sup.events]   # not restarted as a "crash"
    assert result["rc"] == 3
    assert not (tmp_path / "crashes.log").exists()


def test_kiosk_seconds_count_from_the_first_ready_restarts_included(tmp_path):
    """``tabletop run --kiosk --seconds 2``: the kiosk stops 2 s after it was first ready,
    restarts included (not 2 s per child: a drill of 40 s would run 70 s): the child restarted
    after the first crash (at 1 s) is stopped before its own crash (1.5 s after its first
    frame)."""
    cfg = drill_config(tmp_path, [{"start": 0, "after_s": 1.0, "kind": "crash"},
                                  {"start": 1, "after_s": 1.5, "kind": "crash"}])
    cfg.write_text(cfg.read_text().replace("kiosk:", "kiosk:\n  spares: 0", 1))
    out = subprocess.run([sys.executable, "-m", "tabletop", "run", "--config", str(cfg),
                          "--kiosk", "--headless", "--seconds", "2"],
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr[-2000:]
    crashes = (tmp_path / "logs" / "crashes.log").read_text().count("=== ")
    assert crashes == 1, out.stderr[-2000:]   # the second child's crash is never reached
    # the timed end is said once (an installation it stops says "SIGTERM received": why)
    assert out.stderr.count("supervisor: --seconds 2 reached: stopping the installation") == 1


def _run_until(sup: Supervisor, done, timeout_s: float) -> None:
    """Run the supervisor in a thread until ``done()`` or ``timeout_s`` seconds, then stop it."""
    th = threading.Thread(target=sup.run)
    th.start()
    end = time.monotonic() + timeout_s
    while time.monotonic() < end and not done():
        time.sleep(0.02)
    sup.stop.set()
    th.join(30)


def test_the_crash_log_rotates_as_the_kiosk_log_does(tmp_path):
    """A table crashing again and again for weeks: the crash log is kept to max_bytes x
    (backups + 1) (it grew without end: 3.3 KB a crash of a real installation)."""
    crash_log = tmp_path / "logs" / "crashes.log"
    crash = "import sys; sys.stderr.write('the same native crash ' * 20 + '\\n'); sys.exit(1)"
    sup = Supervisor([*BARE, "-c", crash], Policy(backoff_s=(0.0, 0.0)), crash_log,
                     echo=False, spares=0, crash_log_max_bytes=2000, crash_log_backups=2)
    _run_until(sup, lambda: sup.crashes >= 30, 60.0)
    assert sup.crashes >= 30
    files = sorted(p.name for p in crash_log.parent.iterdir())
    assert files == ["crashes.log", "crashes.log.1", "crashes.log.2"], files
    sizes = [p.stat().st_size for p in crash_log.parent.iterdir()]
    assert max(sizes) < 2000 + 1000 and sum(sizes) < 3 * 3000   # each entry ~600 bytes
    assert "the same native crash" in crash_log.read_text()      # the newest one is there


def test_the_supervisor_keeps_its_last_events_not_every_one(tmp_path, monkeypatch):
    """A table crashing again and again for weeks: the supervisor's record of starts, crashes
    and stalls keeps the last ``EVENTS_KEPT`` (it grew by one per event)."""
    monkeypatch.setattr(Supervisor, "EVENTS_KEPT", 3)
    sup = Supervisor([*BARE, "-c", "import sys; sys.exit(1)"],
                     Policy(backoff_s=(0.001, 0.001)), tmp_path / "crashes.log", echo=False,
                     spares=0)
    _run_until(sup, lambda: sup.starts >= 6, 30.0)
    assert sup.starts >= 6
    assert list(sup.events) == [("crash", t) for _, t in sup.events] and len(sup.events) == 3
    assert len(sup.warm) == 3


def test_a_start_on_the_last_good_configuration_says_why_once_in_the_kiosk_log(tmp_path):
    """A kiosk that ran (its configuration kept as the last good one, as every kiosk build
    keeps it: test_live_config's restart test), then a refused config.yaml and a start: the
    table runs the last good configuration, and why is one line in ``logs/tabletop.log``
    (where the technician reads) and one on stderr, though both the supervisor's load and the
    installation's meet the refused file."""
    from tabletop.config import load_config
    from tabletop.kiosk import last_good
    cfg = drill_config(tmp_path, [])
    cfg.write_text(cfg.read_text().replace("kiosk:", "kiosk:\n  spares: 0", 1))
    run = [sys.executable, "-m", "tabletop", "run", "--config", str(cfg), "--kiosk",
           "--headless", "--seconds", "0.3"]
    # what the first run kept (a run of its own: 2.2 CPU s of the test's 4.4)
    last_good.remember(cfg, load_config(cfg))
    assert (tmp_path / ".config.yaml.last-good").is_file()
    cfg.write_text(cfg.read_text().replace("rate_hz: 30", "rate_hz: sixty"))
    out = subprocess.run(run, capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr[-2000:]
    said = "the kiosk runs the last configuration that ran"
    log_lines = [line for line in (tmp_path / "logs" / "tabletop.log").read_text().splitlines()
                 if said in line]
    assert len(log_lines) == 1 and "loop.rate_hz" in log_lines[0], log_lines
    assert out.stderr.count(said) == 1, out.stderr[-2000:]


def test_a_kiosk_whose_every_start_fails_says_restarting_and_why_in_its_status(tmp_path):
    """An installation that stops at every start (exit status 2, its one error line): the
    status file says "restarting", with the exit and that line, not the "stopped" a kiosk that
    ended on purpose left there before."""
    status_file = tmp_path / "status.json"
    status_file.write_text(json.dumps({"name": "t", "mode": "stopped"}) + "\n")
    failing = [*BARE, "-c",
               "import sys; print('tabletop run: error: /x/lover/demonstration.csv: line 9: "
               "2 values, expected 7', file=sys.stderr); sys.exit(2)"]
    sup = Supervisor(failing, Policy(backoff_s=(0.5, 1.0), startup_s=60),
                     tmp_path / "crashes.log", echo=False, spares=0,
                     status_file=status_file, name="table-3")
    th = threading.Thread(target=sup.run)
    th.start()
    status: dict = {}
    end = time.monotonic() + 60     # the file, not sup.crashes: that is counted before the write
    while time.monotonic() < end and status.get("restarts", 0) < 3:
        time.sleep(0.05)
        status = json.loads(status_file.read_text())
    sup.stop.set()                  # in the back-off, or a start: the status says it stopped
    th.join(30)
    stopped = json.loads(status_file.read_text())
    # A further crash may land between the read and the stop: the stopped status keeps the
    # last crash it wrote, which is the one read or a later one of the same kind.
    assert stopped["restarts"] >= status["restarts"]
    assert stopped == dict(stopped, mode="stopped", pid=None, supervisor_pid=os.getpid(),
                           name="table-3")
    error = ": tabletop run: error: /x/lover/demonstration.csv: line 9: 2 values, expected 7"
    assert status["mode"] == "restarting" and status["name"] == "table-3"
    assert status["restarts"] >= 3 and status["pid"] is None
    assert status["supervisor_pid"] == os.getpid()
    for said in (status, stopped):
        assert said["crash"].startswith("exit status 2 after ") and said["crash"].endswith(error)
    if stopped["restarts"] == status["restarts"]:
        assert stopped["crash"] == status["crash"]


def _first_restarting(status_file: Path, sup: Supervisor, timeout_s: float = 60.0) -> dict:
    """Run ``sup`` until its status file says "restarting"; that status (the supervisor stopped)."""
    th = threading.Thread(target=sup.run)
    th.start()
    status: dict = {}
    end = time.monotonic() + timeout_s
    try:
        while time.monotonic() < end and status.get("mode") != "restarting":
            time.sleep(0.02)
            try:
                status = json.loads(status_file.read_text())
            except (OSError, ValueError):
                pass
    finally:
        sup.stop.set()
        th.join(30)
    return status


def test_the_crash_field_names_the_error_not_the_last_info_line(tmp_path):
    """Every line logged to stderr begins "tabletop: INFO: ...": the crash field named the last
    such line, not the traceback's exception after it."""
    status_file = tmp_path / "status.json"
    crash = ("import sys; print('tabletop: INFO: recording to /x/s.jsonl', file=sys.stderr); "
             "sys.stderr.flush(); raise ValueError('boom')")
    sup = Supervisor([*BARE, "-c", crash], Policy(backoff_s=(5.0, 5.0), startup_s=60),
                     tmp_path / "crashes.log", echo=False, spares=0, status_file=status_file)
    status = _first_restarting(status_file, sup)
    assert status["crash"].startswith("exit status 1 after ")
    assert status["crash"].endswith(": ValueError: boom"), status["crash"]


def test_the_crash_line_of_a_native_crash_or_an_error_logged_before_info_lines():
    from tabletop.kiosk.crash_log import last_error
    assert last_error(["tabletop: INFO: starting", "Fatal Python error: Segmentation fault", "",
                       "Current thread 0x7f (most recent call first):",
                       '  File "/x/loop.py", line 9 in tick']) == (
        "Fatal Python error: Segmentation fault")
    assert last_error(["tabletop: ERROR: camera 0: no frame for 5.0 s",
                       "tabletop: INFO: recording stopped"]) == (
        "tabletop: ERROR: camera 0: no frame for 5.0 s")
    assert last_error(["tabletop: INFO: starting", "Killed"]) == "Killed"


def test_a_warm_spare_started_after_a_crash_finds_restarting_and_its_live_stays(tmp_path):
    """The first crash restarts at once with a warm spare: the supervisor writes "restarting"
    before the spare's go, so the spare's first status ("live") is the one that stays."""
    status_file, seen = tmp_path / "status.json", tmp_path / "seen.txt"
    child = (
        "import json, os, sys, time\n"
        "if not os.environ.get('TABLETOP_WAIT_GO'):\n"
        "    sys.exit(1)\n"                                   # every cold start crashes
        "sys.stdin.readline()\n"                              # the go
        f"s = {str(status_file)!r}\n"
        "mode = json.load(open(s)).get('mode') if os.path.exists(s) else None\n"
        f"open({str(seen)!r}, 'w').write(str(mode))\n"
        "open(s + '.tmp', 'w').write(json.dumps({'mode': 'live', 'pid': os.getpid()}))\n"
        "os.replace(s + '.tmp', s)\n"
        "time.sleep(60)\n")
    sup = Supervisor([*BARE, "-c", child], Policy(backoff_s=(5.0, 5.0), startup_s=60),
                     tmp_path / "crashes.log", echo=False, spares=1, status_file=status_file)
    th = threading.Thread(target=sup.run)
    th.start()
    try:
        end = time.monotonic() + 60
        while time.monotonic() < end and not seen.exists():
            time.sleep(0.02)
        time.sleep(1.0)             # the crash log written by now, after the spare's go
        status = json.loads(status_file.read_text())
    finally:
        sup.stop.set()
        th.join(30)
    assert seen.read_text() == "restarting"
    assert status["mode"] == "live" and sup.crashes == 1


def test_the_restarting_status_carries_every_promised_field(tmp_path):
    """The supervisor's "restarting" holds every field the README promises, as the
    installation's own status does (null where only the installation knows it), and the config
    file it runs: a script reading ``status["recording"]`` failed on it."""
    from tests.kiosk.test_health import STATUS_FIELDS
    status_file = tmp_path / "state" / "status.json"     # its folder made too
    config = tmp_path / "config.yaml"
    sup = Supervisor([*BARE, "-c", "import sys; sys.exit(1)"],
                     Policy(backoff_s=(5.0, 5.0), startup_s=60), tmp_path / "crashes.log",
                     echo=False, spares=0, status_file=status_file, config=config)
    status = _first_restarting(status_file, sup)
    promised = STATUS_FIELDS | {"idle_s", "config", "config_error", "config_pending", "studio",
                                "recording", "snapshots", "behavior_errors", "crash"}
    assert promised <= set(status), promised - set(status)
    assert status["config"] == str(config) and status["behavior_errors"] == []
    assert status["recording"] is None and status["studio"] is None


def test_the_restarting_status_names_no_installation_pid_and_the_supervisor_as_such(tmp_path):
    """While "restarting" no installation runs: ``pid`` is null (a script that signals or
    watches the status's pid reached the supervisor) and ``supervisor_pid`` is the
    supervisor's; the installation's own status names its own pid and its supervisor's."""
    status_file, own = tmp_path / "status.json", tmp_path / "own.json"
    child = ("import json, os, sys\n"
             "from tabletop.kiosk.status_fields import own_status\n"
             f"open({str(own)!r}, 'w').write(json.dumps(own_status('t', 'live')))\n"
             "sys.exit(1)\n")
    sup = Supervisor([sys.executable, "-c", child], Policy(backoff_s=(5.0, 5.0), startup_s=60),
                     tmp_path / "crashes.log", echo=False, spares=0, status_file=status_file)
    status = _first_restarting(status_file, sup)
    assert status["mode"] == "restarting"
    assert status["pid"] is None and status["supervisor_pid"] == os.getpid()
    told = json.loads(own.read_text())
    assert told["pid"] not in (None, os.getpid()) and told["supervisor_pid"] == os.getpid()
