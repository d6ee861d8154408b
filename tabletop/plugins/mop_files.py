"""The MOP engine's files: characters' motions and the action templates a config names (the
designer's library of kept actions: :mod:`tabletop.plugins.mop_library`)."""

from __future__ import annotations

import json
import logging
from pathlib import Path
from typing import Any

import numpy as np

from behaviors.motion.clips import Clip, ClipError, clip_from_mapping
from behaviors.mop.puppetry import Action
from tabletop.files import (MAX_CLIP_BYTES, MAX_TEMPLATE_BYTES, FileFormatError, Table,
                            UnreadableText, carrying, check_increasing, check_positions,
                            json_loads, read_shared, read_table,
                            read_text_within, tree_signature)
from tabletop.frames import MAX_FEATURE, InputError

log = logging.getLogger("tabletop")

BUILTIN = {"creature": ("walk", "wag", "curl", "strike"),
           "face": ("laugh", "surprise", "angry", "wink", "talk"),
           "hybrid": ("walk_talk", "strike_angry", "curl_surprise", "wag_laugh"),
           "humanoid_hybrid": ("walk_talk", "punch_angry", "jump_surprise", "dance_laugh"),
           "sprite": ("frames",)}
DEEPMIMIC = ("walk", "run", "jump", "kick", "punch", "spinkick", "backflip", "cartwheel", "crawl",
             "dance_a", "dance_b", "getup_facedown", "getup_faceup", "roll", "spin")


class MopError(InputError):
    """A MOP template, motion or library file cannot be used; the message names it."""


def resolve_motion(kind: str, motion: str, base: Path) -> tuple[str, Any]:
    """("builtin", name) | ("deepmimic", path) | ("clip", path) for a motion, or MopError."""
    if kind in BUILTIN and motion in BUILTIN[kind]:
        return "builtin", motion
    p = Path(motion).expanduser()
    if p.suffix in (".txt", ".json"):
        p = p if p.is_absolute() else base / p
        if not p.is_file():
            raise MopError(f"motion file {motion!r} not found (looked for {p})")
        return ("deepmimic" if p.suffix == ".txt" else "clip"), p
    if kind == "skeleton":
        from behaviors.motion.deepmimic import motion_path
        try:
            return "deepmimic", motion_path(motion)
        except ClipError as exc:
            raise MopError(str(exc)) from None
    raise MopError(f"unknown motion {motion!r} for a {kind.replace('_', ' ')}; built-in: "
                   f"{', '.join(BUILTIN.get(kind, ()))}, or a .json clip file")


class MotionLoader:
    """Loads and caches motions for one character kind."""

    def __init__(self, kind: str, base: Path, rig: Any = None) -> None:
        self.kind, self.base, self.rig = kind, base, rig
        self._cache: dict[str, Clip] = {}
        # the kind's built-in clips, made once for all its motions (each made them all: the
        # example installation's build called creature_clips 6 -> 2, face_clips 7 -> 4 times;
        # the build 0.128 -> 0.108 CPU s)
        self._builtin: dict[str, Clip] | None = None

    def __call__(self, motion: str) -> Clip:
        if motion not in self._cache:
            how, what = resolve_motion(self.kind, motion, self.base)
            if how == "builtin" and self.kind == "sprite":
                clip = self.rig.cycle()
            elif how == "builtin" and self.kind == "humanoid_hybrid":
                from behaviors.mop.creatures import humanoid_hybrid_clip
                clip = humanoid_hybrid_clip(what)
            elif how == "builtin":
                from behaviors.mop.creatures import creature_clips, face_clips, hybrid_clips
                if self._builtin is None:
                    self._builtin = {"creature": creature_clips, "face": face_clips,
                                     "hybrid": hybrid_clips}[self.kind]()
                clip = self._builtin[what]
            elif how == "deepmimic":
                from behaviors.motion.deepmimic import load_motion
                clip = load_motion(what)
            else:
                try:
                    data = json_loads(read_text_within(Path(what), MAX_CLIP_BYTES, "clip",
                                                       MopError))
                except (OSError, UnreadableText, json.JSONDecodeError) as exc:
                    raise MopError(f"{what}: cannot read clip: {exc}") from None
                clip = clip_from_mapping(data, str(what))
            self._cache[motion] = clip
        return self._cache[motion]

    def available(self) -> tuple[str, ...]:
        return BUILTIN[self.kind] if self.kind in BUILTIN else DEEPMIMIC


MAX_TEMPLATE_S = 3600.0   # seconds an action's template may span (gestures take seconds): one
# whose last t was 1e9 was resampled at the engine's rate and stopped the run "out of memory"


class Template(Table):
    """A template CSV's path carrying what the config's load read of it (:class:`Table`:
    its header, rows and the file line of each row, read-only). :func:`load_template` takes
    it while the file is unchanged (a stat, no open) and reads a file changed since again."""


def read_template(path: Path, read: dict | None = None) -> Template:
    """A template CSV read (FileFormatError naming the file), for :func:`load_template`;
    ``read``: the config load's files read (:func:`tabletop.files.read_shared`: a template
    that is also a gesture CSV is read once)."""
    if read is None:
        return read_table(path, "template CSV", (), 2, MAX_TEMPLATE_BYTES, Template)
    t = read_shared(read, path, "template CSV", (), 2, MAX_TEMPLATE_BYTES)
    return t if isinstance(t, Template) else carrying(Template, str(t), t.content, t.read)


def load_template(path: Path, names: tuple[str, ...], rate_hz: float) -> np.ndarray:
    """A template (n x d) with the performer's feature columns, resampled to ``rate_hz`` when it
    has a ``t`` column. Raises FileFormatError naming the file. A :class:`Template` unchanged
    on disk since it was read is not read again."""
    if isinstance(path, Template) and path.unchanged():
        header, data, lines = path.content
    else:
        header, data, lines = read_template(path).content
    cols = [c for c in header if c != "t"]
    if sorted(cols) != sorted(names):
        raise FileFormatError(f"{path}: template columns {','.join(cols)} do not match the "
                              f"performer's features {','.join(names)}")
    check_positions(data, header, cols, path, lines, MAX_FEATURE, "",
                    "more than a feature can be followed with")
    x = data[:, [header.index(n) for n in names]]
    if "t" in header:
        t = data[:, header.index("t")]
        check_increasing(t, path, lines=lines)   # named by its file line, as every CSV error
        if t[-1] - t[0] > MAX_TEMPLATE_S:
            raise FileFormatError(f"{path}: the template spans {t[-1] - t[0]:g} s (column 't'); "
                                  f"at most {MAX_TEMPLATE_S:g} s can be followed")
        x = resample(t, x, rate_hz)
    return x


def resample(t: np.ndarray, x: np.ndarray, rate_hz: float) -> np.ndarray:
    """Samples ``x`` (n x d) taken at increasing times ``t`` (s), linearly interpolated at
    ``rate_hz`` from ``t[0]`` to about ``t[-1]`` (at least 2 samples); the caller bounds the
    span (:data:`MAX_TEMPLATE_S`)."""
    n = max(2, int(round((t[-1] - t[0]) * rate_hz)) + 1)
    tt = t[0] + np.arange(n) / rate_hz
    return np.stack([np.interp(tt, t, x[:, k]) for k in range(x.shape[1])], axis=1)


def action_files(action: dict[str, Any], base: Path) -> tuple[Path, ...]:
    """The files a configured ``action`` of a character reads: its template, then its motion
    where that is a clip file (``.txt``, ``.json``; relative to ``base``)."""
    files = [Path(action["template"])]
    m = Path(action["motion"]).expanduser()
    if m.suffix in (".txt", ".json"):
        files.append(m if m.is_absolute() else base / m)
    return tuple(files)


def configured_action(character: dict[str, Any], action: dict[str, Any],
                      features: dict[str, tuple[str, ...]], loader: MotionLoader,
                      rate_hz: float, check_rig: bool = True
                      ) -> tuple[Action, str, np.ndarray]:
    """The configured ``action`` of ``character``: the action, its performer and template
    (samples at ``rate_hz``); InputError naming the file that cannot be read. ``check_rig``:
    its clip is checked against the character's rig (else the puppet checks it)."""
    from behaviors.motion.clips import TimeWarp
    performer = action["performer"] or character["performer"]
    clip = loader(action["motion"])
    if check_rig and loader.rig is not None:
        loader.rig.check(clip)
    samples = load_template(_path(action["template"]), features[performer], rate_hz)
    return (Action(action["name"], clip, TimeWarp(action["warp"]) if action.get("warp")
                   else TimeWarp()), performer, samples)


def _path(p: str | Path) -> Path:
    """``p`` as a path, a :class:`Template` as it is (``Path(t)`` drops what it carries)."""
    return p if isinstance(p, Path) else Path(p)


def action_entries(character: dict[str, Any], base: Path,
                   bad: list[tuple[dict[str, Any], str, tuple]], signed: dict[str, tuple]
                   ) -> tuple[list[dict[str, Any]], list[dict[str, Any]]]:
    """The entries :mod:`tabletop.kiosk.actions` watches, one per configured action of
    ``character`` (``character``, ``action``, ``why``: why its files cannot be followed or
    None, ``read``: their signature before they were read, ``files``): those of the ``bad``
    ones (:func:`configured_actions`'s third), which the character starts without, and all of
    them (the same entries for the bad ones)."""
    gone = {a["name"]: dict(character=character, action=a, why=why, read=read,
                            files=action_files(a, base)) for a, why, read in bad}
    every = [gone.get(a["name"]) or dict(character=character, action=a, why=None,
                                         read=signed.get(a["name"], ()),
                                         files=action_files(a, base))
             for a in character["actions"]]
    return list(gone.values()), every


def configured_actions(character: dict[str, Any], features: dict[str, tuple[str, ...]],
                       loader: MotionLoader, rate_hz: float, without: bool,
                       recorded: Any = None, signed: dict[str, tuple] | None = None
                       ) -> tuple[list[Action], dict[str, tuple[str, np.ndarray]],
                                  list[tuple[dict[str, Any], str, tuple]]]:
    """The actions the config gives ``character``, their templates (``{action: (performer,
    samples at rate_hz)}``; ``features``: each performer's feature columns), and each action
    whose clip or template cannot be read: (the action, why, the signature of its
    :func:`action_files` taken before they were read). With ``without`` (a kiosk's start, or
    the replay of one) the character starts without such actions, each named with its file
    (and line): a kiosk restarted for ever on a corrupt template, its last good config naming
    the same file; the kiosk follows them once fixed (:mod:`tabletop.kiosk.actions`).
    Otherwise the first is raised (MopError naming the action, or the file's).
    ``recorded``: the replay of a kiosk's start, the engine's ``started_without`` text (these
    messages, joined by "; "): the character starts without exactly the actions it names,
    else MopError names both sets (a carried file missing or damaged: the replay would differ
    from the run). ``signed``, when given, receives each action's signature (by name), taken
    before it was read (:func:`action_entries`)."""
    actions, tmpl, missing = [], {}, []
    for a in character["actions"]:
        read = tuple(map(tree_signature, action_files(a, loader.base))) \
            if without or signed is not None else ()
        if signed is not None:
            signed[a["name"]] = read
        try:
            action, performer, samples = configured_action(character, a, features, loader,
                                                           rate_hz, check_rig=without)
        except InputError as exc:
            why = f"{_action_named(character['name'], a['name'])}: {exc}"
            if not without:
                raise (MopError(why) if isinstance(exc, ClipError) else exc) from None
            log.error("MOP character starts without the action until the file is fixed: %s",
                      why)
            missing.append((a, why, read))
            continue
        actions.append(action)
        tmpl[a["name"]] = (performer, samples)
    if isinstance(recorded, str):           # (a recording's header may hold anything)
        unread = [a["name"] for a, _, _ in missing]
        was = [a["name"] for a in character["actions"]
               if _names_action(recorded, _action_named(character["name"], a["name"]))]
        if sorted(was) != sorted(unread):
            def named(names: list[str]) -> str:
                return ", ".join(repr(n) for n in sorted(names)) or "nothing"
            raise MopError(f"character {character['name']!r}: the recording started without "
                           f"{named(was)}, but this replay could not read {named(unread)}")
    return actions, tmpl, missing


def _action_named(character: str, action: str) -> str:
    """An action as a start's messages name it (a recording's ``started_without`` holds them)."""
    return f"character {character!r}, action {action!r}"


def _names_action(recorded: str, named: str) -> bool:
    """Does a recording's ``started_without`` text (a start's messages joined by "; ") hold a
    message about the action ``named`` (:func:`_action_named`)? Matched in the whole text, not
    split on "; ": a name may hold "; " itself."""
    return recorded.startswith(f"{named}: ") or f"; {named}: " in recorded


def twin_of(action: tuple, before: list[tuple]) -> str:
    """Why ``action`` (name, performer, samples, template file) of a character cannot play
    when an earlier one of it (``before``, to which it is added) holds the same samples for
    the same performer: the follower takes them as one action and the later one never plays
    (a bird given "wave2" on wave.csv for another motion: 0 of 2,227 ticks); else ""."""
    name, performer, x, path = action
    twin = next((b for b in before if b[1] == performer and b[2].shape == x.shape
                 and np.array_equal(b[2], x)), None)
    before.append(action)
    if twin is None:
        return ""
    same = ("the same template as" if str(twin[3]) == str(path)
            else f"{path} holds the same samples as the template of")
    return (f"{same} action {twin[0]!r} ({twin[3]}): the follower cannot tell them apart, so "
            f"{name!r} would never play; give it a gesture of its own")
