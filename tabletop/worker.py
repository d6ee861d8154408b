"""One job at a time in a daemon thread, its result picked up between ticks.

The frame loop never waits for a job: :meth:`Worker.poll` returns the finished job's result
once (else None; an exception the job raised is returned as its result); starting a new job, or :meth:`Worker.cancel`, drops the result of the job
still running. Used to train designers' takes off the hot path.
"""

from __future__ import annotations

import logging
import threading
from typing import Any, Callable

log = logging.getLogger("tabletop")


class Worker:
    """Runs ``fn(*args)`` in a daemon thread named ``name``; see the module docstring."""

    def __init__(self, name: str = "tabletop-worker") -> None:
        self.name = name
        self._lock = threading.Lock()
        self._thread: threading.Thread | None = None
        self._done: Any = None
        self._job = 0

    @property
    def busy(self) -> bool:
        """True while a job runs."""
        t = self._thread
        return t is not None and t.is_alive()

    def start(self, fn: Callable[..., Any], *args: Any) -> None:
        """Run ``fn(*args)``; a job still running is forgotten (its result is dropped). The
        result must not be None (None means "not finished" to :meth:`poll`)."""
        with self._lock:
            self._job += 1
            job = self._job
            self._done = None
        thread = threading.Thread(target=self._run, args=(job, fn, args), name=self.name,
                                  daemon=True)
        self._thread = thread
        thread.start()

    def _run(self, job: int, fn: Callable[..., Any], args: tuple) -> None:
        try:
            result = fn(*args)
        except Exception as exc:     # the job's failure is its result; the loop goes on
            log.exception("%s: job failed", self.name)
            result = exc
        with self._lock:
            if job == self._job:
                self._done = result

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
        """Block until the running job ends (tests, replays that must be exact)."""
        t = self._thread
        if t is not None:
            t.join(timeout)
