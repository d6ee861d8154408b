"""The kiosk's last good configuration.

A config edit the kiosk refuses leaves the running configuration in charge
(:mod:`tabletop.kiosk.watch`), but only while that process runs: the next start (a crash, a
stall, a reboot) read the refused file and stopped at once, and the table stayed dark until
someone fixed it (measured: a refused ``rate_hz: sixty``, then a crash drill: "exit status 2"
at every restart, for ever). So every configuration the kiosk builds is kept beside the config
file as ``.NAME.last-good`` (same folder: its relative paths mean the same), and a kiosk start
whose config is refused runs that one instead, with the refusal in the log, the status's
``config_error`` and on the overlay; fixing the file on disk applies it as any edit.
"""

from __future__ import annotations

import logging
from pathlib import Path
from typing import Any

import yaml

from tabletop.files import atomic_write_text
from tabletop.errors import InputError
from tabletop.kiosk.paths import last_good_path as path_of

log = logging.getLogger("tabletop")


def remember(config_path: Path, cfg: Any) -> None:
    """Keep ``cfg`` (a loaded config: its ``raw`` mapping) as the last good one; a file that
    cannot be written (a full disk) is one warning, nothing else changes."""
    path = path_of(config_path)
    text = yaml.safe_dump(cfg.raw, sort_keys=False, allow_unicode=True)
    try:
        if path.is_file() and path.read_text(encoding="utf-8") == text:
            return
        atomic_write_text(path, text)
    except OSError as exc:
        log.warning("the last good configuration %s not kept: %s", path, exc.strerror or exc)


def load(config_path: Path, kiosk: bool) -> tuple[Any, str | None]:
    """(config, None) for a good ``config_path``; for a refused one, in a kiosk (``kiosk``, or
    the last good configuration has ``kiosk.enabled``) that has one: (the last good config,
    the refusal, for :func:`say`). Otherwise the refusal is raised as ever."""
    from tabletop.config import load_config
    try:
        return load_config(config_path), None
    except InputError as exc:
        try:    # a kiosk starts a character without the actions whose files it cannot read
            # (tabletop.plugins.mop.build): the refusal of such a file alone is not the config's
            cfg = load_config(config_path, start_without=True)
            if kiosk or cfg["kiosk"]["enabled"]:
                return cfg, None
        except InputError:
            pass
        if not Path(config_path).name:   # no file named at all: nothing was ever kept
            raise
        kept = path_of(config_path)
        if not kept.is_file():
            raise
        try:
            cfg = load_config(kept, start_without=True)
        except InputError:
            raise exc from None
        if not (kiosk or cfg["kiosk"]["enabled"]):
            raise
        return cfg, str(exc)


def say(config_path: Path, refusal: str) -> None:
    """Log that the kiosk runs the last good configuration because of ``refusal``: by the
    installation, once its kiosk log is open. Logged within :func:`load`, the line went to
    stderr only, twice (the supervisor's load, then the installation's), and never into
    ``logs/tabletop.log``, where a technician reads why the table runs an old configuration."""
    log.error("%s; the kiosk runs the last configuration that ran (%s) until the file is fixed",
              refusal, path_of(config_path))
