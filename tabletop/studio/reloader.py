"""Behaviour folders loaded and trained in a worker thread, swapped in between ticks.

Training a stored behaviour inside a tick stalled that tick 44-67 ms for an 80 s demonstration
(about 400 ms for 600 s). :class:`BehaviorReloader` (a Puppet Master engine outside the studio)
and the studio's library picks (:class:`~tabletop.studio.targets.PuppetMasterTarget`) hand the
folder to a :class:`~behaviors.worker.Worker`; the character plays on with the behaviour it has
and the new one (with its reactor, built in the worker) is played from a tick boundary.
"""

from __future__ import annotations

import logging
from pathlib import Path
from typing import Any

from behaviors.worker import Worker
from tabletop import library
from tabletop.frames import Frame, InputError
from tabletop.kiosk.watch import Poller

log = logging.getLogger("tabletop")


def stored_params(stored: library.StoredBehavior, rate_hz: float | None) -> dict[str, Any]:
    """The parameters a stored behaviour trains with: its own, at the engine's rate (Hz) where
    its config gives one."""
    params = dict(stored.parameters)
    if rate_hz is not None:
        params["rate_hz"] = rate_hz
    return params


def load_and_train(folder: Path, rate_hz: float | None,
                   table: tuple[float, float, float, float]) -> tuple[str, Any, Any]:
    """Read ``folder`` and train it: (stored name, behaviour, reactor on ``table``, metres).
    A bad or half-written folder raises InputError naming the file."""
    from behaviors.puppet_master.engine import Behavior, Reactor
    stored = library.load_behavior(folder)
    behavior = Behavior.train(stored.demonstration, **stored_params(stored, rate_hz))
    return stored.name, behavior, Reactor(behavior, table)


class BehaviorReloader:
    """Frame-loop hook for a Puppet Master engine outside the studio: its behaviour folder is
    reloaded when its files change, read and trained in a worker (``background``; else within
    the tick) while the behaviour in play goes on; the new one plays from the first tick after
    the worker is done. A bad file is logged once and shown in the character's label, and the
    behaviour that was playing goes on."""

    def __init__(self, engine, background: bool = True) -> None:
        self.engine = engine
        self.folder = Path(engine.folder)
        self.poller = Poller(self.folder, read=getattr(engine, "folder_read", None))
        self.problem: str | None = None
        self.worker = Worker("puppet-master-reload") if background else None
        self.loading = False          # a job is in the worker

    def __call__(self, frame: Frame | None = None) -> None:
        if self.loading and self.worker is not None:
            self._apply(self.worker.poll())
        if not self.poller.changed():
            return
        args = (self.folder, self.engine.rate_hz, self.engine.table)
        if self.worker is None:
            try:
                self._apply(load_and_train(*args))
            except InputError as exc:
                self._apply(exc)
            return
        self.loading = True           # a job still running is dropped for the newer files
        self.worker.start(load_and_train, *args)

    def wait(self) -> None:
        """Wait for the job in the worker and play its behaviour (tests; the loop never waits)."""
        if self.loading and self.worker is not None:
            self.worker.wait()
            self._apply(self.worker.poll())

    def _apply(self, done: tuple[str, Any, Any] | Exception | None) -> None:
        if done is None:
            return
        self.loading = False
        if isinstance(done, Exception):
            self.problem = str(done)
            self.engine.note = f"bad file, still playing the previous behaviour: {done}"
            log.error("behaviour not reloaded: %s", done)
            return
        name, behavior, reactor = done
        self.engine.play(behavior, name, reactor)
        self.problem = self.engine.note = ""
        log.info("behaviour %s reloaded", self.folder)
