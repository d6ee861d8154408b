"""One job at a time in a thread of its own, its result picked up between ticks.

The frame loop never waits for a job: :meth:`Worker.poll` returns the finished job's result
once (else None; an exception the job raised is returned as its result); starting a new job,
or :meth:`Worker.cancel`, drops the result of the job still running.

Two things keep a job from stalling the ticks meanwhile (measured in ``bench/studio.py``): the
thread is started once, when the worker is made (starting one per job cost the loop up to a
switch interval), and while a job runs the interpreter's GIL switch interval is shortened from
5 ms to :data:`SWITCH_S`, so the frame loop gets the GIL back within that when a job runs
Python code.

The job threads (the workers', the studio's review-sheet drawing) are not daemons: a daemon
thread still inside native code when the interpreter finalises (OpenCV's, matplotlib's: C++
that gives the GIL back in a destructor) is unwound from under it and the process aborts
("terminate called without an active exception", exit 134: as daemons, a quit a moment after
the studio started aborted one time in four). Such a thread ends itself once the main thread has
ended, after the jobs queued for it (:func:`next_job`); the command line's entry waits for them,
bounded, with its stop signals still caught (:func:`finish_jobs`).
"""

from __future__ import annotations

import logging
import queue
import sys
import threading
import time
import weakref
from typing import Any, Callable

from tabletop.frames import InputError

log = logging.getLogger("tabletop")

SWITCH_S = 0.0005        # GIL switch interval while a job runs (s)
EXIT_POLL_S = 0.25       # how often an idle job thread looks whether the main thread has ended (s)

FINISH_S = 5.0           # how long the process's end waits for the job threads (s); a kiosk's
                         # supervisor kills an installation that takes 10 s to stop
_switch_lock = threading.Lock()
_job_threads: weakref.WeakSet[threading.Thread] = weakref.WeakSet()
_ending = threading.Event()    # set by finish_jobs: jobs that look at it (warm-ups) skip
_running = 0             # jobs running in every worker
_saved_switch = 0.005


def _job_begins() -> None:
    global _running, _saved_switch
    with _switch_lock:
        if _running == 0:
            _saved_switch = sys.getswitchinterval()
            sys.setswitchinterval(min(_saved_switch, SWITCH_S))
        _running += 1


def _job_ends() -> None:
    global _running
    with _switch_lock:
        _running -= 1
        if _running == 0:
            sys.setswitchinterval(_saved_switch)


def job_thread(target: Callable[..., None], args: tuple = (),
               name: str = "job") -> threading.Thread:
    """A started job thread (not a daemon; see the module docstring) running ``target(*args)``."""
    th = threading.Thread(target=target, args=args, name=name, daemon=False)
    _job_threads.add(th)
    th.start()
    return th


def next_job(jobs: queue.SimpleQueue) -> Any:
    """The next item queued for a job thread, or None once nothing is queued and the process is
    ending (:func:`finish_jobs` called, or the main thread ended): the thread then returns."""
    main = threading.main_thread()
    while True:
        try:
            return jobs.get(timeout=0.0 if _ending.is_set() else EXIT_POLL_S)
        except queue.Empty:
            if _ending.is_set() or not main.is_alive():
                return None


def ending() -> bool:
    """True once the process is ending (a job that only prepares, a warm-up, may skip)."""
    return _ending.is_set()


def finish_jobs() -> bool:
    """At the process's end: every job thread runs what is queued for it and returns; waits up
    to :data:`FINISH_S` in all and says whether they all ended. Only for the process's end:
    job threads started before it do not serve afterwards."""
    _ending.set()
    deadline = time.monotonic() + FINISH_S
    for th in list(_job_threads):
        th.join(max(0.0, deadline - time.monotonic()))
    return not any(th.is_alive() for th in list(_job_threads))


class Worker:
    """Runs ``fn(*args)`` in its thread named ``name``; see the module docstring."""

    def __init__(self, name: str = "tabletop-worker") -> None:
        self.name = name
        self._lock = threading.Lock()
        self._jobs: queue.SimpleQueue = queue.SimpleQueue()
        self._idle = threading.Event()
        self._idle.set()
        self._done: Any = None
        self._job = 0
        self._queued = 0         # jobs started and not yet run by the thread
        self._closed = False
        # the thread holds the worker weakly: a worker no longer used ends its thread
        self._thread = job_thread(_serve, (self._jobs, weakref.ref(self)), name)

    def __del__(self) -> None:
        self._jobs.put(None)

    def close(self, timeout: float = FINISH_S) -> bool:
        """End the thread once the jobs queued for it have run (their results are dropped
        unless polled); waits up to ``timeout`` seconds and says whether it ended. The owner
        closes its worker as the installation closes, so no thread of it outlives the run. A job
        started after this runs at once in the caller's thread (nothing else would run it)."""
        with self._lock:
            self._closed = True
        self._jobs.put(None)
        self._thread.join(timeout)
        return not self._thread.is_alive()

    @property
    def busy(self) -> bool:
        """True while a job runs (or waits to) in the worker's thread."""
        return not self._idle.is_set() and self._thread.is_alive()

    def start(self, fn: Callable[..., Any], *args: Any) -> None:
        """Run ``fn(*args)``; a job still running is forgotten (its result is dropped). The
        result must not be None (None means "not finished" to :meth:`poll`). Once the worker is
        closed the job runs here, before this returns, its result polled as any other."""
        with self._lock:
            self._job += 1
            self._done = None
            if not self._closed:
                self._queued += 1
                self._idle.clear()
                self._jobs.put((self._job, fn, args))
                return
            job = self._job
        self._run(job, fn, args, queued=False)

    def _run(self, job: int, fn: Callable[..., Any], args: tuple, queued: bool = True) -> None:
        _job_begins()
        try:
            result = fn(*args)
        except InputError as exc:    # the take refused (too still, too short): the caller
            result = exc             # says so to the designer; no traceback in the log
        except Exception as exc:     # the job's failure is its result; the loop goes on
            log.exception("%s: job failed", self.name)
            result = exc
        finally:
            _job_ends()
        with self._lock:
            if job == self._job:
                self._done = result
            if queued:
                self._queued -= 1
                if self._queued == 0:
                    self._idle.set()

    def cancel(self) -> None:
        """Forget the running job (its result is dropped) and any result not yet polled."""
        with self._lock:
            self._job += 1
            self._done = None

    def poll(self) -> Any:
        """The finished job's result once, else None."""
        with self._lock:
            done, self._done = self._done, None
        return done

    def wait(self, timeout: float | None = None) -> None:
        """Block until the jobs started so far have ended, or the worker's thread has (tests,
        replays that must be exact); at most ``timeout`` seconds (None: no limit)."""
        end = None if timeout is None else time.monotonic() + timeout
        while self._thread.is_alive():
            left = EXIT_POLL_S if end is None else min(EXIT_POLL_S, end - time.monotonic())
            if self._idle.wait(max(0.0, left)) or (end is not None and time.monotonic() >= end):
                return


def close_workers(*workers: Worker | None, deadline: float | None = None) -> bool:
    """Close each worker given (None: none), as its owner closes with the installation,
    waiting for them until ``deadline`` (time.monotonic(), s; None: :data:`FINISH_S` each);
    says whether they all ended. A worker not ended by then ends itself after its jobs."""
    ended = True
    for worker in workers:
        if worker is not None:
            left = FINISH_S if deadline is None else max(0.0, deadline - time.monotonic())
            ended = worker.close(left) and ended
    return ended


def _serve(jobs: queue.SimpleQueue, ref: weakref.ref) -> None:
    """A worker's thread: runs its jobs until the worker is gone."""
    while True:
        item = next_job(jobs)
        worker = ref()
        if item is None or worker is None:
            return
        worker._run(*item)
        del worker, item
