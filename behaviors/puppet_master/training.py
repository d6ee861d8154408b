"""Training off the hot path: a behaviour and its reactor prepared in a worker thread.

Training a minute of demonstration takes tens of milliseconds (ten minutes: about 0.3 s), and
a reactor preallocates its search buffers; done inside a tick, either would stall the loop.
:class:`BackgroundTrainer` runs one job at a time in a daemon thread (:class:`behaviors.worker.
Worker`); the studio polls it once a tick and swaps the new behaviour in between ticks. Only the
reactor's start (placing it at the main's pose, O(N n d)) stays in the tick, once.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from behaviors.puppet_master.engine import Behavior, Reactor
from tabletop.frames import InputError
from behaviors.worker import Worker


def _train(demo: np.ndarray, params: dict[str, Any],
           table: tuple[float, float, float, float]) -> tuple[Any, ...]:
    try:
        behavior = Behavior.train(demo, **params)
        return behavior, Reactor(behavior, table), None
    except InputError as exc:
        return None, None, exc


class BackgroundTrainer(Worker):
    """Trains one demonstration at a time in a worker thread."""

    def __init__(self) -> None:
        super().__init__("puppet-master-training")

    def start(self, demo: np.ndarray, params: dict[str, Any],  # type: ignore[override]
              table: tuple[float, float, float, float]) -> None:
        """Train ``demo`` with ``params`` and build a reactor for ``table``; a job still
        running is forgotten (its result is dropped)."""
        super().start(_train, demo, dict(params), table)

    def poll(self) -> tuple[Behavior | None, Reactor | None, InputError | None] | None:
        """The finished job's (behaviour, reactor, error) once, else None."""
        return super().poll()
