"""The MOP engine's files: characters' motions, action templates and the designer's library of
kept actions (``<library>/<character>/actions.yaml`` beside each take's template CSV)."""

from __future__ import annotations

import json
import logging
from pathlib import Path
from typing import Any, Collection, ContextManager

import numpy as np

from behaviors.motion.clips import Clip, ClipError, clip_from_mapping
from behaviors.mop.puppetry import Action
from tabletop.files import (FileFormatError, atomic_write_text, check_increasing, check_positions,
                            parse_yaml, read_csv_lines, write_csv)
from tabletop.frames import MAX_FEATURE, InputError
from tabletop.files import (MAX_CLIP_BYTES, MAX_DESCRIPTION_BYTES, MAX_TEMPLATE_BYTES, NameTaken,
                            UnreadableText, json_loads, read_text_within)
from tabletop.swap import exclusive

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
                clip = {"creature": creature_clips, "face": face_clips,
                        "hybrid": hybrid_clips}[self.kind]()[what]
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


def load_template(path: Path, names: tuple[str, ...], rate_hz: float) -> np.ndarray:
    """A template (n x d) with the performer's feature columns, resampled to ``rate_hz`` when it
    has a ``t`` column. Raises FileFormatError naming the file."""
    header, data, lines = read_csv_lines(path, what="template CSV", min_rows=2,
                                         max_bytes=MAX_TEMPLATE_BYTES)
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
    samples = load_template(Path(action["template"]), features[performer], rate_hz)
    return (Action(action["name"], clip, TimeWarp(action["warp"]) if action.get("warp")
                   else TimeWarp()), performer, samples)


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
    from tabletop.kiosk.watch import tree_signature
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


def check_shared_library(options: dict[str, Any], ctx: Any) -> None:
    """An engine listed earlier keeping actions in the same library may not have a character
    of the same name: both kept takes as ``<library>/<character>/take1.csv`` (the later keep
    wrote over the earlier) and each loaded the other's actions with its own performer."""
    engines, names, mine = ctx.engines(options)
    if options["library"] is None or mine == len(names):
        return
    lib = Path(options["library"]).resolve()
    for i, e in enumerate(engines[:mine]):
        if e.get("kind") != "mop" or e.get("library") is None \
                or Path(e["library"]).resolve() != lib:
            continue
        common = sorted({c["name"] for c in options["characters"]}
                        & {c["name"] for c in e["characters"]})
        if common:
            raise MopError(f"{ctx.where(options, 'library')}: engines[{i}] ({e['name']!r}) "
                           f"keeps its actions there too and has a character {common[0]!r} as "
                           "well; give one of them another library")


def _action_named(character: str, action: str) -> str:
    """An action as a start's messages name it (a recording's ``started_without`` holds them)."""
    return f"character {character!r}, action {action!r}"


def _names_action(recorded: str, named: str) -> bool:
    """Does a recording's ``started_without`` text (a start's messages joined by "; ") hold a
    message about the action ``named`` (:func:`_action_named`)? Matched in the whole text, not
    split on "; ": a name may hold "; " itself."""
    return recorded.startswith(f"{named}: ") or f"; {named}: " in recorded


# --- the designer's library ----------------------------------------------------------------------

LIBRARY_FILE = "actions.yaml"


class ActionsFile:
    """``<folder>/<character>/actions.yaml`` parsed once: its kept actions (:meth:`entries`) and
    the follower's window the studio saved (:meth:`window`) come from the one parse, at an
    engine's start and at a keep alike (two parses could give the window of one version and
    the entries of another when a keep lands between them)."""

    def __init__(self, folder: Path, character: str) -> None:
        self.path = folder / character / LIBRARY_FILE
        self._data: Any = None
        self._error: str | None = None      # why the file cannot be read
        if not self.path.is_file():
            return
        try:   # a syntax error in one line naming its place (it printed PyYAML's four)
            text = read_text_within(self.path, MAX_DESCRIPTION_BYTES, LIBRARY_FILE, MopError)
            self._data = parse_yaml(text, self.path, MopError,
                                    "cannot read the action library: YAML syntax error")
        except MopError as exc:
            self._error = str(exc)
        except (OSError, UnreadableText) as exc:
            self._error = f"{self.path}: cannot read the action library: {exc}"

    def entries(self) -> list[dict[str, str]]:
        """Kept actions: ``[{name, template, motion}]`` (none when the file does not exist). A
        corrupt file is refused with a message naming it (and is never overwritten: a keep is
        refused; the engine starts without that character's kept actions, see
        :func:`library_actions`)."""
        if self._error is not None:
            raise MopError(self._error)
        data = self._data
        if data is None:
            return []
        if not (isinstance(data, dict) and isinstance(data.get("actions"), list)):
            raise MopError(f"{self.path}: expected 'actions:' followed by a list of "
                           "{name, template, motion}")
        for i, a in enumerate(data["actions"]):
            why = _entry_fault(a)
            if why:
                named = f" ({a['name']})" if isinstance(a, dict) and isinstance(
                    a.get("name"), str) else ""
                raise MopError(f"{self.path}: actions[{i}]{named}: {why}; each action is "
                               "{name, template, motion}")
        return data["actions"]

    def window(self) -> int | None:
        """The follower's window (states) the studio saved, None when the file has none or
        cannot be read (:meth:`entries` says why); one out of :data:`WINDOW_RANGE` or not an
        integer is refused naming the file."""
        lo, hi = WINDOW_RANGE
        w = self._data.get("window") if isinstance(self._data, dict) else None
        if w is None:
            return None
        if isinstance(w, bool) or not isinstance(w, int) or not lo <= w <= hi:
            raise MopError(f"{self.path}: window: expected a whole number of states in "
                           f"{lo}..{hi}, got {w!r}")
        return w


def _entry_fault(entry: Any) -> str:
    """What is wrong with one entry of an actions.yaml edited by hand, or "": the file said
    only "expected 'actions:' followed by a list of {name, template, motion}" for a key
    misspelt in one of them ("motoin"), leaving the designer to find which."""
    import difflib
    keys = ("name", "template", "motion")
    if not isinstance(entry, dict):
        return f"expected a mapping, got {entry!r}"
    for k in keys:
        if k not in entry:
            typo = difflib.get_close_matches(k, [str(x) for x in entry if x not in keys], n=1)
            return f"no {k!r}" + (f" ({typo[0]!r} misspelt?)" if typo else "")
        if not isinstance(entry[k], str):
            return f"{k!r} must be text, got {entry[k]!r}"
    return ""


def read_library(folder: Path, character: str) -> list[dict[str, str]]:
    """Kept actions of ``character`` (:meth:`ActionsFile.entries`)."""
    return ActionsFile(folder, character).entries()


def library_actions(folder: Path, character: str, names: tuple[str, ...], rate_hz: float,
                    loader: MotionLoader, configured: Collection[str] = (),
                    file: ActionsFile | None = None
                    ) -> tuple[list[tuple[Action, np.ndarray]], list[str]]:
    """The kept actions of ``character`` in the library ``folder`` (each with its template at
    ``rate_hz``), and one message per bad file or entry: skipped, the others load. An entry
    without a name, with the name of an earlier entry or of an action the config gives the
    character (``configured``) is bad, skipped and named with its file rather than stopping the
    engine's start or silently replacing the earlier entry's action (a repeated name) or the
    configured action (a configured one). ``file``: its actions.yaml as already read."""
    try:
        entries = (file or ActionsFile(folder, character)).entries()
    except MopError as exc:
        return [], [str(exc)]
    out, problems = [], []
    seen: set[str] = set()
    for a in entries:
        p = Path(a["template"])
        where = f"{folder / character / LIBRARY_FILE}: action {a['name']!r}"
        why = ("needs a name" if not a["name"].strip() else
               "is named twice in the library; the first is kept" if a["name"] in seen else
               "has the name of an action the config gives the character" if a["name"] in configured
               else "")
        if why:
            problems.append(f"{where} {why}")
            continue
        try:
            samples = load_template(p if p.is_absolute() else folder / character / p, names,
                                    rate_hz)
            clip = loader(a["motion"])
            if loader.rig is not None:   # a clip the character cannot play (a face's for a
                loader.rig.check(clip)   # creature) stopped the engine's start
            out.append((Action(a["name"], clip), samples))
            seen.add(a["name"])   # only a kept entry claims its name: a later fixed copy loads
        except InputError as exc:
            problems.append(f"{where}: {exc}")
    return out, problems


def library_names(folder: Path, character: str,
                  entries: list[dict[str, str]] | None = None) -> set[str]:
    """Every name ``character``'s library folder holds, loaded or not: its entries' names (when
    actions.yaml reads; ``entries``: as already read) and the stems of its files (a template
    skipped at load as corrupt, or one no entry names, is still someone's data). A new take is
    named none of them."""
    d = folder / character
    names = {p.stem for p in d.iterdir()} if d.is_dir() else set()
    try:
        names |= {a["name"] for a in (read_library(folder, character) if entries is None
                                      else entries)}
    except MopError:
        pass                        # (a keep is refused while actions.yaml is corrupt)
    return names


def template_table(samples: np.ndarray, names: tuple[str, ...], rate_hz: float
                   ) -> tuple[tuple[str, ...], list[list[float]]]:
    """A template CSV's header and rows: ``t`` (s, from 0 at ``rate_hz``) and the performer's
    feature columns ``names``, as a kept take is saved and :func:`load_template` reads."""
    t = np.arange(len(samples)) / rate_hz
    return ("t",) + tuple(names), np.column_stack([t, samples]).tolist()


def save_to_library(folder: Path, character: str, action: str, samples: np.ndarray,
                    names: tuple[str, ...], motion: str, rate_hz: float) -> str:
    """Write a kept take: its template CSV (with ``t``) and its entry in actions.yaml, both
    atomically. Returns a short message for the operator. A name the library holds already
    (an entry, or a file, e.g. a template skipped at load) is refused (:class:`NameTaken`: the
    stage keeps the take under the next free name): nothing saved is written over."""
    d = folder / character
    with library_lock(folder, character):
        file = ActionsFile(folder, character)
        entries = file.entries()
        csv_name = f"{action}.csv"
        if action in library_names(folder, character, entries):
            raise NameTaken(f"{d}: {action!r} is in the library already; not written over")
        write_csv(d / csv_name, *template_table(samples, names, rate_hz))
        write_library(folder, character, entries + [{"name": action, "template": csv_name,
                                                     "motion": motion}], window=file.window())
    return f"kept {action} -> {motion} in {d}"


LIBRARY_WAIT_S = 2.0    # longest wait for another run's save into a library (s)


def library_lock(folder: Path, character: str) -> ContextManager[None]:
    """The lock of ``character``'s actions.yaml, held while it is read, changed and written:
    without it two runs keeping into one library at once each write the entries they read and
    lose the other's keeps (37 of 80 in two processes keeping 40 takes each). Taken in the
    frame loop's thread (K, F2, Del, U): a holder stalled for :data:`LIBRARY_WAIT_S` gets
    InputError (the take stays, to be kept again) rather than a frozen installation."""
    d = folder / character
    d.mkdir(parents=True, exist_ok=True)
    return exclusive(d / LIBRARY_FILE, wait_s=LIBRARY_WAIT_S)


#: The follower's window (p, states either side of the progress) a config, the studio or a
#: character's actions.yaml may set.
WINDOW_RANGE = (1, 10_000)


def write_library(folder: Path, character: str, entries: list[dict[str, str]],
                  window: int | None | type[Ellipsis] = ...) -> None:
    """Write ``character``'s actions.yaml atomically (its :func:`library_lock` held), with the
    follower's ``window`` the studio set (``...``: the one the file has; None: none)."""
    import yaml
    if window is ...:
        window = ActionsFile(folder, character).window()
    data: dict = {"actions": entries}
    if window is not None:
        data["window"] = int(window)
    atomic_write_text(folder / character / LIBRARY_FILE, yaml.safe_dump(data, sort_keys=False))
