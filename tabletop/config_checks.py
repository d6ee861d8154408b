"""The config's checks across its sections (sources, engines, tracking, the studio, the view):
what each section's schema cannot see alone. Each refuses with one message naming the key path
(:meth:`tabletop.schema.Context.error`); :func:`tabletop.config._check_all` runs them."""

from __future__ import annotations

from tabletop.frames import InputError
from tabletop.schema import Context

# Sources that draw markers from the configured ids (so every id must be in the dictionary).
MARKER_SOURCES = ("synthetic_camera",)
# Sources whose pucks are printed markers read by the tracker (a marker id is a puck id).
CAMERA_SOURCES = ("camera", "synthetic_camera")


def check_sprites(cfg: dict, ctx: Context) -> None:
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


def check_calibrations(cfg: dict, ctx: Context) -> None:
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


def check_marker_ids(cfg: dict, ctx: Context) -> None:
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
    for i, _, key, marker in moved_pucks(cfg):
        s = cfg["sources"][i]
        if s["kind"] in MARKER_SOURCES:
            check(key, marker, s.get("dictionary") or default)


def moved_pucks(cfg: dict) -> list[tuple[int, str, str, int]]:
    """Every puck a source moves (its ``pucks`` and its performers' ``puck``): (source index,
    the list's key, the puck's own key, puck id), in the config's order."""
    out: list[tuple[int, str, str, int]] = []
    for i, s in enumerate(cfg["sources"]):
        out += [(i, f"sources[{i}].pucks", f"sources[{i}].pucks[{j}]", m)
                for j, m in enumerate(s.get("pucks") or [])]
        out += [(i, f"sources[{i}].performers", f"sources[{i}].performers[{j}].puck", p["puck"])
                for j, p in enumerate(s.get("performers") or [])]
    return out


def check_scripted_pucks(cfg: dict, ctx: Context) -> None:
    """Each puck moved by one scripted source at most (``scripted``, ``synthetic_camera``): the
    tracker would merge two sources moving one id into one puck jumping between the two paths,
    with no word of it. (Within a source a performer's puck may also be in ``pucks``.)"""
    moved: dict[int, tuple[int, str]] = {}     # puck -> (source index, its key)
    for i, _, key, puck in moved_pucks(cfg):
        first = moved.setdefault(puck, (i, key))
        if first[0] != i:
            raise ctx.error(key, f"puck {puck} is also moved by {first[1]} "
                                 f"({cfg['sources'][first[0]]['name']}); two sources "
                                 "moving one puck merge into one jumping between them: "
                                 "give each puck to one source")


def check_studio_markers(cfg: dict, ctx: Context) -> None:
    """The studio's control markers: each its own id (one marker sending two commands would
    start and stop a take at once), none a puck a source moves (the studio takes control
    markers out of the frame: that puck would vanish from the characters' inputs), and each in
    the marker dictionary when a camera reads them."""
    studio = cfg.get("studio") or {}
    tracking = cfg.get("tracking") or {}
    first: dict[int, str] = {}
    moved = {puck: where for _, where, _, puck in moved_pucks(cfg)}
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


def check_named_pucks(cfg: dict, ctx: Context) -> None:
    """Where ``tracking.pucks`` names the pucks on the table, every puck an engine binds is
    named: the tracker shows no other id, so that engine would never see its puck."""
    named = set((cfg.get("tracking") or {}).get("pucks") or ())
    if not named:
        return
    for key, puck in _engine_pucks(cfg):
        if puck not in named:
            raise ctx.error(key, f"puck {puck} is not in tracking.pucks {sorted(named)}; the "
                                 "tracker shows only those: add it there")


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
    the studio looks for control markers among the mapped ids, so ``{10: 46}`` would make
    marker 10 stop every take when set down, and ``{46: 3}`` would hide the stop marker from
    the studio for good."""
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


#: Sources whose pucks the config lists: no other puck ever arrives from them.
LISTED_SOURCES = ("scripted", "synthetic_camera")


def unmoved_engine_pucks(cfg: dict) -> list[str]:
    """What to warn of: a puck an engine binds (:func:`_engine_pucks`) that no source moves,
    when every source is one whose pucks the config lists (:data:`LISTED_SOURCES`); its
    character waits for it for ever (a camera, OSC or serial source may bring any puck)."""
    if not cfg["sources"] or any(s["kind"] not in LISTED_SOURCES for s in cfg["sources"]):
        return []
    moved = sorted({puck for *_, puck in moved_pucks(cfg)})
    listed = ", ".join(map(str, moved)) or "none"
    return [f"{key}: puck {puck} is moved by no source (the sources move pucks {listed}); "
            "what waits for it never moves" for key, puck in _engine_pucks(cfg)
            if puck not in moved]


def check_reactor_mains(cfg: dict, ctx: Context) -> None:
    """Each Puppet Master engine's main reads a character that can be read
    (:func:`tabletop.plugins.puppet_master.binding_problem`)."""
    from tabletop.plugins.puppet_master import binding_problem
    engines = cfg["engines"]
    for i, e in enumerate(engines):
        if e["kind"] == "puppet_master":
            why = binding_problem(e, engines, i)
            if why:
                raise ctx.error(f"engines[{i}].main", why)
