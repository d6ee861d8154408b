"""The ``kiosk:`` section of config.yaml (:data:`SCHEMA`) and the checks of the kiosk's own
files made at a kiosk's start (:func:`check_files`)."""

from __future__ import annotations

from typing import Any

from tabletop.plugins import scripted
from tabletop.plugins.osc import HostName, port_spec
from tabletop.schema import Bool, Context, FilePath, ListOf, Number, Optional_, Record, Str


def service_key_code(name: str) -> int | None:
    """pygame's key code of a key name (``F12``, ``o``, ``f12``...), None when pygame has no
    such key (an empty name: no service key)."""
    if not name:
        return None
    import os
    os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
    import pygame
    return next((getattr(pygame, f"K_{n}") for n in (name, name.upper(), name.lower())
                 if hasattr(pygame, f"K_{n}")), None)


def _check(k: dict[str, Any], path: str, ctx: Context) -> None:
    """What the fields cannot say alone: a back-off that grows, a key the keyboard has, a
    status file and crash log that are not folders and whose folders are not files (either
    would never be written, the table's monitors seeing nothing for weeks; a folder that
    cannot be made yet, a disk still mounting, is retried while running)."""
    from pathlib import Path

    from tabletop.files import file_on_path
    for key in ("status_file", "crash_log"):
        if k[key] is None:
            continue
        if Path(k[key]).is_dir():
            raise ctx.error(f"{path}.{key}", f"{k[key]} is a folder; expected a file name")
        # a folder that is a file never becomes one: refused here, not warned every heartbeat
        blocking = file_on_path(Path(k[key]).parent)
        if blocking is not None:
            raise ctx.error(f"{path}.{key}", f"{k[key]} cannot be written: {blocking} is a "
                                             "file, not a folder")
    if k["enabled"] or any(k[key] is not None for key in ("status_file", "log_file", "crash_log")):
        _check_distinct(k, path, ctx)   # (a config named status.json runs outside a kiosk)
        _check_own_logs(k, path, ctx)
    if k["status_file"] is not None and _not_a_status(Path(k["status_file"])):
        raise ctx.error(f"{path}.status_file", f"{k['status_file']} holds something else than "
                        "a kiosk status (a JSON object); the status written there every second "
                        "would replace it: name another file")
    first, longest = k["backoff_s"]
    if first > longest:
        raise ctx.error(f"{path}.backoff_s", f"the first wait {first:g} s is longer than the "
                                             f"longest {longest:g} s; give [first, longest]")
    if k["service_key"] not in ("", "F12") and service_key_code(k["service_key"]) is None:
        raise ctx.error(f"{path}.service_key", f"{k['service_key']!r} is not a key name; "
                                               "expected a pygame key name such as F12 or o")


def _not_a_status(file: Any) -> bool:
    """Does ``file`` hold something a status written over it would destroy (another config,
    notes, a calibration)? A status is a JSON object; a file that is empty, missing or
    unreadable (said where the status is written) or all NUL bytes (a disk's damage) is not
    kept from the kiosk."""
    try:
        if not file.is_file():   # (a pipe or device: opening a pipe waits for a writer)
            return False
        with open(file, "rb") as f:
            head = f.read(256).lstrip(b"\x00 \t\r\n")
    except OSError:
        return False
    return bool(head) and not head.startswith(b"{")


def check_files(cfg: Any) -> None:
    """:func:`_check_distinct` for a config run as a kiosk (``run --kiosk``) whose
    ``kiosk.enabled`` is off, which its validation left unchecked; ConfigError when two of
    its files are one."""
    from pathlib import Path

    from tabletop.schema import Context
    ctx = Context(str(cfg.file), Path(cfg.base))
    _check_distinct(cfg["kiosk"], "kiosk", ctx)
    _check_own_logs(cfg["kiosk"], "kiosk", ctx)


def _check_own_logs(k: dict[str, Any], path: str, ctx: Context) -> None:
    """The log and crash log name no file of someone else's (:func:`foreign_log`): the kiosk
    would append to it, then rotate it away. Refused at the start, naming key and file; a log
    the kiosk wrote itself (a restart, an earlier run) is its own."""
    from tabletop.kiosk.paths import foreign_log, kiosk_paths
    files = kiosk_paths({"kiosk": k}, ctx.base)
    for key in ("log_file", "crash_log"):
        found = foreign_log(key, files[key], k["log_backups"])
        if found is None:
            continue
        file, backup, first = found
        what = "the log" if key == "log_file" else "the crash log"
        where = (f"{file}" if not backup else
                 f"{file}, where {what}'s backup {backup} goes,")
        fate = ("its lines would be appended there and the file rotated away" if not backup
                else "a rotation would replace it")
        raise ctx.error(f"{path}.{key}", f"{where} holds something else than a log of the "
                        f"kiosk (it begins {first!r}); {fate}: name another file")


def _check_distinct(k: dict[str, Any], path: str, ctx: Context) -> None:
    """The status file, log and crash log are three files, none of them the config file: a
    status written atomically over ``config.yaml`` would replace the config with the status
    JSON (the next edit check refuses it, the designer's file is gone); a log appended to it
    or to the status file would mix them."""
    from pathlib import Path

    from tabletop.kiosk.paths import kiosk_paths, last_good_path
    taken: dict[Path, str] = {}
    config = Path(ctx.file)
    if config.is_file():
        name = config.name
        if name.startswith(".") and name.endswith(".last-good"):   # run for the file it keeps
            config = config.with_name(name[1:-len(".last-good")])
        taken[config.resolve()] = "the config file itself"
        taken[last_good_path(config).resolve()] = "the config's last good copy"
    for key, file in kiosk_paths({"kiosk": k}, ctx.base).items():
        where = file.resolve()
        if where in taken:
            raise ctx.error(f"{path}.{key}", f"{file} is {taken[where]}; give each kiosk file "
                                             "its own name")
        taken[where] = f"also {path}.{key}"


SCHEMA = Record({
    "enabled": Bool(False, doc="run as a gallery kiosk (same as run --kiosk)"),
    "name": Str("", doc="installation name in the status and heartbeat (default: host name)"),
    "idle_s": Number(60.0, lo=1.0, hi=3600.0, unit="seconds",
                     doc="attract mode after this long with no visitor, seconds"),
    "handover_s": Number(1.0, lo=0.0, hi=30.0,
                         doc="seconds over which attract pucks glide to a visitor's pucks"),
    "attract": Record(dict(scripted.SCHEMA.fields), check=scripted.check_pucks,
                      doc="the scripted visitor of attract mode (pucks, seed, performers)"),
    "grace_s": Number(1.0, lo=0.0, hi=60.0,
                      doc="an input down this long shows the 'one moment' screen, seconds"),
    "stall_s": Number(5.0, lo=0.5, hi=600.0,
                      doc="supervisor: no frame for this long restarts the loop, seconds"),
    "backoff_s": ListOf(Number(lo=0.0, hi=3600.0), default=[0.1, 30.0], min_len=2, max_len=2,
                        doc="supervisor: first and longest wait before a restart (none after "
                            "a first failure), seconds"),
    "spares": Number(2, integer=True, lo=0, hi=4,
                     doc="supervisor: warm spare processes kept prepared for a restart"),
    "watch_config": Bool(True, doc="apply edits of the config file made while running"),
    "service_key": Str("F12", doc="key (pygame name) that shows the overlay in kiosk mode"),
    "heartbeat": Record({
        "enabled": Bool(True),
        "host": HostName("127.0.0.1", doc="where heartbeats go (a broadcast address works "
                                          "too)"),
        "port": port_spec(9000, "heartbeat UDP port", lo=1),
        "every_s": Number(1.0, lo=0.05, hi=3600.0),
    }),
    "status_file": Optional_(FilePath(must_exist=False),
                             doc="status JSON file (default: status.json beside the config)"),
    "log_file": Optional_(FilePath(must_exist=False),
                          doc="rotating log (default: logs/tabletop.log beside the config)"),
    "log_max_bytes": Number(1_000_000, integer=True, lo=10_000),
    "log_backups": Number(5, integer=True, lo=1, hi=100),
    "crash_log": Optional_(FilePath(must_exist=False),
                           doc="supervisor's crash log (default: logs/crashes.log)"),
}, check=_check)
