"""The kiosk's status file as a kiosk run leaves it: the recording it writes (or why it stopped),
every promised field also for parts that are off, and "stopped" as the last word of a kiosk,
also one stopped before its first status or while a slow status write was still going on."""

import json

from tabletop.frames import Frame
from tabletop.kiosk.health import HealthReporter
from tabletop.loop import LoopStats
from tests.kiosk.test_health import STATUS_FIELDS


def test_the_status_says_when_the_recording_stopped_on_a_full_disk(tmp_path):
    """A kiosk whose disk is full (as the kernel says it: EFBIG, the process's file size limit
    of 8 KB, above the status file)
    keeps running without recording; its status (and so the heartbeat) says so, not only a
    log line."""
    import resource
    import signal
    import subprocess
    import sys

    import yaml

    def limit() -> None:
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (8192, 8192))

    gesture = tmp_path / "g.csv"
    gesture.write_text("t,dx,dy\n" + "".join(f"{i / 100},{i / 1e4:.6f},0.0\n" for i in range(500)))
    cfg = tmp_path / "config.yaml"
    cfg.write_text(yaml.safe_dump({
        "sources": [{"kind": "scripted", "pucks": [1, 2, 5],
                     "performers": [{"puck": 3, "home": [0.5, 0.4], "gestures": ["g.csv"]}]}],
        "view": {"size": [320, 180], "headless": True},
        "recorder": {"enabled": True, "folder": "sessions"},
        "kiosk": {"heartbeat": {"enabled": False}}}))
    r = subprocess.run([sys.executable, "-m", "tabletop", "run", "--config", str(cfg),
                        "--kiosk", "--no-supervisor", "--headless", "--seconds", "2"],
                       capture_output=True, text=True, preexec_fn=limit, timeout=120)
    assert r.returncode == 3, r.stderr[-2000:]
    status = json.loads((tmp_path / "status.json").read_text())
    assert "File too large" in status["recording"]["failed"]
    assert str(tmp_path / "sessions") in status["recording"]["failed"]


def test_the_status_of_a_kiosk_that_records_names_its_file(tmp_path):
    """The ``recording`` field while recording: the file, frames written, ``failed`` null."""
    import subprocess
    import sys

    import yaml
    cfg = tmp_path / "config.yaml"
    cfg.write_text(yaml.safe_dump({
        "sources": [{"kind": "scripted", "pucks": [1, 2]}],
        "view": {"size": [320, 180], "headless": True},
        "recorder": {"enabled": True, "folder": "sessions"},
        "kiosk": {"heartbeat": {"enabled": False}}}))
    r = subprocess.run([sys.executable, "-m", "tabletop", "run", "--config", str(cfg),
                        "--kiosk", "--no-supervisor", "--headless", "--seconds", "2"],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr[-2000:]
    rec = json.loads((tmp_path / "status.json").read_text())["recording"]
    (session,) = (tmp_path / "sessions").glob("session-*.jsonl")
    assert rec["file"] == str(session) and rec["frames"] > 0 and rec["failed"] is None


def test_the_status_carries_every_promised_field_also_for_parts_that_are_off(tmp_path):
    """Every field the status promises (README "Health", health.py) is there, null for a part
    that is off: a kiosk without a studio and with ``watch_config: false`` sent no ``studio``,
    ``config`` or ``config_error`` at all, and a script reading ``status["studio"]`` failed."""
    import subprocess
    import sys

    import yaml
    cfg = tmp_path / "config.yaml"
    cfg.write_text(yaml.safe_dump({
        "sources": [{"kind": "scripted", "pucks": [1, 2]}],
        "view": {"size": [320, 180], "headless": True},
        "kiosk": {"heartbeat": {"enabled": False}, "watch_config": False}}))
    r = subprocess.run([sys.executable, "-m", "tabletop", "run", "--config", str(cfg),
                        "--kiosk", "--no-supervisor", "--headless", "--seconds", "2"],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr[-2000:]
    status = json.loads((tmp_path / "status.json").read_text())
    promised = STATUS_FIELDS | {"idle_s", "config", "config_error", "studio", "recording",
                                "snapshots", "behavior_errors"}
    assert promised <= set(status), promised - set(status)
    assert status["studio"] is None and status["config_error"] is None
    assert status["config"] == str(cfg) and status["recording"] is None
    assert status["snapshots"] is None and status["behavior_errors"] == []


def test_a_kiosk_that_stops_before_its_first_status_says_so_over_the_one_before(tmp_path):
    """The status file held the last kiosk's "live" (a kiosk killed before it); this one
    stopped within its first second, before its first status (the loop waits for a rate):
    the file says this kiosk stopped, with every promised field, not the dead one's "live"."""
    import os
    status_file = tmp_path / "status.json"
    status_file.write_text(json.dumps({"name": "table-7", "pid": 999_999, "mode": "live",
                                       "fps": 60.0}) + "\n")
    stats = LoopStats()
    rep = HealthReporter("table-7", stats, status_file=status_file,
                         extra=lambda: {"config_error": None})
    rep(Frame(seq=0, t=0.0))                 # no rate yet: no status
    assert json.loads(status_file.read_text())["pid"] == 999_999
    rep.close()
    rep.stopped()
    status = json.loads(status_file.read_text())
    assert STATUS_FIELDS | {"config_error"} <= set(status)
    assert status["pid"] == os.getpid() and status["mode"] == "stopped" and status["fps"] == 0
    assert status["sources"] == [] and status["ticks"] == 0


def test_the_stopped_status_is_the_last_even_after_a_slow_status_write(tmp_path):
    """The status writer still busy when the kiosk stops (an fsync on an SD card outlasting
    close's wait, stood in for by its warning held in a log handler): the "stopped" written
    beside it was overwritten by its late "live", the file saying live with a dead pid. And a
    kiosk stopped before its first status made no status folder: "stopped" was not written."""
    import logging
    import threading
    entered, release = threading.Event(), threading.Event()

    class Held(logging.Handler):
        def emit(self, record: logging.LogRecord) -> None:
            if record.getMessage().startswith("status file") and not release.is_set():
                entered.set()
                release.wait(60)

    folder = tmp_path / "run"
    folder.write_text("a file where the status folder goes")   # the first write fails
    held = Held()
    logging.getLogger("tabletop").addHandler(held)
    try:
        rep = HealthReporter("table-7", LoopStats(), status_file=folder / "status.json")
        rep.writer.close_wait_s = 0.5      # (5 s in a kiosk: the same race, sooner)
        rep.writer.put(json.dumps({"mode": "live"}))
        assert entered.wait(60)            # the writer is in its (failed) write, held
        folder.unlink()
        rep.writer.put(json.dumps({"mode": "live"}) + "\n")   # the live still to be written
        rep.close()                        # its wait over, the writer still busy
        rep.stopped()
        release.set()
        rep.writer._thread.join(60)
        assert not rep.writer._thread.is_alive()
    finally:
        release.set()
        logging.getLogger("tabletop").removeHandler(held)
    assert json.loads((folder / "status.json").read_text())["mode"] == "stopped"

    missing = tmp_path / "not" / "yet" / "status.json"
    rep = HealthReporter("table-7", LoopStats(), status_file=missing)
    rep.close()
    rep.stopped()
    assert json.loads(missing.read_text())["mode"] == "stopped"


def test_a_kiosk_stopped_on_purpose_says_so_in_a_last_heartbeat(tmp_path):
    """A gallery watching the heartbeats (``tabletop status``) saw a kiosk stopped on purpose
    fall silent, as one that crashed or lost its power does; only its status file said
    "stopped". Its last heartbeat now says it, with 0 fps; one without a status file too."""
    from tabletop.commands.status import format_heartbeat
    from tabletop.kiosk.health import Heartbeat
    from tests.kiosk.test_health import Clock, OscListener
    from tracking.scenes import wait_for
    osc, clock, stats = OscListener(), Clock(), LoopStats()
    stats.tick_times.extend(k / 30.0 for k in range(31))
    try:
        for status_file in (tmp_path / "status.json", None):
            rep = HealthReporter("table-7", stats, status_file=status_file, clock=clock,
                                 heartbeat=Heartbeat("127.0.0.1", osc.port), started=40.0)
            rep(Frame(seq=0, t=clock.t))
            assert wait_for(lambda: len(osc.got) % 2 == 1, 5.0)
            rep.close()
            clock.t += 3.0
            rep.stopped()
            assert wait_for(lambda: len(osc.got) % 2 == 0, 5.0)
            name, uptime, fps, unhealthy, text = osc.got[-1]
            assert json.loads(text)["mode"] == "stopped" and fps == 0.0 and uptime == clock.t - 40
            assert format_heartbeat("127.0.0.1:1", name, uptime, fps, unhealthy,
                                    text).endswith("0.0 fps  0 unhealthy  stopped")
    finally:
        osc.close()
    assert json.loads((tmp_path / "status.json").read_text())["mode"] == "stopped"
