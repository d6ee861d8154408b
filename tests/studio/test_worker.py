"""The worker that trains designers' takes off the frame loop."""

import gc
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
