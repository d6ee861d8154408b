"""The kiosk's own files, named by its config: the status file, the log and the crash log
(defaults beside the config file), the last good copy of the config, and the log's setup. The
supervisor, the supervised installation and the config's checks all name them from here."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

# The first line of a log the kiosk wrote: its log's (health.setup_log_file's format: time,
# pid, level) and its crash log's (crash_log.crash_entry's header). Every file of either begins
# with one: a rotation starts the next file with the next record.
OWN_FIRST_LINE = {
    "log_file": re.compile(rb"\d{4}-\d\d-\d\d \d\d:\d\d:\d\d,\d{3} \d+ [A-Z]+ "),
    "crash_log": re.compile(rb"=== \d{4}-\d\d-\d\dT\S+ crash \d+: "),
}


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


def foreign_log(key: str, path: Path, backups: int) -> tuple[Path, int, str] | None:
    """The first of the log ``path`` (``key``: ``log_file`` or ``crash_log``) and the backups
    its rotation writes (``path.1`` ... ``path.N``) that holds something else than a log the
    kiosk wrote, as (file, backup number or 0, its first line); None when there is none. The
    log is appended to and rotated away after ``backups`` rotations, a backup replaced by the
    next: a file of the technician's named there (notes, another program's log) would be lost.
    A missing, empty or all-NUL file (a disk's damage) is the kiosk's; a pipe or device is
    never opened (opening a pipe waits for a writer) and never rotated."""
    own = OWN_FIRST_LINE[key]
    for i in range(backups + 1):
        file = path if i == 0 else path.with_name(f"{path.name}.{i}")
        try:
            if not file.is_file():
                continue
            with open(file, "rb") as f:
                head = f.read(200).lstrip(b"\x00 \t\r\n")
        except OSError:   # (said where the log is written)
            continue
        if head and not own.match(head):
            first = head.split(b"\n", 1)[0][:60].decode("utf-8", "replace")
            return file, i, first
    return None
