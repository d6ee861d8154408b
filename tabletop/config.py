"""Loading and validating config.yaml.

Strict at start-up: a YAML syntax error (with its line), an unknown key, a wrong type, an
out-of-range value or a missing referenced file fails at once with one message naming the file,
the key path and what would be right, then every other mistake found with its key path
(:class:`~tabletop.schema.Mistakes`). Nothing starts half-configured.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from tabletop import registry
from tabletop.config_checks import (check_calibrations, check_marker_ids, check_named_pucks,
                                    check_reactor_mains, check_scripted_pucks, check_sprites,
                                    check_studio_markers)
from tabletop.config_ports import check_udp_ports
from tabletop.file_io import file_signature
from tabletop.files import read_yaml
from tabletop.schema import (REQUIRED, Bool, ConfigError, Context, FilePath, FileRef, ListOf,
                             MapOf, Number, Optional_, Record, Spec, shown)


class ImageFile(FilePath):
    """An image file pygame can read (PNG, JPEG...): checked when the config is loaded."""

    def __init__(self, doc: str = "") -> None:
        super().__init__(kind="file", doc=doc)

    def describe(self) -> str:
        return "a path to an image file (PNG)"

    def validate(self, value: Any, path: str, ctx: Context) -> Any:
        p = super().validate(value, path, ctx)
        import os
        os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
        import pygame
        from tabletop.quiet import quiet_stderr
        try:
            with quiet_stderr():  # libpng prints its own complaint
                pygame.image.load(str(p))
        except (pygame.error, OSError, ValueError) as exc:
            raise ctx.error(path, f"{value!r} is not an image pygame can read ({exc})") from None
        return p


TABLE = Record({
    "width": Number(1.2, unit="metres", lo=0.05, hi=20.0, doc="table length along x, metres"),
    "height": Number(0.8, unit="metres", lo=0.05, hi=20.0, doc="table width along y, metres"),
})

LOOP = Record({
    "rate_hz": Number(60.0, lo=1.0, hi=1000.0, doc="main loop rate, ticks per second"),
    "realtime_priority": Number(0, integer=True, lo=0, hi=50,
                                doc="1-50: while paced, the installation's threads run with "
                                    "this real-time (SCHED_FIFO) priority, so other programs "
                                    "on the machine do not delay its frames (needs root, "
                                    "CAP_SYS_NICE or systemd's LimitRTPRIO); 0: off"),
})

VIEW = Record({
    "enabled": Bool(True),
    "size": ListOf(Number(integer=True, unit="pixels",
                          lo=64, hi=8192), default=[1280, 720], min_len=2,
                   max_len=2, doc="projector resolution in pixels"),
    "fullscreen": Bool(False),
    "display": Number(0, integer=True, lo=0, hi=16, doc="display index for fullscreen"),
    "headless": Bool(False, doc="force the dummy video driver (no window)"),
    "overlay": Bool(False, doc="operator overlay shown at start (toggle with F1 or o)"),
    "calibration_check": Bool(False, doc="measure the calibration check every 10 s (crosses "
                                         "under the pucks) and show it on the overlay"),
    "snapshot_every_s": Number(0.0, lo=0.0, hi=86_400.0,
                               doc="save a PNG of the view every N seconds of wall-clock time, "
                                   "with or without a window (0: never)"),
    "snapshot_folder": FilePath("snapshots", must_exist=False),
    "snapshot_per_run": Bool(False, doc="each run in its own subfolder (else the numbering "
                                        "continues from the highest snapshot in the folder)"),
    "snapshot_keep": Number(2000, integer=True, lo=1, hi=10_000_000,
                            doc="snapshots kept in the folder (the oldest are removed)"),
    "snapshot_max_mb": Number(500.0, lo=1.0, hi=10_000_000.0,
                              doc="megabytes of snapshots kept in the folder"),
    "snapshot_overlay": Bool(True, doc="snapshots show the operator overlay (health at that "
                                       "moment) even when the screen does not"),
    "margin_px": Number(24, integer=True, lo=0, hi=1000,
                        doc="border around the table when no calibration maps it"),
    "puck_radius": Number(0.03, unit="metres", lo=0.005, hi=0.5, doc="drawn puck radius, metres"),
    "sprites": MapOf(ImageFile(), default={},
                     doc="character name -> PNG drawn instead of the vector shape (facing +x)"),
})

RECORDER = Record({
    "enabled": Bool(False),
    "folder": FilePath("sessions", must_exist=False, doc="where session .jsonl files go"),
    "path": Optional_(FilePath(must_exist=False),
                      doc="session file name (overrides folder); when it exists, the next free "
                          "name NAME-2.jsonl, NAME-3.jsonl... is used, never overwritten"),
    "max_mb": Number(200.0, lo=0.01, hi=1_000_000.0,
                     doc="a recording reaching this size continues in a new file"),
    "keep": Optional_(Number(integer=True, lo=1, hi=1_000_000),
                      default=100, doc="recording files kept in the folder, the oldest "
                                       "removed (null: all)"),
})


class Component(Spec):
    """One entry of a component list: ``kind`` chooses the plugin, whose SCHEMA checks the rest."""

    def __init__(self, role: str) -> None:
        self.role, self.default, self.doc = role, REQUIRED, ""

    def describe(self) -> str:
        kinds = ", ".join(sorted(registry.REGISTRIES[self.role]))
        return f"a {self.role} mapping with 'kind' ({kinds})"

    def validate(self, value: Any, path: str, ctx: Context) -> Any:
        if not isinstance(value, dict):
            raise self.wrong_type(value, path, ctx)
        kind = value.get("kind")
        if not isinstance(kind, str):
            raise ctx.error(f"{path}.kind", f"missing; expected {self.describe()}")
        module = registry.plugin_module(self.role, kind)
        if module is None:
            known = ", ".join(registry.available(self.role)) or "none installed"
            raise ctx.error(f"{path}.kind", f"unknown {self.role} kind {kind!r} (known: {known})")
        options = {k: v for k, v in value.items() if k not in ("kind", "name")}
        name = value.get("name", kind)
        since = len(ctx.errors)
        if not isinstance(name, str) or not name:
            ctx.note(ctx.error(f"{path}.name", f"expected a non-empty string, got {shown(name)}"))
        validated = ctx.attempt(module.SCHEMA, options, path)
        ctx.settle(since)
        return {"kind": kind, "name": name, **validated}


def _check_unique_names(cfg: dict, key: str, ctx: Context) -> None:
    """Refuse two items of ``cfg[key]`` (a list of named parts) with one name."""
    seen: set[str] = set()
    for i, item in enumerate(cfg[key]):
        if item["name"] in seen:
            raise ctx.error(f"{key}[{i}].name", f"duplicate name {item['name']!r}; "
                            "give each one its own 'name'")
        seen.add(item["name"])


def _check_all(cfg: dict, path: str, ctx: Context) -> None:
    for key in ("sources", "engines", "sinks"):
        _check_unique_names(cfg, key, ctx)
    check_calibrations(cfg, ctx)
    check_marker_ids(cfg, ctx)
    check_scripted_pucks(cfg, ctx)
    check_studio_markers(cfg, ctx)
    check_named_pucks(cfg, ctx)
    _check_on_table(cfg, ctx)
    check_udp_ports(cfg, ctx)
    check_sprites(cfg, ctx)
    check_reactor_mains(cfg, ctx)


def _check_on_table(cfg: dict, ctx: Context) -> None:
    """Places given in table metres (a performer's ``home``, an engine's or a MOP character's
    ``at``) lie on the table: one off it (``home: [1e300, 0.4]`` was accepted) put a puck the
    camera never sees or a character nobody can reach."""
    w, h = cfg["table"]["width"], cfg["table"]["height"]
    places = [(f"sources[{i}].performers[{j}].home", p.get("home"))
              for i, s in enumerate(cfg["sources"])
              for j, p in enumerate(s.get("performers") or [])]
    for i, e in enumerate(cfg["engines"]):
        places.append((f"engines[{i}].at", e.get("at")))
        places += [(f"engines[{i}].characters[{j}].at", c.get("at"))
                   for j, c in enumerate(e.get("characters") or []) if isinstance(c, dict)]
    for key, xy in places:
        if isinstance(xy, list) and not (0.0 <= xy[0] <= w and 0.0 <= xy[1] <= h):
            raise ctx.error(key, f"[{xy[0]:g}, {xy[1]:g}] is off the {w:g} x {h:g} m table "
                                 f"(x from 0 to {w:g}, y from 0 to {h:g} metres)")


def tracking_schema() -> Spec:
    """The puck tracker's options (owned by the tracking plugin when installed)."""
    tracking = registry.optional_module("tabletop.plugins.tracking")
    return tracking.SCHEMA if tracking is not None else Record({})


def top_schema() -> Record:
    from tabletop.kiosk.settings import SCHEMA as KIOSK
    from tabletop.studio import SCHEMA as STUDIO
    return Record({
        "table": TABLE,
        "loop": LOOP,
        "calibration": Optional_(FilePath(kind="file"), doc="calibration YAML file"),
        "tracking": tracking_schema(),
        "sources": ListOf(Component("source"), min_len=1),
        "engines": ListOf(Component("engine"), default=[]),
        "sinks": ListOf(Component("sink"), default=[]),
        "view": VIEW,
        "recorder": RECORDER,
        "kiosk": KIOSK,
        "studio": STUDIO,
    }, check=_check_all)


class Config(dict):
    """A validated config (every default filled in), remembering where it came from: ``raw``,
    the mapping as written; ``base``, the folder its relative paths are relative to; ``refs``,
    the files and folders it names (a recording embeds them, see :mod:`tabletop.bundle`);
    ``read``, the file's signature taken just before it was read
    (:func:`tabletop.file_io.file_signature`; None when validated from a mapping)."""

    def __init__(self, values: dict[str, Any], raw: Any, base: Path, file: str,
                 refs: list[FileRef], read: tuple | None = None) -> None:
        super().__init__(values)
        self.raw, self.base, self.file, self.refs = raw, base, file, refs
        self.read = read


MAX_CONFIG_BYTES = 2**20   # the largest shipped config (examples/mop.yaml) is 4.9 kB


def load_config(path: str | Path, start_without: bool = False) -> Config:
    """Read and validate a config file; returns the config with every default filled in.
    ``start_without``: the files of engines' actions are read by the build, not here
    (:class:`~tabletop.schema.Context`)."""
    p = Path(path)
    read = file_signature(p)     # (the config watcher's first look compares with it)
    data = read_yaml(p, ConfigError, missing="config file not found", max_bytes=MAX_CONFIG_BYTES,
                     kind="config")
    _no_library_file(data, p)
    cfg = validate_config(data, str(p), p.resolve().parent, start_without)
    cfg.read = read
    return cfg


def _no_library_file(data: Any, p: Path) -> None:
    """A library's file given as the config (a behaviour's behavior.yaml, a MOP character's
    actions.yaml) is said to be one, with where it goes, not "format: unknown key"."""
    from tabletop import library
    if not isinstance(data, dict):
        return
    if data.get("format") == library.FORMAT:
        raise ConfigError(f"{p}: a behaviour's {library.BEHAVIOR_FILE}, not a config; an "
                          f"engine plays its folder (behavior: {p.parent})")
    if "actions" in data and not data.keys() & {"sources", "engines"}:
        raise ConfigError(f"{p}: a MOP character's actions file (LIBRARY/CHARACTER/"
                          "actions.yaml of a mop engine's library: FOLDER), not a config")


def validate_config(data: Any, file: str = "<config>", base: Path | None = None,
                    start_without: bool = False) -> Config:
    """Validate an already parsed config mapping."""
    ctx = Context(file=file, base=base or Path.cwd(), start_without=start_without)
    if data is None:
        raise ConfigError(f"{file}: the file is empty; expected a mapping with 'sources'")
    return Config(top_schema().validate(data, "", ctx), data, ctx.base, file, ctx.refs)
