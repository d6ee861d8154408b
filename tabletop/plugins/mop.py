"""Engine ``mop``: action following (MOP). Performers' gestures drive characters' motions.

Config (see ``examples/mop.yaml``)::

    - kind: mop
      rate_hz: 30                 # follower rate; templates are resampled to it
      library: mop_library        # where the designer's kept actions are saved (optional)
      follower: {sigma: 0.2, window: 15, ...}
      performers:
        - name: left
          inputs:
            - {kind: puck, id: 1, features: [dx, dy]}
            - {kind: stream, name: arm, columns: [0, 1]}
      characters:
        - name: dancer
          kind: skeleton          # skeleton (URDF humanoid), creature, face, hybrid or sprite
          performer: left
          at: [0.3, 0.4]
          actions:
            - {name: circle, template: gestures/circle.csv, motion: walk}

A ``motion`` is a built-in clip of the character (creature: walk, wag, curl, strike; face: laugh,
surprise, angry, wink, talk; hybrid, a creature with a face whose skeletal and blendshape
channels one action drives together: walk_talk, strike_angry, curl_surprise, wag_laugh, or with
``body: humanoid`` pybullet_data's humanoid with a face on its neck: walk_talk, punch_angry,
jump_surprise, dance_laugh; sprite: frames, its sheet in order), a DeepMimic clip name for a
skeleton (walk, backflip, ...; from ``pybullet_data``), or a path to a DeepMimic ``.txt`` or a
``tabletop.clip`` ``.json`` file. A ``sprite`` character is a vector sprite sheet (``sheet``:
``{"format": "tabletop.sprites", "bones": [[a, b], ...], "frames": [[[x, y], ...], ...]}``).
Template CSVs hold the performer's feature columns (an optional ``t`` column, seconds, lets them
be resampled to ``rate_hz``).

Designer flow: every character is an action slot of the studio (:mod:`tabletop.studio`; Tab
picks it): R records its performer after the countdown and stops, the take is trained at once and
can be performed; A cycles the motion it plays; K saves it to the library, X drops it, R again
redoes it.
"""

from __future__ import annotations

import logging
import math
from pathlib import Path
from typing import TYPE_CHECKING, Mapping, Sequence

from behaviors.motion.clips import ClipError, TimeWarp
from behaviors.mop.inputs import Performer, PuckInput, StreamInput, TouchInput
from behaviors.mop.puppetry import Puppet
from behaviors.mop.stage import MopStage
from tabletop.plugins.mop_rigs import check_body, make_rig, motion_kind
from tabletop.plugins.mop_stream import check_stream
from tabletop.plugins.mop_files import (MopError, MotionLoader, action_entries, action_files,
                                        configured_action, configured_actions, load_template,
                                        read_template, resolve_motion, twin_of)
from tabletop.plugins.mop_follower import FOLLOWER
from tabletop.plugins.mop_library import (ActionsFile, check_shared_library, configured_templates,
                                          library_actions, library_names, save_to_library)
from tabletop.files import FileFormatError
from tabletop.kiosk.watch import tree_signature
from tabletop.registry import BuildContext
from tabletop.schema import Bool, Context, FilePath, ListOf, Number, Optional_, Record, Str

if TYPE_CHECKING:
    import numpy as np

PUCK_FEATURES = ("dx", "dy", "heading", "speed")

log = logging.getLogger("tabletop")


INPUT = Record({
    "kind": Str(choices=("puck", "touch", "stream")),
    "id": Number(1, integer=True, lo=0, doc="puck: marker id"),
    "features": ListOf(Str(choices=PUCK_FEATURES), default=["dx", "dy"], min_len=1,
                       doc="puck: which path features"),
    "rest_time": Number(0.8, lo=0.05, hi=60.0, unit="seconds",
                        doc="puck: seconds still that end a gesture"),
    "rest_radius": Number(0.003, unit="metres", lo=0.0001, hi=0.1,
                          doc="puck: metres it may wander (jitter) and still be resting"),
    "name": Optional_(Str(), doc="stream: its name on the bus"),
    "columns": Optional_(ListOf(Number(integer=True, lo=0), min_len=1), doc="stream: columns"),
    "relative_to": Optional_(ListOf(Number(integer=True, lo=0), min_len=1, max_len=3),
                             doc="stream: columns (root or head x, y[, z]) subtracted from "
                                 "every group of as many columns"),
})


PUCK_KEYS = ("id", "features", "rest_time", "rest_radius")   # what a puck input alone reads
STREAM_KEYS = ("name", "columns", "relative_to")              # and a stream input
SKELETON_KEYS = ("skeleton", "view_yaw", "elevation", "travel")  # a skeleton character alone


def _refuse_unread(value: dict, spec: Record, keys: tuple[str, ...], owner: str, noun: str,
                   path: str, ctx: Context) -> None:
    """Refuse a key of ``keys`` given other than its default: a ``value["kind"]`` ``noun`` does
    not read it (taken, it would change nothing)."""
    for key in keys:
        if value[key] != spec.fields[key].default:
            raise ctx.error(f"{path}.{key}", f"only a {owner} {noun} takes {key}; a "
                                             f"{value['kind']} {noun} does not read it")


def _check_input(value: dict, path: str, ctx: Context) -> None:
    for keys, owner in ((PUCK_KEYS, "puck"), (STREAM_KEYS, "stream")):
        if value["kind"] != owner:
            _refuse_unread(value, INPUT, keys, owner, "input", path, ctx)
    if value["kind"] == "stream":
        check_stream(value, path, ctx)


INPUT.check = _check_input

PERFORMER = Record({
    "name": Str(),
    "inputs": ListOf(INPUT, min_len=1, doc="concatenated in this order"),
})

ACTION = Record({
    "name": Str(),
    "template": FilePath(kind="file", built_without=True,
                         doc="CSV of the performer's feature columns"),
    "motion": Str(doc="built-in clip, DeepMimic clip name, or a .txt/.json clip file"),
    "warp": Optional_(ListOf(ListOf(Number(lo=0.0, hi=1.0), min_len=2, max_len=2), min_len=2),
                      doc="[[action, motion], ...] progress pairs from [0,0] to [1,1]"),
    "performer": Optional_(Str(), doc="overrides the character's performer"),
})

CHARACTER = Record({
    "name": Str(),
    "kind": Str(choices=("skeleton", "creature", "face", "hybrid", "sprite")),
    "body": Optional_(Str(choices=("creature", "humanoid")),
                      doc="hybrid: the body its face rides on (default creature; a humanoid: "
                          "pybullet_data's)"),
    "performer": Str(),
    "at": Optional_(ListOf(Number(), min_len=2, max_len=2), doc="[x, y] metres; default centre"),
    "heading": Number(math.pi / 2, doc="radians; the figure's up points this way"),
    "size": Number(0.25, unit="metres",
                   lo=0.01, hi=5.0, doc="metres: height, body length or face height"),
    "color": ListOf(Number(integer=True, lo=0, hi=255), default=[240, 170, 60],
                    min_len=3, max_len=3),
    "skeleton": Optional_(FilePath(kind="file"), doc="URDF; default pybullet_data humanoid"),
    "sheet": Optional_(FilePath(kind="file"), doc="sprite: a tabletop.sprites JSON sheet"),
    "view_yaw": Number(0.5, doc="skeleton: viewing side, radians (0 side, pi/2 front)"),
    "elevation": Number(0.25, unit="radians", lo=-1.5, hi=1.5, doc="skeleton: view tilt, radians"),
    "travel": Bool(False, doc="skeleton: let the root travel as in the clip"),
    "motions": ListOf(Str(), default=[], doc="motions the designer may assign (default: all)"),
    "actions": ListOf(ACTION, default=[]),
    "blend_s": Number(0.2, lo=0.0, hi=5.0),
    "hold_s": Number(0.5, lo=0.0, hi=60.0),
    "rest_s": Number(0.4, lo=0.0, hi=60.0),
    "min_probability": Number(0.5, lo=0.0, hi=1.0,
                              doc="an action less probable than this shows nothing"),
})

def _check_motion(ctx: Context, key: str, c: dict, motion: str, rigs: dict) -> None:
    """Resolve a motion of character ``c`` (MopError if it cannot be); a clip file is noted so
    a recording embeds it, read, and checked against the character's rig (made once per
    character in ``rigs``; a face's clip with no blendshape channel stopped the build naming
    the character alone). A sprite's frames are its sheet's own."""
    kind = motion_kind(c)
    try:
        how, found = resolve_motion(kind, motion, ctx.base)
    except MopError:
        if not (ctx.start_without and Path(motion).suffix in (".txt", ".json")):
            raise
        # a kiosk's start: a clip file deleted (or a folder now) is the build's to go without
        how, found = "clip", action_files({"template": "", "motion": motion}, ctx.base)[1]
    if how != "builtin" and Path(motion).suffix in (".txt", ".json"):
        ctx.refer(key, motion, found)
        if ctx.start_without:     # a kiosk's start: the build reads it (and may go without)
            return
        # read now: a clip file that is no clip stopped the build naming no key, and a
        # kiosk took such an edit for a good one
        clip = MotionLoader(kind, ctx.base)(motion)
        if kind != "sprite":
            if c["name"] not in rigs:
                rigs[c["name"]] = make_rig(c)
            rigs[c["name"]].check(clip)


def _check_all(cfg: dict, path: str, ctx: Context) -> None:
    if cfg["library"] is not None:   # refused at load, not at the designer's first keep
        from tabletop.studio.session import unusable
        why = unusable(cfg["library"])
        if why:
            raise ctx.error(f"{path}.library", f"cannot hold kept actions: {why}")
    names = set()
    for i, p in enumerate(cfg["performers"]):
        if p["name"] in names:
            raise ctx.error(f"{path}.performers[{i}].name", f"duplicate performer {p['name']!r}")
        names.add(p["name"])
    features: dict[str, tuple[str, ...]] = {}    # each performer's feature columns
    for i, p in enumerate(cfg["performers"]):
        try:
            features[p["name"]] = _make_performer(p).names
        except MopError as exc:
            raise ctx.error(f"{path}.performers[{i}].inputs", str(exc)) from None
    chars = set()
    rigs: dict = {}                              # each character's rig, made for a clip file
    for i, c in enumerate(cfg["characters"]):
        where = f"{path}.characters[{i}]"
        if not c["name"].strip() or c["name"] in (".", "..") or any(s in c["name"] for s in "/\\"):
            # its kept actions are the folder <library>/<name>: '..' kept them beside the
            # library, '' in the library's own folder; and '/' splits the studio's focus
            raise ctx.error(f"{where}.name", f"{c['name']!r} cannot name a character: it names "
                            "its folder of kept actions (not empty, '.' or '..', no '/' or '\\')")
        if c["name"] in chars:
            raise ctx.error(f"{where}.name", f"duplicate character {c['name']!r}")
        chars.add(c["name"])
        if c["performer"] not in names:
            raise ctx.error(f"{where}.performer", f"no performer {c['performer']!r} "
                            f"(performers: {', '.join(sorted(names))})")
        if c["kind"] == "sprite" and c["sheet"] is None:
            raise ctx.error(f"{where}.sheet", "a sprite character needs its sheet (a JSON file)")
        if c["kind"] != "sprite":
            _refuse_unread(c, CHARACTER, ("sheet",), "sprite", "character", where, ctx)
        if c["kind"] not in ("skeleton", "hybrid"):
            _refuse_unread(c, CHARACTER, SKELETON_KEYS, "skeleton", "character", where, ctx)
        check_body(c, {k: f.default for k, f in CHARACTER.fields.items()}, where, ctx.error)
        if motion_kind(c) in ("skeleton", "humanoid_hybrid") and c["skeleton"] is None:
            from behaviors.motion.deepmimic import humanoid_urdf
            try:
                humanoid_urdf()
            except ClipError as exc:
                raise ctx.error(f"{where}.skeleton", str(exc)) from None
        if c["kind"] == "skeleton" and c["skeleton"] is not None:
            # made now: a file that is no URDF stopped the check (or the build) naming no key
            from behaviors.motion.skeleton import SkeletonError
            try:
                rigs[c["name"]] = make_rig(c)
            except SkeletonError as exc:
                raise ctx.error(f"{where}.skeleton", str(exc)) from None
        seen, loaded = set(), []   # loaded: (action, performer, samples, template file)
        for j, a in enumerate(c["actions"]):
            aw = f"{where}.actions[{j}]"
            if not a["name"].strip():   # the followers refused it, naming neither key nor file
                raise ctx.error(f"{aw}.name", "an action needs a name")
            if a["name"] in seen:
                raise ctx.error(f"{aw}.name", f"duplicate action {a['name']!r}")
            seen.add(a["name"])
            if a["performer"] is not None and a["performer"] not in names:
                raise ctx.error(f"{aw}.performer", f"no performer {a['performer']!r}")
            try:
                _check_motion(ctx, f"{aw}.motion", c, a["motion"], rigs)
            except (MopError, ClipError) as exc:
                raise ctx.error(f"{aw}.motion", str(exc)) from None
            try:
                if a["warp"] is not None:
                    TimeWarp(a["warp"])
            except ClipError as exc:
                raise ctx.error(f"{aw}.warp", str(exc)) from None
            if ctx.start_without:   # a kiosk's start: the build reads it (or goes without)
                continue
            try:    # its columns, times and span, at load: the key is named, not only the file
                # (load_config of examples/mop.yaml 20 -> 30 ms, mean of 5 on a loaded machine);
                # read once however many actions name it, the build takes what was read
                a["template"] = read_template(Path(a["template"]), ctx.read)
                performer = a["performer"] or c["performer"]
                x = load_template(a["template"], features[performer], cfg["rate_hz"])
            except FileFormatError as exc:
                raise ctx.error(f"{aw}.template", str(exc)) from None
            twin = twin_of((a["name"], performer, x, a["template"]), loaded)
            if twin:
                raise ctx.error(f"{aw}.template", twin)
        for j, m in enumerate(c["motions"]):
            try:
                _check_motion(ctx, f"{where}.motions[{j}]", c, m, rigs)
            except (MopError, ClipError) as exc:
                raise ctx.error(f"{where}.motions[{j}]", str(exc)) from None


SCHEMA = Record({
    "rate_hz": Number(30.0, lo=1.0, hi=1000.0, doc="follower steps per second"),
    "library": Optional_(FilePath(must_exist=False, kind="dir", embed=True),
                         doc="folder of the designer's kept actions"),
    "follower": FOLLOWER,
    "performers": ListOf(PERFORMER, min_len=1),
    "characters": ListOf(CHARACTER, min_len=1),
}, check=_check_all)


# --- loading ------------------------------------------------------------------------------------

def _make_performer(p: dict) -> Performer:
    many = len(p["inputs"]) > 1
    inputs = []
    for k, i in enumerate(p["inputs"]):
        if i["kind"] == "puck":
            inputs.append(PuckInput(i["id"], i["features"], i["rest_time"],
                                    f"puck{i['id']}_" if many else "", i["rest_radius"]))
        elif i["kind"] == "touch":
            inputs.append(TouchInput("touch_" if many else ""))
        else:
            inputs.append(StreamInput(i["name"], i["columns"], relative_to=i["relative_to"]))
    names = [n for i in inputs for n in i.names]
    if len(set(names)) != len(names):
        raise MopError(f"performer {p['name']!r}: two inputs give the same feature names {names}")
    return Performer(p["name"], inputs)


# --- building -----------------------------------------------------------------------------------

def build(options: dict, ctx: BuildContext) -> MopStage:
    from behaviors.mop.follower import ActionFollower
    from behaviors.mop.group import FollowerGroup
    from behaviors.mop.group_split import grouped
    check_shared_library(options, ctx)
    rate = float(options["rate_hz"])
    fo = options["follower"]
    params = dict(sigma=fo["sigma"], window=fo["window"], transitions=tuple(fo["transitions"]),
                  backward=fo["backward"], restart=fo["restart"], memory=fo["memory"],
                  null_distance=fo["null_distance"], null_memory=fo["null_memory"],
                  onset=fo["onset"], accept_distance=fo["accept_distance"],
                  scale_range=tuple(fo["scale_range"]),
                  switch_margin=fo["switch_margin"], confirm=fo["confirm"],
                  hold_tolerance=fo["hold_tolerance"],
                  max_spread=fo["max_spread"],
                  relative_floor=fo["relative_floor"])

    def make_follower(templates: Mapping[str, np.ndarray], units: np.ndarray | None = None,
                      min_scale: np.ndarray | None = None,
                      window: int | None = None) -> ActionFollower:
        # size, place and direction of motion only where the features' units are known (puck
        # and touch paths); a stream's columns are followed as recorded
        spatial = units is not None
        invariance = (fo["invariance"] if fo["invariance"] != "auto"
                      else "scale" if spatial else "none")
        return ActionFollower(templates, units=units, invariance=invariance, min_scale=min_scale,
                              tangent=fo["tangent"] if spatial else 0.0,
                              **dict(params, window=window or params["window"]))

    performers = {p["name"]: _make_performer(p) for p in options["performers"]}
    library: Path | None = options["library"]
    w, h = ctx.table
    puppets, templates, motions, loaders, bound = [], {}, {}, {}, {}
    problems: dict[str, list[str]] = {}      # each character's bad library files (skipped)
    loaded: dict[str, list[str]] = {}        # each character's actions from the library
    read: dict[str, tuple] = {}              # its folder's signature: the studio's first baseline
    windows: dict[str, int] = {}             # the follower windows the studio saved
    bad_window: dict[str, str] = {}          # why a character's saved window is not read
    chars = {c["name"]: c for c in options["characters"]}
    # a kiosk's start (or its replay) runs without the configured actions it cannot read
    started = ctx.shared.get("started_without", {})     # (a replay's: the run's, per engine)
    without = bool(ctx.shared.get("kiosk_start") or options["name"] in started)
    started_without: list[str] = []
    missing: list[dict] = []        # those actions, followed once fixed (tabletop.kiosk.actions)
    watched: list[dict] = []        # every configured action (those too): a kiosk follows them
    features = {n: p.names for n, p in performers.items()}
    for c in options["characters"]:
        rig = make_rig(c)
        loader = MotionLoader(motion_kind(c), ctx.base, rig)
        loaders[c["name"]] = loader
        bound[c["name"]] = c["performer"]
        signed: dict[str, tuple] = {}
        actions, tmpl, bad = configured_actions(c, features, loader, rate, without,
                                                started.get(options["name"]), signed)
        started_without += [why for _, why, _ in bad]
        gone, every = action_entries(c, ctx.base, bad, signed)
        missing += gone
        watched += every
        if library is not None:
            read[c["name"]] = tree_signature(library / c["name"])
            file = ActionsFile(library, c["name"])          # read once: window and entries
            try:
                window = file.window()
            except MopError as exc:
                bad_window[c["name"]] = str(exc)
                window = None
            if window is not None:
                windows[c["name"]] = window
                log.info("MOP character %r follows with the window %d saved in its actions.yaml "
                         "(the config's follower.window: %d)", c["name"], window, fo["window"])
            kept, bad = library_actions(library, c["name"], performers[c["performer"]].names,
                                        rate, loader, configured_templates(c, tmpl), file,
                                        c["performer"])
            for action, samples in kept:
                actions.append(action)
                tmpl[action.name] = (c["performer"], samples)
            problems[c["name"]] = problems.get(c["name"], []) + bad
            loaded[c["name"]] = [a.name for a, _ in kept]
        at = c["at"] or [w / 2, h / 2]
        try:
            puppets.append(Puppet(c["name"], rig, actions, at[0], at[1], c["heading"], c["size"],
                                  tuple(c["color"]), c["blend_s"], c["hold_s"], c["rest_s"],
                                  c["min_probability"]))
        except ClipError as exc:
            raise MopError(f"character {c['name']!r}: {exc}") from None
        templates[c["name"]] = tmpl
        motions[c["name"]] = tuple(c["motions"]) or loader.available()

    def save(character: str, action: str, samples: np.ndarray, names: Sequence[str],
             motion: str) -> str:
        return save_to_library(library, character, action, samples, tuple(names), motion, rate)

    stage = MopStage(options["name"], rate, performers, puppets, templates, make_follower,
                     motions, lambda character, motion: loaders[character](motion),
                     save if library is not None else None, bound,
                     make_group=grouped(FollowerGroup), windows=windows,
                     taken=(lambda character: library_names(library, character))
                     if library is not None else None, default_window=fo["window"])
    # (the status's behavior_errors; a recording's started_without)
    stage.start_problems, stage.problem = started_without, "; ".join(started_without)
    stage.missing, stage.watched = missing, watched
    stage.configured_action = lambda c, a: configured_action(      # read afresh from disk
        c, a, features, MotionLoader(motion_kind(c), ctx.base, loaders[c["name"]].rig), rate)
    for p in (p for bad in problems.values() for p in bad):
        log.error("MOP action skipped: %s", p)
    for character, why in bad_window.items():      # reported with the library's problems
        log.error("MOP saved window ignored, the config's follower.window %d used: %s",
                  fo["window"], why)
        problems[character].append(why)
    stage.library_problems, stage.library_loaded, stage.library_read = problems, loaded, read
    stage.library_actions = lambda character: library_actions(          # the studio reloads
        library, character, performers[bound[character]].names, rate, loaders[character],
        configured_templates(chars[character], stage.templates[character]), None,
        bound[character])
    return stage
