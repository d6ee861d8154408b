"""Files watched while running: ``config.yaml`` edits applied or refused, folders reloaded.

:class:`ConfigWatcher` is a frame-loop hook: about once a second it looks at the config file's
modification time and size; when they change it validates the new file (the run's watcher in
a worker thread, settled at a later tick: the tick stays free of it). A bad file is refused
with one line naming the file, key and reason (logged, in the status as ``config_error``, on
the overlay), and the running configuration stays. A good one that differs from the running
configuration is handed to ``apply`` (the run command rebuilds the installation with it).
An edit refused for a file it names (a corrupt gesture template: the error's ``files``) is
validated again once one of those files changes too, so fixing the file the refusal names
applies the edit.
"""

from __future__ import annotations

import logging
import time
from pathlib import Path
from typing import Any, Callable

from behaviors.worker import Worker
from tabletop.file_io import file_signature, tree_signature  # noqa: F401  (watched files)
from tabletop.frames import Frame, InputError

log = logging.getLogger("tabletop")


class Poller:
    """``changed()`` is True once after ``path``'s signature changes; looks at most every
    ``every_s`` seconds of ``clock``."""

    def __init__(self, path: Path, every_s: float = 1.0,
                 clock: Callable[[], float] = time.monotonic, since_start: bool = False,
                 read: tuple | None = None,
                 signature: Callable[[Path], tuple] = tree_signature,
                 settle: bool = False) -> None:
        """``since_start``: the first look counts as a change (what was read of ``path`` may be
        older than this poller). ``read``: the signature taken just before ``path`` was read
        (an engine's build, seconds before its studio or reloader exists): the first look
        compares with it, so an edit saved in between is seen. ``settle``: a change counts
        once the signature stayed the same for a whole look (a copy still being written)."""
        self.path, self.every_s, self.clock = Path(path), every_s, clock
        self.sign, self.settle = signature, settle
        self.signature: tuple | None = (None if since_start else read if read is not None
                                        else signature(self.path))
        self.seen = self.signature
        self._next = clock()

    def changed(self) -> bool:
        now = self.clock()
        if now < self._next:
            return False
        self._next = now + self.every_s
        sig = self.sign(self.path)
        steady, self.seen = sig == self.seen, sig
        if sig == self.signature or self.settle and not steady:
            return False
        self.signature = sig
        return True


class ConfigWatcher:
    """Frame-loop hook validating edits of ``path``; ``apply(config)`` receives a good one.

    The running configuration was read before the installation was built (seconds at a cold
    start, at a warm spare's go): an edit saved meanwhile must be applied or refused too (not
    status ``config_error: null``). ``read``, the file's :func:`file_signature` taken just
    before that read: the first look validates the file only if it differs. Without it the
    first look validates the file whatever its time (examples/mop.yaml: 20-30 ms of the loop's
    CPU in one tick at every start, to find the file unchanged; with it, 0.03 ms)."""

    def __init__(self, path: Path, current: dict[str, Any], load: Callable[[Path], dict],
                 apply: Callable[[dict[str, Any]], None], every_s: float = 1.0,
                 clock: Callable[[], float] = time.monotonic, read: tuple | None = None,
                 background: bool = False) -> None:
        self.path, self.current, self.load, self.apply = Path(path), current, load, apply
        self.named: tuple[Path, ...] = ()    # the files a refused edit names
        # ``background``: a changed file is validated in a worker thread and settled at the
        # first look after it is done (examples/mop.yaml: 20-33 ms of CPU, within the tick
        # the change was seen in)
        self.worker = Worker("config-watch") if background else None
        self._named: tuple[Path, ...] | None = None     # a validation in the worker: named
        self.poller = Poller(self.path, every_s, clock, since_start=read is None,
                             read=None if read is None else (read,), signature=self._signature)
        self.error: str | None = None
        self.refused = 0
        self.applied = 0

    def _signature(self, path: Path) -> tuple:
        return (file_signature(path), *map(file_signature, self.named))

    def _config_seen(self) -> tuple:
        """The config file's signature as the look that loaded it saw it (a save made while it
        was loaded is a change still to look at)."""
        seen = self.poller.signature
        return seen[:1] if seen else (file_signature(self.path),)

    def __call__(self, frame: Frame | None = None) -> None:
        if self.worker is not None and self._named is not None:
            done = self.worker.poll()
            if done is None:
                return
            named, self._named = self._named, None
            self._settle(done, named)
            return
        if not self.poller.changed():
            return
        named, self.named = self.named, ()
        if self.worker is not None:
            self._named = named
            self.worker.start(self._validate)
            return
        self._settle(self._validate(), named)

    def _validate(self) -> dict[str, Any] | InputError:
        try:
            return self.load(self.path)
        except InputError as exc:
            return exc

    def _settle(self, got: Any, named: tuple[Path, ...]) -> None:
        """Apply the validated config ``got``, or say its refusal (``named``: the files the
        refusal before it named)."""
        if isinstance(got, InputError):
            self._refuse(got, named)
            return
        if isinstance(got, BaseException):   # (a fault, not a refusal: raised as before)
            raise got
        cfg = got
        if named:
            self.poller.signature = self._config_seen()
        was_refused, self.error = self.error is not None, None
        if cfg == self.current:
            if was_refused:   # the refusal logged is over: the log said nothing (status did)
                log.info("config %s is valid again: it is the running configuration", self.path)
            return
        log.info("config %s changed: applying it", self.path)
        self.current = cfg
        self.applied += 1
        self.apply(cfg)

    def _refuse(self, exc: InputError, named: tuple[Path, ...]) -> None:
        self.named = tuple(getattr(exc, "files", ()))
        if self.named != named:     # what they are now: a change from here is looked at
            self.poller.signature = self._config_seen() + tuple(
                map(file_signature, self.named))
        if str(exc) == self.error:    # already said (a kiosk started on the last good one)
            return
        self.error = str(exc)
        self.refused += 1
        log.error("config edit refused, the running configuration stays: %s", exc)

    def wait(self) -> None:
        """Wait for a validation in the worker and settle it (tests; the loop never waits)."""
        if self.worker is not None and self._named is not None:
            self.worker.wait()
            self()

    def close(self) -> None:
        """End the worker's thread (the run is over)."""
        if self.worker is not None:
            self.worker.close()

    def status(self) -> dict[str, Any]:
        return {"config": str(self.path), "config_error": self.error}


