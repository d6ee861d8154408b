"""The command line in a subprocess, as outside scripts call it."""

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from tests import children

ROOT = Path(__file__).resolve().parents[2]


def tabletop(*args, **kw) -> subprocess.CompletedProcess:
    env = dict(os.environ, SDL_VIDEODRIVER="dummy")
    return subprocess.run([sys.executable, "-m", "tabletop", *args], capture_output=True,
                          text=True, cwd=kw.pop("cwd", ROOT), env=env, timeout=120, **kw)


def frames_of(path: Path) -> list[dict]:
    lines = path.read_text().splitlines()
    assert json.loads(lines[0])["format"] == "tabletop-session"
    return [json.loads(line) for line in lines[1:]]


def test_run_headless_two_seconds_records_consecutive_frames(tmp_path):
    """``--seconds 2``: the frame loop runs 2 s (said in its last line, with the ticks it ran)
    and the recording holds every tick of it, its frames within the run. Judged against the
    run's own figures and frames: a loaded machine runs fewer or later ticks, which only
    ever lengthen the run past its 2 s, so its length is checked only at that lower end."""
    out = tmp_path / "run.jsonl"
    r = tabletop("run", "--config", "config.yaml", "--headless", "--seconds", "2",
                 "--record", str(out))
    assert r.returncode == 0, r.stderr
    assert r.stdout == ""  # no banner, no noise on stdout
    (ran,) = [ln for ln in r.stderr.splitlines() if "ran " in ln and " ticks in " in ln]
    ticks = int(ran.split("ran ")[1].split()[0])
    run_s = float(ran.split(" ticks in ")[1].split()[0])
    assert run_s >= 2.0
    frames = frames_of(out)
    seqs = [f["seq"] for f in frames]
    assert seqs == list(range(len(seqs))) and len(frames) == ticks >= 10
    # It stopped on its own once 2 s had passed: each tick starts only while under 2 s have
    # passed, and a frame's time (its capture, from the first frame's, itself after the start)
    # is no later than its tick, so every frame before the last is within the 2 s. No capture
    # is after the run's end (run_s is said to 0.01 s).
    assert frames[-2]["t"] < 2.0 and frames[-1]["t"] - frames[0]["t"] <= run_s + 0.01
    assert all(len(f["pucks"]) >= 1 for f in frames[len(frames) // 2:])


def scripted_config(tmp_path: Path) -> Path:
    """A scripted table without engines or view: a run whose facet tested is none of theirs
    (the default config's rendered camera and character cost ~0.9 CPU s more a run)."""
    cfg = tmp_path / "scripted.yaml"
    cfg.write_text("sources: [{kind: scripted, name: s}]\nengines: []\nview: {enabled: false}\n")
    return cfg


def test_a_run_shorter_than_a_second_says_its_own_rate(tmp_path):
    """Under a second there is no windowed rate yet: the last line gives the run's own average
    (ticks over seconds), not 0.0 fps, which reads as a loop that stalled."""
    r = tabletop("run", "--config", str(scripted_config(tmp_path)), "--headless", "--seconds",
                 "0.5")
    assert r.returncode == 0, r.stderr
    (ran,) = [ln for ln in r.stderr.splitlines() if "ran " in ln and " ticks in " in ln]
    ticks = int(ran.split("ran ")[1].split()[0])
    run_s = float(ran.split(" ticks in ")[1].split()[0])
    fps = float(ran.split(" at ")[1].split()[0])
    assert ticks >= 1 and fps > 0.0                 # a loaded machine may give one tick
    assert abs(fps - ticks / run_s) <= 0.05 * ticks / run_s + 0.1


def test_the_last_lines_rate_is_the_runs_own_and_the_windows_beside_it_where_they_differ():
    """"ran N ticks in T s at R fps" reads as N / T: a kiosk said "ran 755 ticks in 12.34 s at
    65.6 fps" (the kept window's rate after a catch-up); now R is the run's own, the window's
    rate said beside it where they differ by more than 2%."""
    from tabletop.commands.run import rate_words
    assert rate_words(755, 12.34, 65.6, 600) == "61.2 fps (65.6 fps over the last 600 ticks)"
    assert rate_words(242, 4.0, 60.7, 242) == "60.5 fps"       # within 2%: the average alone
    assert rate_words(30, 0.5, None, 30) == "60.0 fps"         # no window rate yet
    assert rate_words(0, 0.0, None, 0) == "0.0 fps"


def test_a_run_that_captured_nothing_says_so_in_its_last_line(tmp_path):
    """A camera that never opens: the run goes on ("one moment") and its last line says no
    capture was rendered, not "nan ms"."""
    cfg = tmp_path / "nocamera.yaml"
    cfg.write_text("sources: [{kind: camera, name: overhead, device: 57}]\n")
    r = tabletop("run", "--config", str(cfg), "--headless", "--seconds", "0.5")
    assert r.returncode == 0, r.stderr
    (ran,) = [ln for ln in r.stderr.splitlines() if "ran " in ln and " ticks in " in ln]
    assert ran.endswith("capture-to-render none (nothing was captured)") and "nan" not in ran
    assert "cannot open camera 57" in r.stderr and "Traceback" not in r.stderr


def recorded_run(out: Path, *config: str, **kw) -> subprocess.Popen:
    """``tabletop run --headless --record OUT`` (``config``: ``--config FILE``, or none for the
    default config) started as a terminal's shell starts it, ``kw`` for
    :func:`children.popen`."""
    env = dict(os.environ, SDL_VIDEODRIVER="dummy")
    return children.popen([sys.executable, "-m", "tabletop", "run", *config, "--headless",
                           "--record", str(out)], cwd=ROOT, env=env, stderr=subprocess.PIPE,
                          text=True, **kw)


def lines_in(out: Path) -> int:
    return out.read_bytes().count(b"\n") if out.exists() else 0


def wait_for_lines(out: Path, n: int, deadline: float, p: subprocess.Popen) -> None:
    """Until ``out`` holds ``n`` lines, ``p`` ends or the (monotonic) deadline passes."""
    while time.monotonic() < deadline and lines_in(out) < n and p.poll() is None:
        time.sleep(0.1)


def assert_ended_cleanly(p: subprocess.Popen, err: str, sig: signal.Signals, out: Path) -> None:
    """The run ended by ``sig`` cleanly: status 0, the signal said, the recorder closed (not
    killed) and the recording whole, every frame in order."""
    assert p.returncode == 0, err
    assert f"{sig.name} received" in err and "Traceback" not in err, err
    assert "recording " in err and " frames" in err, err  # the recorder was closed, not killed
    assert out.read_text().endswith("\n")
    frames = frames_of(out)
    assert [f["seq"] for f in frames] == list(range(len(frames)))


def test_a_sighup_ends_a_run_cleanly_with_a_complete_recording(tmp_path):
    """A SIGHUP (a closed terminal or session) ends a run as Ctrl-C does, its recording
    complete. (SIGTERM's clean end, the same handler: the nohup test below ends the default
    config's run, its camera and character, with it.)"""
    out = tmp_path / "hup.jsonl"
    p = recorded_run(out, "--config", str(scripted_config(tmp_path)))
    wait_for_lines(out, 30, time.monotonic() + 60, p)
    p.send_signal(signal.SIGHUP)
    _, err = p.communicate(timeout=30)
    assert_ended_cleanly(p, err, signal.SIGHUP, out)


def test_a_run_started_under_nohup_outlives_a_sighup_and_ends_cleanly_on_sigterm(tmp_path):
    """``nohup tabletop run ... &`` starts the run with SIGHUP ignored, to outlive the
    terminal: a SIGHUP (the logout) leaves it running; SIGTERM still ends it cleanly, its
    recording complete. The run caught SIGHUP whatever it inherited, and a logout ended it.
    (One run for both facets: SIGTERM's handler is installed whatever SIGHUP's disposition,
    tabletop.cli.catch_stop_signals.)"""
    out = tmp_path / "nohup.jsonl"
    p = recorded_run(out, preexec_fn=lambda: signal.signal(signal.SIGHUP, signal.SIG_IGN))
    deadline = time.monotonic() + 60
    wait_for_lines(out, 30, deadline, p)
    p.send_signal(signal.SIGHUP)
    wait_for_lines(out, lines_in(out) + 30, deadline, p)
    running = p.poll() is None
    p.send_signal(signal.SIGTERM)
    _, err = p.communicate(timeout=30)
    assert running, err
    assert "SIGHUP" not in err, err
    assert_ended_cleanly(p, err, signal.SIGTERM, out)


def caught(pid: int, sig: int) -> bool:
    """Does process ``pid`` catch ``sig`` now (its SigCgt mask in /proc)?"""
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("SigCgt:"):
            return bool(int(line.split()[1], 16) >> (sig - 1) & 1)
    return False


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGHUP], ids=["SIGTERM", "SIGHUP"])
def test_a_stop_signal_while_a_run_imports_its_modules_is_an_interrupt(sig):
    """SIGTERM or SIGHUP landing while ``run`` is still importing its modules (the first second
    or so) ends it as a Ctrl-C there does: one line, status 130. The signal killed the process
    without a word (status -15 / -1). It is sent as soon as the process catches it."""
    env = dict(os.environ, SDL_VIDEODRIVER="dummy")
    p = children.popen([sys.executable, "-m", "tabletop", "run", "--headless", "--seconds",
                        "30"], cwd=ROOT, env=env, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 30
    while time.monotonic() < deadline and p.poll() is None and not caught(p.pid, sig):
        time.sleep(0.001)
    p.send_signal(sig)
    _, err = p.communicate(timeout=60)
    assert p.returncode == 130, err
    assert err.strip().splitlines() == ["tabletop run: interrupted"]


def test_a_replay_stopped_by_a_signal_says_so_and_exits_130(tmp_path):
    """An outside script comparing a replay's --out must not take a replay cut short for a
    whole one: it exited 0, "replayed N frames", whatever part of the recording was left."""
    from tabletop.app import build_live
    from tabletop.config import load_config
    # the recording, 3 s of a scripted table, made here (the replay is the process tested)
    rec, out = tmp_path / "rec.jsonl", tmp_path / "out.jsonl"
    build_live(load_config(scripted_config(tmp_path)), record_path=rec).loop.run(seconds=3)
    recorded = len(frames_of(rec))
    p = children.popen([sys.executable, "-m", "tabletop", "replay", str(rec), "--no-view",
                        "--out", str(out)], cwd=ROOT, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and (not out.exists() or out.read_bytes().count(b"\n") < 31):
        time.sleep(0.05)   # the header and 30 frames
    p.send_signal(signal.SIGINT)
    _, err = p.communicate(timeout=30)
    assert p.returncode == 130, err
    replayed = len(frames_of(out))
    assert 30 <= replayed < recorded
    assert f"replay interrupted by SIGINT after {replayed} frames of {rec}" in err, err
    assert "Traceback" not in err and "replayed " not in err


def small_parts_config(tmp_path: Path) -> Path:
    """A config recording parts of 0.05 MB with the lover's behaviour (a 0.14 MB header)."""
    lover = ROOT / "behaviors" / "library" / "lover"
    cfg = tmp_path / "small.yaml"
    cfg.write_text("sources: [{kind: scripted, name: s}]\n"
                   f"engines: [{{kind: puppet_master, name: lover, behavior: {lover}, "
                   "main: {puck: 1}}]\nview: {enabled: false}\n"
                   "recorder: {enabled: true, folder: rec, max_mb: 0.05}\n")
    return cfg


def test_a_recorder_max_mb_the_header_alone_reaches_is_refused_at_start(tmp_path):
    """Every part begins with the header (the config and the files it names: the lover's
    behaviour makes it 0.14 MB): with max_mb 0.05 each frame started a part of its own (480
    files in 8 s) and the run said nothing of it."""
    cfg = small_parts_config(tmp_path)
    r = tabletop("run", "--config", str(cfg), "--seconds", "1")
    assert r.returncode == 2, r.stderr
    (line,) = r.stderr.splitlines()
    assert line.startswith(f"tabletop run: error: {cfg}: recorder.max_mb: 0.05 MB is less than "
                           "the header every part of the recording begins with (0.1"), line
    assert not (tmp_path / "rec").exists() or not any((tmp_path / "rec").iterdir())


def test_a_recorder_max_mb_below_the_header_runs_on_at_a_supervised_restart(tmp_path):
    """A supervised start (a crash or morning restart, a named file grown since the config
    first ran) runs on with parts of 4 headers, saying why once, where it was refused and
    every supervised restart failed the same way: the table was down."""
    cfg = small_parts_config(tmp_path)
    env = dict(os.environ, SDL_VIDEODRIVER="dummy", TABLETOP_SUPERVISED="1",
               TABLETOP_SUPERVISOR_PID=str(os.getpid()))
    r = subprocess.run([sys.executable, "-m", "tabletop", "run", "--config", str(cfg),
                        "--seconds", "1"], capture_output=True, text=True, cwd=ROOT, env=env,
                       timeout=120)
    assert r.returncode == 0, r.stderr
    (warning,) = [line for line in r.stderr.splitlines() if "recorder.max_mb" in line]
    assert "0.05 MB is less than the header" in warning and "parts of 0.5" in warning, warning
    (part,) = (tmp_path / "rec").iterdir()    # one part: 1 s of frames is far below 4 headers
    assert len(frames_of(part)) >= 10



def test_a_recorder_max_mb_below_the_header_runs_on_in_a_kiosk_systemd_restarts(tmp_path):
    """``--kiosk --no-supervisor`` (systemd restarting it): every start may be a restart, and
    each was refused as a first start, so the table stayed down after a crash or a reboot."""
    cfg = small_parts_config(tmp_path)
    r = tabletop("run", "--config", str(cfg), "--seconds", "1", "--kiosk", "--no-supervisor",
                 "--headless")
    assert r.returncode == 0, r.stderr
    assert any("recorder.max_mb: 0.05 MB is less than the header" in line
               for line in r.stderr.splitlines()), r.stderr
    assert any((tmp_path / "rec").iterdir())


def test_no_supervisor_without_a_kiosk_is_refused(tmp_path):
    """``--no-supervisor`` says where a kiosk's loop runs: on a run that is no kiosk (no
    ``--kiosk``, ``kiosk.enabled`` off) it did nothing and said nothing."""
    cfg = tmp_path / "plain.yaml"
    cfg.write_text("sources: [{kind: scripted, name: s}]\nengines: []\nview: {enabled: false}\n"
                   "recorder: {enabled: true, folder: rec}\n")
    r = tabletop("run", "--config", str(cfg), "--seconds", "1", "--no-supervisor")
    assert (r.returncode, r.stderr.splitlines()) == (2, [
        f"tabletop run: error: --no-supervisor is for a kiosk: add --kiosk (or kiosk.enabled: "
        f"true in {cfg})"])
    assert not (tmp_path / "rec").exists()   # nothing ran


def test_version_and_help():
    r = tabletop("--version")
    assert r.returncode == 0 and r.stdout.startswith("tabletop ")
    r = tabletop("--help")
    assert r.returncode == 0
    for cmd in ("run", "replay"):
        assert cmd in r.stdout
        sub = tabletop(cmd, "--help")
        assert sub.returncode == 0 and "usage: tabletop " + cmd in sub.stdout


def test_no_command_is_a_usage_error_on_stderr():
    """``tabletop`` alone is bad usage, as ``tabletop calibrate`` without its step: one line on
    stderr naming what is missing, status 2, nothing on stdout (it printed the whole help on
    stdout with status 2: a script's output got the help, and the README's statuses say 2 is
    bad input told in one line on stderr)."""
    r = tabletop()
    assert r.returncode == 2
    assert r.stdout == ""
    lines = r.stderr.splitlines()
    assert len(lines) == 1 and "COMMAND" in lines[0] and "tabletop --help" in lines[0], lines


def test_bad_config_is_one_line_not_a_traceback(tmp_path):
    cfg = tmp_path / "bad.yaml"
    cfg.write_text("sources:\n  - kind: scripted\n    pucks: seven\n")
    r = tabletop("run", "--config", str(cfg), "--headless", "--seconds", "1")
    assert r.returncode == 2
    assert "Traceback" not in r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "sources[0].pucks" in lines[0] and "bad.yaml" in lines[0]


def test_replay_of_a_missing_file_is_one_line(tmp_path):
    r = tabletop("replay", str(tmp_path / "absent.jsonl"))
    assert r.returncode == 2 and "not found" in r.stderr and "Traceback" not in r.stderr


@pytest.mark.parametrize("seconds", ["0", "-3"])
def test_bad_seconds(seconds):
    r = tabletop("run", "--headless", "--seconds", seconds)
    assert r.returncode == 2 and "--seconds" in r.stderr


def test_the_command_line_and_a_refused_value_import_no_pygame_nor_numpy():
    """Building the command line (every command's options, ``--help``, ``--version``) and
    refusing a value load neither pygame and OpenCV nor numpy (0.2 of the 0.32 CPU s of a
    ``tabletop --version``)."""
    code = ("import sys; from tabletop import cli; rc = cli.main(['run', '--seconds', '-3']); "
            "print(rc, *(m in sys.modules for m in ('pygame', 'cv2', 'numpy')))")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT)
    assert r.stdout.split() == ["2", "False", "False", "False"], r.stderr
    assert r.stderr.startswith("tabletop run: error: --seconds '-3' must be"), r.stderr


def test_a_value_list_beginning_with_a_minus_sign_is_a_value():
    """``--view -90,15`` (the character's left side) is the azimuth -90, as ``--view=-90,15``
    is; argparse took a comma list beginning with '-' for an option ("expected one argument")."""
    spaced = tabletop("pose", "--describe", "--view", "-90,15")
    joined = tabletop("pose", "--describe", "--view=-90,15")
    assert spaced.returncode == joined.returncode == 0, spaced.stderr
    assert spaced.stdout == joined.stdout
    bad = tabletop("behave", "--train", "d.csv", "--input", "m.csv", "--out", "r.csv",
                   "--table", "-1.2,0.8")
    assert bad.returncode == 2
    assert bad.stderr.strip() == ("tabletop behave: error: --table '-1.2,0.8': width and height "
                                  "must be metres from 0.05 to 20")


def test_a_file_named_as_an_image_that_is_none_is_one_line(tmp_path):
    """``track`` of a ``.png`` holding text: OpenCV hands it to FFmpeg, whose own log line
    ("[png @ 0x...] Invalid PNG signature") came before ours: two lines, one of them not ours."""
    fake = tmp_path / "frame.png"
    fake.write_text("not an image")
    r = tabletop("track", str(fake), "--out", str(tmp_path / "o.jsonl"))
    assert r.returncode == 2
    lines = r.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"tabletop track: error: {fake}:"), lines


INTERRUPT_AT_NUMPY = """
import os, signal, sys
class InterruptAtNumpy:
    \"\"\"A Ctrl-C (SIGINT to this process) as numpy's import begins, once.\"\"\"
    sent = False
    def find_spec(self, name, path=None, target=None):
        if name == "numpy" and not self.sent:
            self.sent = True
            os.kill(os.getpid(), signal.SIGINT)
        return None
sys.meta_path.insert(0, InterruptAtNumpy())
from tabletop.cli import main
sys.exit(main(sys.argv[1:]))
"""


def test_ctrl_c_while_the_command_line_starts_is_one_line_and_130():
    """README: 130 when interrupted, one line, never a traceback. A Ctrl-C in the first
    fraction of a second (numpy and the commands' modules being imported) printed a
    KeyboardInterrupt traceback. The child interrupts itself as numpy's import begins (an
    import finder of its own), so the Ctrl-C always lands among the imports; ``status``
    would then wait 60 s for heartbeats."""
    port = free_port()
    r = children.run([sys.executable, "-c", INTERRUPT_AT_NUMPY, "status",
                      f"127.0.0.1:{port}", "--seconds", "60"], capture_output=True, text=True,
                     cwd=ROOT, timeout=120)
    assert r.returncode == 130 and r.stderr.splitlines() == ["tabletop status: interrupted"], \
        r.stderr[-2000:]


def free_port() -> int:
    import socket
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.mark.parametrize("args", [("pose", "--describe"),
                                  ("pose", "--describe", "--out", "/dev/stdout")])
def test_a_reader_that_closes_the_output_early_ends_the_command_quietly(args):
    """``tabletop pose --describe | head -c 0``: the reader is gone before the command writes;
    no error line (the input was fine), status 141 as for a program ended by SIGPIPE. It was
    "error: Broken pipe", status 2, the status of bad input."""
    p = subprocess.Popen([sys.executable, "-m", "tabletop", *args], cwd=ROOT,
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         env=dict(os.environ, SDL_VIDEODRIVER="dummy"))
    p.stdout.close()
    err = p.stderr.read().decode()
    p.stderr.close()
    assert p.wait(timeout=60) == 141 and err == "", err


def test_run_kiosk_refuses_a_status_file_that_is_the_config(tmp_path):
    """``run --kiosk`` with ``kiosk.enabled`` off checks the kiosk's files as ``enabled``
    does: a config named status.json beside no other status file would be replaced by the
    status JSON."""
    cfg = tmp_path / "status.json"
    text = "sources: [{kind: scripted, name: s}]\nengines: []\nview: {enabled: false}\n"
    cfg.write_text(text)
    r = tabletop("run", "--config", str(cfg), "--seconds", "1", "--kiosk", "--headless")
    assert r.returncode == 2, r.stderr
    (line,) = r.stderr.splitlines()
    assert f"{cfg}: kiosk.status_file: {cfg} is the config file itself" in line, line
    assert cfg.read_text() == text
