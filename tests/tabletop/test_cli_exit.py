"""The program's end while a background job (a take's training, a review sheet) runs native
code: waited for, bounded, and a Ctrl-C meanwhile is one line and status 130."""

import os
import signal
import subprocess
import sys

import pytest

from tests import children

# `tabletop --version` with a worker's job running OpenCV for about `seconds` when it ends
_VERSION_WITH_A_JOB = """
import sys, time
import cv2, numpy as np
import behaviors.worker as worker
from tabletop import cli
seconds, worker.FINISH_S = float(sys.argv[1]), float(sys.argv[2])
image = np.random.default_rng(0).random((1500, 1500), dtype=np.float32)
def job():
    print("began", flush=True)
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        cv2.GaussianBlur(image, (0, 0), 15)   # C++ that gives the GIL back while it runs
    print("job ended", flush=True)
    return 1
w = worker.Worker("exit-test")
w.start(job)
finish_jobs = worker.finish_jobs
def said_finish_jobs():
    print("ending", flush=True)   # the command has ended: its end waits for the job
    return finish_jobs()
worker.finish_jobs = said_finish_jobs
sys.argv = ["tabletop", "--version"]
cli.entry()
"""


def _start(seconds: float, finish_s: float) -> subprocess.Popen:
    return children.popen([sys.executable, "-c", _VERSION_WITH_A_JOB, str(seconds),
                           str(finish_s)], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                          text=True, env={**os.environ, "PYTHONUNBUFFERED": "1"})


def test_the_end_waits_for_a_running_job_and_gives_up_on_one_that_outlasts_its_wait():
    done = _start(0.5, 30.0)
    out, err = done.communicate(timeout=120)
    assert done.returncode == 0, err[-400:]
    assert "job ended" in out.splitlines() and "Traceback" not in err
    stuck = _start(60.0, 0.3)
    out, err = stuck.communicate(timeout=120)
    assert stuck.returncode == 0, err[-400:]
    assert "job ended" not in out
    assert err.strip().splitlines()[-1] == ("tabletop: a background job did not end in time; "
                                            "ending without it")


def test_a_stop_signal_while_the_end_waits_for_a_job_is_one_line_and_130():
    for stop in (signal.SIGINT, signal.SIGTERM):
        proc = _start(60.0, 60.0)
        assert proc.stdout.readline().strip() == "began"
        for line in proc.stdout:              # (the version comes first)
            if line.strip() == "ending":
                break
        proc.send_signal(stop)
        out, err = proc.communicate(timeout=120)
        assert proc.returncode == 130, (stop, err[-400:])
        assert "Traceback" not in err
        assert err.strip().splitlines()[-1] == "tabletop: interrupted", stop


# `tabletop --version`, then a SIGTERM (or SIGHUP) on the way out (from a log handler's close,
# which logging.shutdown runs: the moment a stop signal lands after a command's work is done
# and said)
_SIGNAL_AT_THE_END = """
import logging, os, signal, sys, time
from tabletop import cli
sig = getattr(signal, sys.argv[1])
class LateSignal(logging.Handler):
    def emit(self, record):
        pass
    def close(self):
        os.kill(os.getpid(), sig)
        time.sleep(1.0)
        super().close()
logging.getLogger("late").addHandler(LateSignal())
if len(sys.argv) > 2:   # the command's own status instead of --version's 0
    cli.main = lambda status=int(sys.argv[2]): status
sys.argv = ["tabletop", "--version"]
cli.entry()
"""


def _signal_at_the_end(sig: str, *status: str, ignored: bool = False):
    """The script above run to its end; ``ignored``: started with ``sig`` ignored, as
    ``nohup`` starts its command (SIGHUP) or a script its background job (SIGINT)."""
    start = (lambda: signal.signal(getattr(signal, sig), signal.SIG_IGN)) if ignored else None
    return children.run([sys.executable, "-c", _SIGNAL_AT_THE_END, sig, *status],
                        capture_output=True, text=True, timeout=120, preexec_fn=start)


@pytest.mark.parametrize("sig", ["SIGTERM", "SIGHUP", "SIGINT"])
def test_a_stop_signal_in_the_final_flush_ends_with_128_and_the_signal(sig):
    """The flush a signal cut short may have lost the end of the log: the status says the
    signal (143, 129, 130), not the command's own 0."""
    res = _signal_at_the_end(sig)
    assert res.returncode == 128 + getattr(signal, sig), (res.returncode, res.stderr)
    assert res.stdout.startswith("tabletop ") and res.stderr == ""


@pytest.mark.parametrize("status", [1, 2, 3])
def test_a_stop_signal_in_the_final_flush_keeps_the_commands_failure_status(status):
    """A failed command's status (3: the recording failed, which the kiosk's supervisor reads)
    outranks the log's tail a SIGTERM in the flush may have cut."""
    res = _signal_at_the_end("SIGTERM", str(status))
    assert res.returncode == status, (res.returncode, res.stderr)


@pytest.mark.parametrize("sig", ["SIGHUP", "SIGINT"])
def test_a_stop_signal_the_process_was_started_ignoring_stays_ignored_in_the_flush(sig):
    """``nohup tabletop ...`` (SIGHUP) and a script's background job (SIGINT): the signal
    ignored from the start does not end the flush, which ends with the command's 0."""
    res = _signal_at_the_end(sig, ignored=True)
    assert res.returncode == 0, (res.returncode, res.stderr)
    assert res.stdout.startswith("tabletop ") and res.stderr == ""


# `tabletop --version` in a process holding a non-daemon thread that never ends, or an atexit
# hook that never returns: the interpreter's finalisation waits for either for ever
_HUNG_FINALISATION = """
import atexit, sys, threading
from tabletop import cli
if sys.argv[1] == "thread":
    threading.Thread(target=threading.Event().wait).start()
else:
    atexit.register(threading.Event().wait)
sys.argv = ["tabletop", "--version"]
cli.entry()
"""


@pytest.mark.parametrize("hang", ["thread", "atexit"])
def test_the_end_never_waits_for_a_thread_or_exit_hook_that_hangs(hang):
    """The end skips the interpreter's finalisation: a process whose finalisation would hang
    ends with the command's status (with the stop signals ignored there, only SIGKILL ended
    it)."""
    proc = subprocess.Popen([sys.executable, "-c", _HUNG_FINALISATION, hang],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        out, err = proc.communicate(timeout=60)
    except subprocess.TimeoutExpired:
        proc.kill()
        out, err = proc.communicate()
    assert proc.returncode == 0, (proc.returncode, err[-400:])
    assert out.startswith("tabletop ")


# `tabletop status` whose work frees an object with a finaliser (a weakref callback or a
# __del__, as numba's typing runs many while a kiosk's installation builds) that a stop signal
# lands in: the KeyboardInterrupt raised there is one the interpreter swallows ("Exception
# ignored in ...") and the command worked on
_SIGNAL_IN_A_FINALISER = """
import os, signal, sys
from tabletop import cli
import tabletop.commands.status as status
sig = getattr(signal, sys.argv[1])
class Finaliser:
    def __del__(self):
        os.kill(os.getpid(), sig)
        for _ in range(100_000):   # the handler runs here, within the finaliser
            pass
def work(args):
    Finaliser()
    for _ in range(3_000_000):   # a command still working
        pass
    print("worked on", flush=True)
    return 0
status.main = work
sys.argv = ["tabletop", "status", "127.0.0.1:9"]
cli.entry()
"""


@pytest.mark.parametrize("sig", ["SIGTERM", "SIGINT"])
def test_a_stop_signal_landing_in_a_finaliser_still_stops_the_command(sig):
    res = children.run([sys.executable, "-c", _SIGNAL_IN_A_FINALISER, sig],
                       capture_output=True, text=True, timeout=120)
    assert res.returncode == 130, (res.returncode, res.stdout, res.stderr[-600:])
    assert "worked on" not in res.stdout
    assert res.stderr == "tabletop status: interrupted\n"
