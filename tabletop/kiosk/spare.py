"""The kiosk supervisor's warm spare: a ``tabletop run`` process that prepares everything it
can before it is needed, then waits for ``go RESTARTS`` on its stdin.

Before the go, the spare imports the libraries, validates the config and builds the engines
(behaviours loaded and trained) and initialises pygame's display-independent modules. Nothing
that holds a device or a file is opened (camera, sockets, window, recording): the installation it
replaces may still hold them. After the go only the sources and sinks are built and the first
frame drawn. A config file changed on disk since the preparation, or a file it names (a
behaviour, a gesture template, a clip: what a recording carries), is loaded again: the engines
play the files the recording's header carries, as read at the go (a replay reads those); a
preparation that fails leaves the ordinary build to report the error after
the go.
"""

from __future__ import annotations

import logging
import os
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any

log = logging.getLogger("tabletop")

WAIT_GO = "TABLETOP_WAIT_GO"


@dataclass
class Prepared:
    """What a spare built before its go: the validated config, its build context, engines."""

    config_path: Path
    signature: tuple[int, int]        # config file (st_mtime_ns, st_size) when it was loaded
    cfg: Any
    context: Any
    engines: list
    files: tuple = ()                 # :func:`_files` of ``cfg`` before its engines were built

    def changed(self) -> str | None:
        """The config file, or the first file it names, changed since it was prepared (None:
        the preparation is current)."""
        if _signature(self.config_path) != self.signature:
            return str(self.config_path)
        now = _files(self.cfg)
        return next((str(ref.resolved) for ref, was, sig in zip(_refs(self.cfg), self.files, now)
                     if was != sig), None)

    def current(self) -> bool:
        """Are the config file and the files it names still the ones prepared?"""
        return self.changed() is None


def _signature(path: Path) -> tuple[int, int]:
    try:
        st = path.stat()
    except OSError:
        return (-1, -1)
    return (st.st_mtime_ns, st.st_size)


def _refs(cfg: Any) -> list:
    """The files and folders ``cfg`` names whose content a recording carries."""
    return [ref for ref in getattr(cfg, "refs", None) or () if ref.embed]


def _files(cfg: Any) -> tuple:
    """What each of :func:`_refs` is now (:func:`tabletop.kiosk.watch.file_signature`)."""
    from tabletop.kiosk.watch import file_signature
    return tuple(file_signature(ref.resolved) for ref in _refs(cfg))


def _import_all() -> None:
    import tabletop.app  # noqa: F401  (the heavy imports)
    import tabletop.kiosk.runner  # noqa: F401
    import tabletop.view  # noqa: F401
    from tabletop import registry
    for module in (*registry.SOURCES.values(), *registry.ENGINES.values()):
        registry.optional_module(module)


def prepare(config_path: Path) -> Prepared | None:
    """Validate the config and build its engines (None when that fails: the run after the go
    reports it as usual)."""
    from tabletop.app import _context, build_engines
    from tabletop.config import load_config
    config_path = Path(config_path)
    try:
        signature = _signature(config_path)
        cfg = load_config(config_path)
        files = _files(cfg)
        ctx = _context(cfg)
        engines = build_engines(cfg, ctx)
        import pygame
        pygame.font.init()
        return Prepared(config_path, signature, cfg, ctx, engines, files)
    except Exception as exc:  # noqa: BLE001  (a bad config: the ordinary build says what)
        log.debug("spare: not prepared: %s", exc)
        return None


def wait_for_go(config_path: Path) -> tuple[bool, Prepared | None, str | None]:
    """As a warm spare: prepare, then wait for ``go RESTARTS``. Returns (go, prepared,
    changed); go is False when the supervisor went away instead; ``changed`` names the file
    that changed since the preparation (which is then dropped, None), to be said once the
    kiosk's log is set up (:func:`say_changed`): before it, an INFO line goes nowhere."""
    _import_all()
    prepared = prepare(config_path)
    line = sys.stdin.readline().split()
    if len(line) != 2 or line[0] != "go":
        return False, None, None
    os.environ["TABLETOP_RESTARTS"] = line[1]
    os.environ.pop(WAIT_GO, None)
    changed = None if prepared is None else prepared.changed()
    return True, None if changed is not None else prepared, changed


def say_changed(changed: str | None, config_path: Path) -> None:
    """Log (the kiosk's log) that ``changed`` changed since the spare was prepared."""
    if changed is not None:
        log.info("spare: %s changed since it was prepared; loading %s again", changed,
                 config_path)


def is_spare() -> bool:
    """True in a spare started by the supervisor (waiting for its go)."""
    return os.environ.get(WAIT_GO) == "1"
