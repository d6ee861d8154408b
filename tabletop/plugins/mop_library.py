"""The MOP designer's library of kept actions: ``<library>/<character>/actions.yaml`` (each
kept take's name, template CSV and motion, and the follower's window the studio set) beside
each take's template CSV, read at an engine's start and written atomically, under a lock, at
a keep."""

from __future__ import annotations

from pathlib import Path
from typing import Any, Collection, ContextManager, Mapping

import numpy as np

from behaviors.mop.puppetry import Action
from tabletop.files import (MAX_DESCRIPTION_BYTES, NameTaken, UnreadableText, atomic_write_text,
                            parse_yaml, read_text_within, write_csv)
from tabletop.frames import InputError
from tabletop.plugins.mop_files import MopError, MotionLoader, load_template, twin_of
from tabletop.swap import exclusive

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
                    file: ActionsFile | None = None, performer: str = ""
                    ) -> tuple[list[tuple[Action, np.ndarray]], list[str]]:
    """The kept actions of ``character`` in the library ``folder`` (each with its template at
    ``rate_hz``), and one message per bad file or entry: skipped, the others load. An entry
    without a name, with the name of an earlier entry or of an action the config gives the
    character (``configured``) is bad, skipped and named with its file rather than stopping the
    engine's start or silently replacing the earlier entry's action (a repeated name) or the
    configured action (a configured one). So is one whose template holds the samples of a
    configured action's or an earlier entry's (:func:`~tabletop.plugins.mop_files.twin_of`),
    as the config's own twins are refused: the follower took the two as one and the entry
    never played, without a word (an entry "round" on the config's circle.csv: a circle
    performed, 121 ticks, drove the configured circle 86, "round" none).
    ``configured`` maps each configured action's name to (its performer, its samples, its
    template file) for that check (:func:`configured_templates`); ``performer``: the
    character's, which its kept actions follow. ``file``: its actions.yaml as already read."""
    try:
        entries = (file or ActionsFile(folder, character)).entries()
    except MopError as exc:
        return [], [str(exc)]
    out, problems = [], []
    seen: set[str] = set()
    before = [(n, *v) for n, v in configured.items()] if isinstance(configured, Mapping) else []
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
            path = p if p.is_absolute() else folder / character / p
            samples = load_template(path, names, rate_hz)
            clip = loader(a["motion"])
            if loader.rig is not None:   # a clip the character cannot play (a face's for a
                loader.rig.check(clip)   # creature) stopped the engine's start
            twin = twin_of((a["name"], performer, samples, path), before)
            if twin:
                problems.append(f"{where}: {twin}")
                continue
            out.append((Action(a["name"], clip), samples))
            seen.add(a["name"])   # only a kept entry claims its name: a later fixed copy loads
        except InputError as exc:
            problems.append(f"{where}: {exc}")
    return out, problems


def configured_templates(character: dict[str, Any],
                         templates: Mapping[str, tuple[str, np.ndarray]]
                         ) -> dict[str, tuple[str, np.ndarray, Any]]:
    """Each action the config gives ``character`` (its config entry) that is followed
    (``templates``: action -> (performer, samples)): (its performer, its samples, its template
    file), for :func:`library_actions`' check of templates holding the same samples."""
    return {a["name"]: (*templates[a["name"]], a["template"]) for a in character["actions"]
            if a["name"] in templates}


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
    stage keeps the take under the next free name): nothing saved is written over. A keep
    whose actions.yaml cannot be written (a full disk) removes the CSV it wrote: left there, it
    was in no entry, took the take's name from every later keep and stayed for good."""
    d = folder / character
    with library_lock(folder, character):
        file = ActionsFile(folder, character)
        entries = file.entries()
        csv_name = f"{action}.csv"
        if action in library_names(folder, character, entries):
            raise NameTaken(f"{d}: {action!r} is in the library already; not written over")
        write_csv(d / csv_name, *template_table(samples, names, rate_hz))
        try:
            write_library(folder, character, entries + [{"name": action, "template": csv_name,
                                                         "motion": motion}],
                          window=file.window())
        except BaseException:
            (d / csv_name).unlink(missing_ok=True)
            raise
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
