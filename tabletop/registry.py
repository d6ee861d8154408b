"""Names that config.yaml uses for sources, engines and sinks, mapped to their plugin modules.

A plugin module (``tabletop/plugins/NAME.py``) defines ``SCHEMA`` (a :class:`tabletop.schema.Record`
of its options, without ``kind`` and ``name``) and ``build(options, ctx)`` returning the object.
Modules are imported only when a config names them, so commands that draw nothing never import
pygame.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass, field
from pathlib import Path
from types import ModuleType
from typing import Any

SOURCES: dict[str, str] = {
    "scripted": "tabletop.plugins.scripted",
    "synthetic_camera": "tabletop.plugins.synthetic_camera",
    "camera": "tabletop.plugins.camera",
    "osc": "tabletop.plugins.osc",
    "serial": "tabletop.plugins.serial",
}

ENGINES: dict[str, str] = {
    "puppet_master": "tabletop.plugins.puppet_master",
    "mop": "tabletop.plugins.mop",
    "touch_pose": "tabletop.plugins.touch_pose",
    "fault": "tabletop.plugins.fault",
}

SINKS: dict[str, str] = {
    "tuio": "tabletop.plugins.tuio",
}

REGISTRIES: dict[str, dict[str, str]] = {"source": SOURCES, "engine": ENGINES, "sink": SINKS}


@dataclass
class BuildContext:
    """What a plugin's ``build`` may need besides its own options.

    ``table``: (width, height) in metres; ``rate_hz``: the loop rate; ``config``: the whole
    validated config; ``base``: the config file's folder; ``shared``: objects built once and
    shared between plugins (e.g. the puck tracker a camera source feeds predictions from).
    """

    table: tuple[float, float]
    rate_hz: float
    config: dict[str, Any]
    base: Path
    shared: dict[str, Any] = field(default_factory=dict)

    def engines(self, options: dict) -> tuple[list[dict], list, int]:
        """The config's engines, their names and the index of the engine of ``options``
        (len(names) if not there)."""
        engines = self.config.get("engines", []) if isinstance(self.config, dict) else []
        names = [e.get("name") for e in engines]
        name = options["name"]
        return engines, names, names.index(name) if name in names else len(names)

    def where(self, options: dict, key: str) -> str:
        """``FILE: engines[i].KEY`` of the engine of ``options``, as config errors name a key."""
        _, names, mine = self.engines(options)
        where = f"engines[{mine}].{key}" if mine < len(names) else key
        if getattr(self.config, "file", None):  # name the config file like every other key
            where = f"{self.config.file}: {where}"
        return where


def optional_module(target: str) -> ModuleType | None:
    """Import ``target``, or None when that module itself is not installed (an import error
    inside it still raises)."""
    try:
        return importlib.import_module(target)
    except ModuleNotFoundError as exc:
        if exc.name and target.startswith(exc.name):
            return None
        raise


def plugin_module(role: str, kind: str) -> ModuleType | None:
    """The plugin module for ``kind`` of ``role`` ("source", "engine", "sink"), or None if the
    name is unknown or its module is not present in this installation."""
    target = REGISTRIES[role].get(kind)
    return None if target is None else optional_module(target)


def available(role: str) -> list[str]:
    """The kinds of ``role`` whose plugin modules are installed, sorted."""
    return sorted(k for k in REGISTRIES[role] if plugin_module(role, k) is not None)
