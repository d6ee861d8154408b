"""Loading and validating config.yaml.

Strict at start-up: a YAML syntax error (with its line), an unknown key, a wrong type, an
out-of-range value or a missing referenced file fails at once with one message naming the file,
the key path and what would be right. Nothing starts half-configured.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from tabletop import registry
from tabletop.config_ports import check_udp_ports
from tabletop.files import read_yaml
from tabletop.frames import InputError
from tabletop.schema import (REQUIRED, Bool, ConfigError, Context, FilePath, FileRef, ListOf,
                             MapOf, Number, Optional_, Record, Spec, Str)

# Sources that draw markers from the configured ids (so every id must be in the dictionary).
MARKER_SOURCES = ("synthetic_camera",)
# Sources whose pucks are printed markers read by the tracker (a marker id is a puck id).
CAMERA_SOURCES = ("camera", "synthetic_camera")

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
    "width": Number(1.2, lo=0.05, hi=20.0, doc="table length along x, metres"),
    "height": Number(0.8, lo=0.05, hi=20.0, doc="table width along y, metres"),
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
    "size": ListOf(Number(integer=True, lo=64, hi=8192), default=[1280, 720], min_len=2,
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
    "puck_radius": Number(0.03, lo=0.005, hi=0.5, doc="drawn puck radius, metres"),
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
    _check_calibrations(cfg, ctx)
    _check_marker_ids(cfg, ctx)
    _check_studio_markers(cfg, ctx)
    _check_on_table(cfg, ctx)
    check_udp_ports(cfg, ctx)
    _check_sprites(cfg, ctx)


def _check_sprites(cfg: dict, ctx: Context) -> None:
    """A sprite names a character an engine makes (a misspelt name would never be drawn, silently).
    Only when every engine is of a kind whose characters the config names."""
    made: set[str] = set()
    for e in cfg["engines"]:
        if e["kind"] in ("puppet_master", "touch_pose"):
            made |= {e["name"], f"{e['name']}.main"}   # (.main: the studio's playback ghost)
        elif e["kind"] == "mop":
            made |= {c["name"] for c in e["characters"]}
        elif e["kind"] != "fault":
            return
    shown = ", ".join(sorted(m for m in made if not m.endswith(".main"))) or "none"
    for name in cfg["view"]["sprites"]:
        if name not in made:
            raise ctx.error(f"view.sprites.{name}", f"no engine makes a character {name!r} "
                                                    f"(characters: {shown})")


def _check_on_table(cfg: dict, ctx: Context) -> None:
    """Places given in table metres (a performer's ``home``, an engine's or a MOP character's
    ``at``) lie on the table: one off it (``home: [1e300, 0.4]`` was accepted) put a puck the
    camera never sees or a character nobody can reach."""
    w, h = cfg["table"]["width"], cfg["table"]["height"]
    places = [(f"sources[{i}].performers[{j}].home", p.get("home"))
              for i, s in enumerate(cfg["sources"]) for j, p in enumerate(s.get("performers") or [])]
    for i, e in enumerate(cfg["engines"]):
        places.append((f"engines[{i}].at", e.get("at")))
        places += [(f"engines[{i}].characters[{j}].at", c.get("at"))
                   for j, c in enumerate(e.get("characters") or []) if isinstance(c, dict)]
    for key, xy in places:
        if isinstance(xy, list) and not (0.0 <= xy[0] <= w and 0.0 <= xy[1] <= h):
            raise ctx.error(key, f"[{xy[0]:g}, {xy[1]:g}] is off the {w:g} x {h:g} m table "
                                 f"(x from 0 to {w:g}, y from 0 to {h:g} metres)")


def _check_calibrations(cfg: dict, ctx: Context) -> None:
    """Every calibration file named in the config is read and checked now, not when (or if) a
    camera first uses it: a malformed, 2x2 or singular one fails at start-up with its key."""
    named = [("calibration", cfg["calibration"])]
    named += [(f"sources[{i}].calibration", s.get("calibration"))
              for i, s in enumerate(cfg["sources"])]
    for key, path in named:
        if path is None:
            continue
        from calibration.files import load_calibration
        try:
            load_calibration(path)
        except InputError as exc:
            raise ctx.error(key, str(exc)) from None


def dictionary_size(name: str) -> int | None:
    """How many marker ids OpenCV's predefined dictionary ``name`` holds (None: unknown name)."""
    import cv2
    code = getattr(cv2.aruco, name, None)
    if not isinstance(code, int):
        return None
    return int(cv2.aruco.getPredefinedDictionary(code).bytesList.shape[0])


def _check_marker_ids(cfg: dict, ctx: Context) -> None:
    """Marker ids that are rendered or looked up must exist in their marker dictionary."""
    tracking = cfg.get("tracking") or {}
    default = tracking.get("dictionary")

    def check(key: str, marker: int, name: str | None) -> None:
        n = dictionary_size(name) if name else None
        if n is not None and not 0 <= marker < n:
            raise ctx.error(key, f"marker id {marker} is not in {name} (ids 0 to {n - 1}); "
                                 "use a smaller id or a larger dictionary")

    for key in tracking.get("puck_ids", {}):
        if str(key).isdigit():
            check(f"tracking.puck_ids.{key}", int(key), default)
    for i, s in enumerate(cfg["sources"]):
        if s["kind"] not in MARKER_SOURCES:
            continue
        name = s.get("dictionary") or default
        for j, marker in enumerate(s.get("pucks", [])):
            check(f"sources[{i}].pucks[{j}]", marker, name)
        for j, perf in enumerate(s.get("performers", [])):
            check(f"sources[{i}].performers[{j}].puck", perf["puck"], name)


def _check_studio_markers(cfg: dict, ctx: Context) -> None:
    """The studio's control markers: each its own id (one marker sending two commands would
    start and stop a take at once), none a puck a source moves (the studio takes control
    markers out of the frame: that puck would vanish from the characters' inputs), and each in
    the marker dictionary when a camera reads them."""
    studio = cfg.get("studio") or {}
    tracking = cfg.get("tracking") or {}
    first: dict[int, str] = {}
    moved = {}
    for i, s in enumerate(cfg["sources"]):
        moved.update({m: f"sources[{i}].pucks" for m in s.get("pucks", [])})
        moved.update({p["puck"]: f"sources[{i}].performers" for p in s.get("performers", [])})
    camera = any(s["kind"] in CAMERA_SOURCES for s in cfg["sources"])
    n = dictionary_size(tracking["dictionary"]) if camera and tracking.get("dictionary") else None
    for cmd, marker in (studio.get("markers") or {}).items():
        if marker is None:
            continue
        key = f"studio.markers.{cmd}"
        if marker in first:
            raise ctx.error(key, f"marker {marker} is also studio.markers.{first[marker]}; "
                                 "give each command its own marker (or null)")
        if marker in moved:
            raise ctx.error(key, f"marker {marker} is a puck of {moved[marker]}; a control "
                                 "marker is taken off the table's inputs: use another id")
        if n is not None and not 0 <= marker < n:
            raise ctx.error(key, f"marker id {marker} is not in {tracking['dictionary']} (ids 0 "
                                 f"to {n - 1}); use a smaller id or a larger dictionary")
        first[marker] = cmd
    _check_engine_pucks(cfg, first, ctx)


def _engine_pucks(cfg: dict) -> list[tuple[str, int]]:
    """Every puck an engine binds, with its key: a Puppet Master engine's mains (one, or each
    of ``nearest``/``first``) and its designer's pucks, a MOP performer's puck inputs
    (touch-pose binds touches only)."""
    out: list[tuple[str, int]] = []
    for i, e in enumerate(cfg["engines"]):
        if e["kind"] == "puppet_master":
            main = e["main"]
            many = [(f"{main['kind']}[{j}]", b) for j, b in enumerate(main.get("mains") or [])]
            for sub, b in many or [("", main)]:
                if b["kind"] == "puck":
                    out.append((f"engines[{i}].main{'.' + sub if sub else ''}.puck", b["puck"]))
            d = e.get("designer") or {}
            if d.get("enabled"):
                out += [(f"engines[{i}].designer.{k}", d[k]) for k in ("main_puck", "react_puck")
                        if d.get(k) is not None]
        elif e["kind"] == "mop":
            out += [(f"engines[{i}].performers[{j}].inputs[{k}].id", x["id"])
                    for j, p in enumerate(e["performers"])
                    for k, x in enumerate(p["inputs"]) if x["kind"] == "puck"]
    return out


def _check_engine_pucks(cfg: dict, controls: dict[int, str], ctx: Context) -> None:
    """No engine binds a studio control marker's puck: the studio takes control markers out of
    the frame (the character would never see its puck, and setting it down would stop or keep
    a take). The studio is on for every MOP, touch-pose and designer config and with ``run
    --studio``, so this holds whether or not ``studio.enabled`` is. Through
    ``tracking.puck_ids`` a control marker may arrive as another puck id: that puck is
    refused too (the control marker would move the character instead)."""
    controls = {int(m): f"studio.markers.{cmd}" for m, cmd in controls.items()}
    for i, e in enumerate(cfg["engines"]):
        d = e.get("designer") or {}
        if d.get("enabled") and d.get("record_marker") is not None:
            controls[int(d["record_marker"])] = f"engines[{i}].designer.record_marker"
    mapped = {int(m): int(p) for m, p in ((cfg.get("tracking") or {}).get("puck_ids")
                                          or {}).items() if str(m).isdigit()}
    for key, puck in _engine_pucks(cfg):
        if puck in controls:
            raise ctx.error(key, f"puck {puck} is the studio's control marker {controls[puck]}"
                                 "; the studio takes it off the table's inputs, so this engine "
                                 "would never see it: use another puck or another marker id")
        for marker, to in mapped.items():
            if to == puck and marker in controls:
                raise ctx.error(key, f"puck {puck} is marker {marker} (tracking.puck_ids."
                                     f"{marker}), the studio's control marker "
                                     f"{controls[marker]}: use another puck or marker id")
    _check_puck_map(cfg, controls, ctx)


def _check_puck_map(cfg: dict, controls: dict[int, str], ctx: Context) -> None:
    """No ``tracking.puck_ids`` entry moves a marker onto or off a studio control marker's id:
    the studio looks for control markers among the mapped ids, so ``{10: 46}`` made marker 10
    stop every take set down, and ``{46: 3}`` hid the stop marker from the studio for good."""
    for key, to in ((cfg.get("tracking") or {}).get("puck_ids") or {}).items():
        if not str(key).isdigit() or int(key) == int(to):
            continue
        marker, where = int(key), f"tracking.puck_ids.{key}"
        if int(to) in controls:
            raise ctx.error(where, f"marker {marker} would arrive as puck {to}, the studio's "
                                   f"control marker {controls[int(to)]}: setting it down would "
                                   "give that command; use another puck id")
        if marker in controls:
            raise ctx.error(where, f"marker {marker} is the studio's control marker "
                                   f"{controls[marker]}; as puck {to} the studio would never see "
                                   "it: map another marker (or set that control to null)")


def tracking_schema() -> Spec:
    """The puck tracker's options (owned by the tracking plugin when installed)."""
    tracking = registry.optional_module("tabletop.plugins.tracking")
    return tracking.SCHEMA if tracking is not None else Record({})


def top_schema() -> Record:
    from tabletop.kiosk import SCHEMA as KIOSK
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
    the files and folders it names (a recording embeds them, see :mod:`tabletop.bundle`)."""

    def __init__(self, values: dict[str, Any], raw: Any, base: Path, file: str,
                 refs: list[FileRef]) -> None:
        super().__init__(values)
        self.raw, self.base, self.file, self.refs = raw, base, file, refs


def load_config(path: str | Path) -> Config:
    """Read and validate a config file; returns the config with every default filled in."""
    p = Path(path)
    data = read_yaml(p, ConfigError, missing="config file not found")
    return validate_config(data, str(p), p.resolve().parent)


def validate_config(data: Any, file: str = "<config>", base: Path | None = None) -> Config:
    """Validate an already parsed config mapping."""
    ctx = Context(file=file, base=base or Path.cwd())
    if data is None:
        raise ConfigError(f"{file}: the file is empty; expected a mapping with 'sources'")
    return Config(top_schema().validate(data, "", ctx), data, ctx.base, file, ctx.refs)
