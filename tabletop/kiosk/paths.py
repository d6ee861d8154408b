"""The kiosk's own files, named by its config: the status file, the log and the crash log
(defaults beside the config file), the last good copy of the config, and the log's setup. The
supervisor, the supervised installation and the config's checks all name them from here."""

from __future__ import annotations

from pathlib import Path
from typing import Any


def last_good_path(config_path: Path) -> Path:
    """Where the last good configuration of ``config_path`` is kept
    (:mod:`tabletop.kiosk.last_good`)."""
    config_path = Path(config_path)
    return config_path.with_name(f".{config_path.name}.last-good")


def kiosk_paths(cfg: dict[str, Any], base: Path) -> dict[str, Path]:
    """The kiosk's status file, log and crash log, defaults beside the config file."""
    k = cfg["kiosk"]
    return {"status_file": Path(k["status_file"] or base / "status.json"),
            "log_file": Path(k["log_file"] or base / "logs" / "tabletop.log"),
            "crash_log": Path(k["crash_log"] or base / "logs" / "crashes.log")}


def kiosk_log(cfg: dict[str, Any], path: Path) -> None:
    """The kiosk's rotating log at ``path``; a place it cannot be made stops the start in one
    line naming the config file and ``kiosk.log_file``."""
    from tabletop.kiosk.health import setup_log_file
    from tabletop.schema import ConfigError
    k = cfg["kiosk"]
    try:
        setup_log_file(path, k["log_max_bytes"], k["log_backups"])
    except OSError as exc:
        raise ConfigError(f"{getattr(cfg, 'file', 'config')}: kiosk.log_file: {path}: cannot "
                          f"be used: {exc.strerror or exc}") from None
