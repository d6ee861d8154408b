"""Training off the hot path: a behaviour and its reactor prepared in a worker thread.

Training a minute of demonstration takes tens of milliseconds (ten minutes: about 0.3 s), and
a reactor preallocates its search buffers; done inside a tick, either would stall the loop.
:class:`BackgroundTrainer` runs one job at a time in a daemon thread; the engine polls it once
a tick and swaps the new behaviour in between ticks. Only the reactor's start (placing it at
the main's pose, O(N n d)) stays in the tick, once.
"""

from __future__ import annotations

import threading
from typing import Any

import numpy as np

from behaviors.puppet_master.engine import Behavior, Reactor
from tabletop.frames import InputError


class BackgroundTrainer:
    """Trains one demonstration at a time in a worker thread."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._thread: threading.Thread | None = None
        self._done: tuple[Any, ...] | None = None
        self._job = 0

    @property
    def busy(self) -> bool:
        """True while a job runs."""
        t = self._thread
        return t is not None and t.is_alive()

    def start(self, demo: np.ndarray, params: dict[str, Any],
              table: tuple[float, float, float, float]) -> None:
        """Train ``demo`` with ``params`` and build a reactor for ``table``; a job still
        running is forgotten (its result is dropped)."""
        with self._lock:
            self._job += 1
            job = self._job
            self._done = None
        thread = threading.Thread(target=self._run, args=(job, demo, dict(params), table),
                                  name="puppet-master-training", daemon=True)
        self._thread = thread
        thread.start()

    def _run(self, job: int, demo: np.ndarray, params: dict[str, Any],
             table: tuple[float, float, float, float]) -> None:
        try:
            behavior = Behavior.train(demo, **params)
            result: tuple[Any, ...] = (behavior, Reactor(behavior, table), None)
        except InputError as exc:
            result = (None, None, exc)
        with self._lock:
            if job == self._job:
                self._done = result

    def cancel(self) -> None:
        """Forget the running job (its result is dropped) and any result not yet polled."""
        with self._lock:
            self._job += 1
            self._done = None

    def poll(self) -> tuple[Behavior | None, Reactor | None, InputError | None] | None:
        """The finished job's (behaviour, reactor, error) once, else None."""
        with self._lock:
            done, self._done = self._done, None
        return done  # type: ignore[return-value]

    def wait(self, timeout: float | None = None) -> None:
        """Block until the running job ends (tests, replays that must be exact)."""
        t = self._thread
        if t is not None:
            t.join(timeout)
