"""The worker that trains designers' takes off the frame loop."""

import gc
import subprocess
import sys
import threading
import time

from behaviors.worker import SWITCH_S, Worker


def test_results_once_cancel_drops_a_job_failures_are_results_and_the_thread_ends():
    name = "test-worker-ends"
    w = Worker(name)

    def alive():
        return any(t.name == name for t in threading.enumerate())
    switch = sys.getswitchinterval()
    seen = []
    w.start(lambda: seen.append(sys.getswitchinterval()) or 42)
    w.wait(10.0)
    assert not w.busy and w.poll() == 42 and w.poll() is None
    assert seen == [min(switch, SWITCH_S)] and sys.getswitchinterval() == switch
    w.start(time.sleep, 0.1)
    w.cancel()                      # forgotten: its result (None here) never comes back
    w.start(lambda: "second")
    w.wait(10.0)
    assert w.poll() == "second"
    assert alive()
    del w
    gc.collect()
    for _ in range(100):
        if not alive():
            break
        time.sleep(0.01)
    assert not alive()


def test_a_failing_job_is_its_result_and_the_worker_goes_on():
    w = Worker("test-worker")
    w.start(lambda: 1 / 0)
    w.wait(10.0)
    assert isinstance(w.poll(), ZeroDivisionError)
    w.start(lambda: "after")
    w.wait(10.0)
    assert w.poll() == "after"


def test_a_refused_take_is_a_result_without_a_traceback_a_failure_is_logged(caplog):
    """A touch-pose take whose part hardly moved logged "ERROR poser-training: job failed"
    and a traceback, though the studio tells the designer (seen in an Xvfb walk)."""
    from behaviors.touch_pose.designed import DesignedActionError

    def refused():
        raise DesignedActionError("the head hardly moves (0.00 m)")

    def broken():
        raise ZeroDivisionError("a bug")
    w = Worker("test-worker-refusal")
    w.start(refused)
    w.wait(10.0)
    assert isinstance(w.poll(), DesignedActionError)
    assert not [r for r in caplog.records if r.levelname == "ERROR"]   # one before
    w.start(broken)
    w.wait(10.0)
    assert isinstance(w.poll(), ZeroDivisionError)
    assert [r.exc_info is not None for r in caplog.records if r.levelname == "ERROR"] == [True]


_EXIT_DURING_A_JOB = """
import sys, threading
import cv2, numpy as np
began = threading.Event()
image = np.random.default_rng(0).random((2000, 2000), dtype=np.float32)
def job():
    began.set()
    cv2.GaussianBlur(image, (0, 0), 25)   # C++ that gives the GIL back while it runs
    print("job ended", flush=True)
    return 1
if sys.argv[1] == "worker":
    from behaviors.worker import Worker
    worker = Worker("exit-test")
    worker.start(job)
else:
    from tabletop.studio.session import draw_later
    draw_later(job)
began.wait()
"""


def test_a_process_ending_while_a_job_runs_native_code_ends_cleanly_after_the_job():
    """The main thread ends while a worker's job and a review-sheet job are inside OpenCV:
    the process waits for the job and exits 0 (as daemons, the drawing one aborted with exit
    134 and the worker's job was cut off unfinished)."""
    for kind in ("worker", "draw"):
        out = subprocess.run([sys.executable, "-c", _EXIT_DURING_A_JOB, kind],
                             capture_output=True, text=True, timeout=120)
        assert out.returncode == 0, (kind, out.returncode, out.stderr[-300:])
        assert out.stdout.splitlines() == ["job ended"], kind


def test_a_closed_worker_runs_a_job_started_after_it_at_once_and_waits_for_nothing():
    w = Worker("test-worker-closed")
    w.start(time.sleep, 0.05)
    assert w.close(10.0)            # the job queued before closing ran, then the thread ended
    assert not w.busy
    caller = []
    w.start(lambda: caller.append(threading.current_thread()) or "inline")
    assert caller == [threading.current_thread()]     # run here, before start returned
    assert not w.busy and w.poll() == "inline" and w.poll() is None
    w.wait()                        # no timeout: returns, nothing is left to run
    w.start(lambda: 1 / 0)
    assert isinstance(w.poll(), ZeroDivisionError)
