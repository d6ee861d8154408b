"""One kiosk per installation folder, with real processes: a second kiosk started on the
folder of a running one is refused in one line (status 2) and leaves the first untouched; the
first's own restarts (warm spares) are never refused; a kiosk killed outright leaves no lock
behind; the folder's own Python packages are not imported in the installed code's place."""

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
import yaml

from tracking.scenes import wait_for

ROOT = Path(__file__).resolve().parents[2]


def kiosk_config(tmp_path: Path, faults: list[dict], spares: int = 1) -> Path:
    cfg = {
        "loop": {"rate_hz": 30},
        "sources": [{"kind": "synthetic_camera", "name": "camera", "pucks": [1, 2],
                     "resolution": [320, 180], "fps": 30, "hands": {"every_s": 0}}],
        "engines": [{"kind": "fault", "name": "drill", "faults": faults}],
        "view": {"size": [320, 180], "headless": True},
        "recorder": {"enabled": True, "folder": "sessions"},
        "kiosk": {"spares": spares, "stall_s": 5.0, "backoff_s": [0.1, 2.0],
                  "heartbeat": {"enabled": False, "every_s": 0.2}},   # status.json 5 a second
    }
    path = tmp_path / "config.yaml"
    path.write_text(yaml.safe_dump(cfg))
    return path


def run(cfg: Path, *extra: str, **kw) -> subprocess.Popen:
    env = dict(os.environ, SDL_VIDEODRIVER="dummy")
    env.pop("TABLETOP_SUPERVISED", None)
    return subprocess.Popen([sys.executable, "-m", "tabletop", "run", "--config", str(cfg),
                             "--kiosk", "--headless", *extra], env=env,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, **kw)


def status(tmp_path: Path) -> dict:
    try:
        return json.loads((tmp_path / "status.json").read_text())
    except (OSError, ValueError):
        return {}


def test_a_second_kiosk_on_the_folder_is_refused_and_a_killed_one_leaves_no_lock(tmp_path):
    # the first kiosk's first installation crashes: its restart (a warm spare) must run
    cfg = kiosk_config(tmp_path, [{"start": 0, "after_s": 0.3, "kind": "crash"}])
    first = run(cfg, start_new_session=True)
    try:
        assert wait_for(lambda: status(tmp_path).get("restarts") == 1
                        and status(tmp_path).get("mode") == "live"
                        and status(tmp_path).get("ticks", 0) > 30, 90, every_s=0.1), \
            "the first kiosk's restarted installation never ran: " + str(status(tmp_path))
        assert first.poll() is None
        before = status(tmp_path)
        recordings = sorted(p.name for p in (tmp_path / "sessions").iterdir())
        log_before = (tmp_path / "logs" / "tabletop.log").read_text()

        for extra in ((), ("--no-supervisor",)):
            second = run(cfg, "--seconds", "5", *extra)
            _, err = second.communicate(timeout=60)
            lines = err.strip().splitlines()
            assert second.returncode == 2, err
            assert lines == [f"tabletop run: error: another kiosk is running on {tmp_path} "
                             f"(pid {first.pid}, lock .kiosk.tabletop-lock); stop it first, or "
                             f"start this one from another folder"], err

        # the first ran on, untouched: same installation, still writing its status and its
        # recording; no recording, log line or start of the second
        assert first.poll() is None
        assert wait_for(lambda: status(tmp_path).get("ticks", 0) > before["ticks"] + 30, 30,
                        every_s=0.1)
        after = status(tmp_path)
        assert after["pid"] == before["pid"] and after["restarts"] == 1
        assert after["mode"] == "live"
        assert sorted(p.name for p in (tmp_path / "sessions").iterdir()) == recordings
        log_after = (tmp_path / "logs" / "tabletop.log").read_text()
        assert log_after.startswith(log_before)
        assert log_after.count("supervisor: started the installation") == 2
        assert "another kiosk" not in log_after

        # kill -9 of the whole kiosk (as a power cut): no stale lock refuses the next start
        os.killpg(first.pid, signal.SIGKILL)
        first.wait(10)
    finally:
        if first.poll() is None:
            os.killpg(first.pid, signal.SIGKILL)
            first.wait(10)
    assert (tmp_path / ".kiosk.tabletop-lock").exists()
    # the next start takes the lock (the first thing a start does, tabletop.commands.run):
    # its lock_folder in a process of its own, 0.35 CPU s (a whole kiosk run of a second, as
    # here before, 1.7-2.2 CPU s with its supervisor)
    nxt = refusal(tmp_path)
    assert nxt.stdout.startswith("fd ") and nxt.stdout.split()[1].isdigit(), \
        nxt.stdout + nxt.stderr


HOLD = """
import logging, sys
from pathlib import Path
logging.basicConfig(level=logging.WARNING, format="%(message)s")
{before}
from tabletop.kiosk.lock import lock_folder
print("fd", lock_folder(Path(sys.argv[1])), flush=True)
sys.stdin.read()          # held until the test closes our standard input
"""


def holder(folder: Path, before: str = "", prefix: tuple[str, ...] = ()) -> subprocess.Popen:
    """A process that takes ``folder``'s kiosk lock (after running ``before``) and keeps it
    until its standard input closes; its first line says the descriptor it got."""
    return subprocess.Popen([*prefix, sys.executable, "-c", HOLD.format(before=before),
                             str(folder)], cwd=ROOT, stdin=subprocess.PIPE,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def refusal(folder: Path, prefix: tuple[str, ...] = ()) -> subprocess.CompletedProcess:
    """Another start's lock_folder on ``folder``, in its own process (run under ``prefix``)."""
    code = ("import sys; from pathlib import Path; from tabletop.kiosk.lock import lock_folder\n"
            "try:\n    print('fd', lock_folder(Path(sys.argv[1])))\n"
            "except Exception as exc:\n    print('refused:', exc)\n")
    return subprocess.run([*prefix, sys.executable, "-c", code, str(folder)], cwd=ROOT,
                          capture_output=True, text=True, timeout=60)


def test_taking_the_lock_loads_neither_the_config_plugins_nor_numpy(tmp_path):
    """The lock imported alone (the first thing a kiosk's start does) is a light import: the
    kiosk's config section, which loads the plugins it is checked with and numpy, is
    tabletop.kiosk.settings (a process taking the lock 0.42 -> 0.1 CPU s)."""
    code = ("import sys; from pathlib import Path; from tabletop.kiosk.lock import lock_folder\n"
            "print(lock_folder(Path(sys.argv[1])) is not None, "
            "*(m in sys.modules for m in ('numpy', 'tabletop.plugins.scripted')))\n")
    r = subprocess.run([sys.executable, "-c", code, str(tmp_path)], cwd=ROOT,
                       capture_output=True, text=True, timeout=60)
    assert r.stdout.split() == ["True", "False", "False"], r.stdout + r.stderr


def test_a_full_disk_keeps_the_lock_and_skips_the_pid(tmp_path):
    """The pid's 6-byte write fails as on a full disk (a file size limit of 0 stands in for
    it): the kiosk starts, holding the lock, and says so in one log line; a second start is
    still refused. The OSError stopped every kiosk start with "No space left on device"."""
    first = holder(tmp_path, "import resource; resource.setrlimit(resource.RLIMIT_FSIZE, (0, 0))")
    try:
        line = first.stdout.readline()
        assert line.startswith("fd ") and line.split()[1].isdigit(), \
            line + first.communicate(timeout=30)[1][-2000:]
        second = refusal(tmp_path)
        assert second.stdout.strip() == (
            f"refused: another kiosk is running on {tmp_path} (its pid not yet written, lock "
            f".kiosk.tabletop-lock); stop it first, or start this one from another folder"), \
            second.stdout + second.stderr
    finally:
        _, err = first.communicate(timeout=30)
    assert err.splitlines() == [f"kiosk lock {tmp_path / '.kiosk.tabletop-lock'}: held, but "
                                "this kiosk's pid cannot be written in it (File too large)"], err


def test_a_lock_file_this_account_cannot_write_still_locks(tmp_path, unprivileged):
    """The service made the lock file (0644) and a technician starts a kiosk by hand under
    another account: the lock is taken read-only, so the technician's start is refused while
    the service runs (naming the service's pid) and locks the folder once it has ended. Its
    open for writing failed and it ran unlocked beside the service."""
    other = unprivileged
    service = holder(tmp_path)
    try:
        assert service.stdout.readline().startswith("fd ")
        lock = tmp_path / ".kiosk.tabletop-lock"
        lock.chmod(0o444)          # not writable by the technician's account
        technician = refusal(tmp_path, other)
        assert technician.stdout.strip() == (
            f"refused: another kiosk is running on {tmp_path} (pid {service.pid}, lock "
            f".kiosk.tabletop-lock); stop it first, or start this one from another folder"), \
            technician.stdout + technician.stderr
    finally:
        service.communicate(timeout=30)
    technician = holder(tmp_path, prefix=other)
    try:
        line = technician.stdout.readline()
        assert line.startswith("fd ") and line.split()[1].isdigit(), \
            line + technician.communicate(timeout=30)[1][-2000:]
        third = refusal(tmp_path)          # the technician's read-only lock refuses the next
        assert third.stdout.startswith(f"refused: another kiosk is running on {tmp_path}"), \
            third.stdout + third.stderr
    finally:
        _, err = technician.communicate(timeout=30)
    assert err == "", err


def test_a_folder_this_account_cannot_write_says_why_the_lock_was_not_made(tmp_path,
                                                                          unprivileged):
    """No lock file yet, in a folder the account cannot write: the kiosk runs unlocked and
    the log says why, "Permission denied" (it said "No such file or directory", the error of
    the read-only open tried next)."""
    other = unprivileged
    folder = tmp_path / "installation"
    folder.mkdir()
    folder.chmod(0o555)
    code = ("import logging, sys; from pathlib import Path\n"
            "logging.basicConfig(level=logging.WARNING, format='%(message)s')\n"
            "from tabletop.kiosk.lock import lock_folder\n"
            "print('fd', lock_folder(Path(sys.argv[1])))\n")
    r = subprocess.run([*other, sys.executable, "-c", code, str(folder)], cwd=ROOT,
                       capture_output=True, text=True, timeout=60)
    assert r.stdout.strip() == "fd None", r.stdout + r.stderr
    assert r.stderr.splitlines() == [f"kiosk lock {folder / '.kiosk.tabletop-lock'} cannot be "
                                     f"made (Permission denied): a second kiosk on {folder} "
                                     "would not be refused"], r.stderr


def test_a_refusal_by_a_holder_whose_pid_has_ended_says_it_is_ending(tmp_path):
    """The pid in the lock file is a process gone (a supervisor killed outright while its
    installation, holding the lock, still ends; a holder that could not write its own): the
    refusal says so and to try again, not "pid N" alone, naming a process that is not there."""
    first = holder(tmp_path)
    try:
        line = first.stdout.readline()
        assert line.startswith("fd "), line + first.communicate(timeout=30)[1][-2000:]
        gone = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                              capture_output=True, text=True, timeout=60)
        dead = int(gone.stdout)
        (tmp_path / ".kiosk.tabletop-lock").write_text(f"{dead}\n")
        second = refusal(tmp_path)
        assert second.stdout.strip() == (
            f"refused: another kiosk is running on {tmp_path} (lock .kiosk.tabletop-lock; the "
            f"pid written there, {dead}, has ended: a kiosk still ending, or one that could not "
            f"write its pid); try again in a few seconds, or stop it first"), second.stdout
    finally:
        first.communicate(timeout=30)


def test_a_kiosk_started_in_a_folder_holding_a_package_of_ours_runs_the_installed_code(tmp_path):
    """The installation and its spares are ``python -m tabletop``, which puts the current
    folder first on the import path: a gallery folder holding a copy of ``behaviors/`` (for its
    library, with an older checkout's code) or ``tracking/`` had the kiosk run that code
    instead of the installed one's."""
    from tests.kiosk.test_supervisor import drill_config
    cfg = drill_config(tmp_path, [])
    cfg.write_text(cfg.read_text().replace("kiosk:", "kiosk:\n  spares: 0", 1))
    (tmp_path / "tracking").mkdir()
    marker = tmp_path / "tracking" / "imported"
    (tmp_path / "tracking" / "__init__.py").write_text(
        f"open({str(marker)!r}, 'w').close()\nraise SystemExit(9)\n")
    script = Path(sys.executable).with_name("tabletop")   # as a technician starts it
    p = subprocess.Popen([str(script), "run", "--config", str(cfg), "--kiosk", "--headless",
                          "--seconds", "0.3"], cwd=tmp_path, stderr=subprocess.PIPE, text=True)
    end = time.monotonic() + 120
    while p.poll() is None and not marker.exists() and time.monotonic() < end:
        time.sleep(0.05)
    if p.poll() is None and marker.exists():
        p.kill()
    _, err = p.communicate(timeout=30)
    assert not marker.exists(), err[-2000:]
    assert p.returncode == 0 and "installation ready" in err, err[-2000:]
