"""Loading and validating config.yaml.

Strict at start-up: a YAML syntax error (with its line), an unknown key, a wrong type, an
out-of-range value or a missing referenced file fails at once with one message naming the file,
the key path and what would be right. Nothing starts half-configured.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from tabletop import registry
from tabletop.files import read_yaml
from tabletop.schema import (REQUIRED, Bool, ConfigError, Context, FilePath, ListOf, MapOf,
                             Number, Optional_, Record, Spec, Str)

TABLE = Record({
    "width": Number(1.2, lo=0.05, hi=20.0, doc="table length along x, metres"),
    "height": Number(0.8, lo=0.05, hi=20.0, doc="table width along y, metres"),
})

LOOP = Record({
    "rate_hz": Number(60.0, lo=1.0, hi=1000.0, doc="main loop rate, ticks per second"),
})

VIEW = Record({
    "enabled": Bool(True),
    "size": ListOf(Number(integer=True, lo=64, hi=8192), default=[1280, 720], min_len=2,
                   max_len=2, doc="projector resolution in pixels"),
    "fullscreen": Bool(False),
    "display": Number(0, integer=True, lo=0, hi=16, doc="display index for fullscreen"),
    "headless": Bool(False, doc="force the dummy video driver (no window)"),
    "overlay": Bool(False, doc="operator overlay shown at start (toggle with F1 or o)"),
    "calibration_check": Bool(False, doc="measure the calibration check every 10 s (crosses "
                                         "under the pucks) and show it on the overlay"),
    "snapshot_every_s": Number(0.0, lo=0.0, doc="headless: save a PNG every N seconds (0: never)"),
    "snapshot_folder": FilePath("snapshots", must_exist=False),
    "margin_px": Number(24, integer=True, lo=0, hi=1000,
                        doc="border around the table when no calibration maps it"),
    "puck_radius": Number(0.03, lo=0.005, hi=0.5, doc="drawn puck radius, metres"),
    "sprites": MapOf(FilePath(kind="file"), default={},
                     doc="character name -> PNG drawn instead of the vector shape (facing +x)"),
})

RECORDER = Record({
    "enabled": Bool(False),
    "folder": FilePath("sessions", must_exist=False, doc="where session .jsonl files go"),
    "path": Optional_(FilePath(must_exist=False), doc="exact session file (overrides folder)"),
})


class Component(Spec):
    """One entry of a component list: ``kind`` chooses the plugin, whose SCHEMA checks the rest."""

    def __init__(self, role: str) -> None:
        self.role, self.default, self.doc = role, REQUIRED, ""

    def describe(self) -> str:
        return f"a {self.role} mapping with 'kind' ({', '.join(sorted(registry.REGISTRIES[self.role]))})"

    def validate(self, value: Any, path: str, ctx: Context) -> Any:
        if not isinstance(value, dict):
            raise ctx.error(path, f"expected {self.describe()}, got {value!r}")
        kind = value.get("kind")
        if not isinstance(kind, str):
            raise ctx.error(f"{path}.kind", f"missing; expected {self.describe()}")
        module = registry.plugin_module(self.role, kind)
        if module is None:
            known = ", ".join(registry.available(self.role)) or "none installed"
            raise ctx.error(f"{path}.kind", f"unknown {self.role} kind {kind!r} (known: {known})")
        options = {k: v for k, v in value.items() if k not in ("kind", "name")}
        name = value.get("name", kind)
        if not isinstance(name, str) or not name:
            raise ctx.error(f"{path}.name", f"expected a non-empty string, got {name!r}")
        validated = module.SCHEMA.validate(options, path, ctx)
        return {"kind": kind, "name": name, **validated}


def _unique_names(key: str):
    def check(cfg: dict, path: str, ctx: Context) -> None:
        seen: set[str] = set()
        for i, item in enumerate(cfg[key]):
            if item["name"] in seen:
                raise ctx.error(f"{key}[{i}].name", f"duplicate name {item['name']!r}; "
                                "give each one its own 'name'")
            seen.add(item["name"])
    return check


def _check_all(cfg: dict, path: str, ctx: Context) -> None:
    for key in ("sources", "engines", "sinks"):
        _unique_names(key)(cfg, path, ctx)


def tracking_schema() -> Spec:
    """The puck tracker's options (owned by the tracking plugin when installed)."""
    tracking = registry.optional_module("tabletop.plugins.tracking")
    return tracking.SCHEMA if tracking is not None else Record({})


def top_schema() -> Record:
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
    }, check=_check_all)


def load_config(path: str | Path) -> dict[str, Any]:
    """Read and validate a config file; returns the config with every default filled in."""
    p = Path(path)
    data = read_yaml(p, ConfigError, missing="config file not found")
    return validate_config(data, str(p), p.resolve().parent)


def validate_config(data: Any, file: str = "<config>", base: Path | None = None) -> dict[str, Any]:
    """Validate an already parsed config mapping."""
    ctx = Context(file=file, base=base or Path.cwd())
    if data is None:
        raise ConfigError(f"{file}: the file is empty; expected a mapping with 'sources'")
    return top_schema().validate(data, "", ctx)
