"""The behaviour library: one folder per behaviour, ``<library>/<name>/behavior.yaml`` beside its
demonstration CSV.

``behavior.yaml`` says what the behaviour is (``kind``), how to train it (``parameters``) and
which data files it uses (``data``); ``demonstration.csv`` has the header
``t,main_x,main_y,main_dir,react_x,react_y,react_dir`` (seconds, table metres, radians).

Saved behaviours are never half-written: a new behaviour is written into a hidden temporary
folder (every file fsynced) that is then renamed into place, and a replaced behaviour is
written whole beside the old one and swapped in by renames (:mod:`tabletop.swap`), so a kill at
any moment leaves the old behaviour or the new one, never the new demonstration beside the old
``behavior.yaml``; a read that a swap overtook is read again (:func:`load_behavior`). A corrupt
``behavior.yaml`` or CSV is refused with one message naming the file, the line or key, and what is
wrong, and it is never overwritten.
"""

from __future__ import annotations

import base64
import errno
import os
import re
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterable, Mapping

import numpy as np
import yaml

from tabletop.files import (MAX_DEMONSTRATION_BYTES, MAX_DESCRIPTION_BYTES, FileFormatError,
                            UnreadableText, atomic_write_text, check_increasing, check_positions,
                            folder_failure, format_csv, new_folder, read_csv_lines,
                            read_text_within, read_yaml)
from tabletop.frames import InputError
from tabletop.swap import MARKER, locked, real, recover, recover_all, replace_folder, saving
from tabletop.schema import (REQUIRED, ConfigError, Context, FilePath, Number, Record, Spec,
                             Str, yaml_number_hint)

BEHAVIOR_FILE = "behavior.yaml"
DEMONSTRATION_FILE = "demonstration.csv"
FORMAT = "tabletop-behavior"
VERSION = 1
COLUMNS = ("t", "main_x", "main_y", "main_dir", "react_x", "react_y", "react_dir")
POSITIONS = ("main_x", "main_y", "react_x", "react_y")   # table metres
KINDS = ("puppet_master",)
NAME_MAX = 64                                              # characters of a behaviour's name
NAME_RE = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]{0,63}$")


class LibraryError(InputError):
    """A behaviour folder or file is missing, corrupt or cannot be written; the message names it."""


class NameTakenError(LibraryError):
    """A behaviour of that name exists already (:func:`save_behavior` without ``replace``)."""


class _NumberMap(Spec):
    """A mapping of parameter names to numbers (the trainer checks names and ranges); every
    behavior.yaml has one (``{}``: the defaults), so a file cut short before it is refused."""

    default: Any = REQUIRED

    def describe(self) -> str:
        return "a mapping of parameter names to numbers"

    def validate(self, value: Any, path: str, ctx: Context) -> Any:
        if value is None:
            return {}
        if not isinstance(value, dict):
            raise self.wrong_type(value, path, ctx)
        out: dict[str, Any] = {}
        for k, v in value.items():
            if not isinstance(k, str):
                raise ctx.error(path, f"parameter name {k!r} is not a string")
            if isinstance(v, bool) or not isinstance(v, (int, float)) or v != v:
                raise ctx.error(f"{path}.{k}", f"expected a number, got {v!r}"
                                               f"{yaml_number_hint(v)}")
            out[k] = v
        return out


def _schema() -> Record:
    return Record({
        "format": Str(choices=[FORMAT]),
        "version": Number(integer=True, lo=VERSION, hi=VERSION),
        "kind": Str(choices=KINDS),
        "name": Str(""),
        "description": Str(""),
        "parameters": _NumberMap(),
        "data": Record({"demonstration": FilePath(DEMONSTRATION_FILE, kind="file")}),
        "samples": Number(0, integer=True, lo=0),
        "duration_s": Number(0.0, lo=0.0),
        "source": Str(""),
    })


@dataclass
class StoredBehavior:
    """A behaviour read from the library: its folder, what it is and its demonstration (n, 7),
    read from ``data_file`` (the file its behavior.yaml names, in the folder)."""

    folder: Path
    name: str
    kind: str
    parameters: dict[str, Any]
    demonstration: np.ndarray
    description: str = ""
    source: str = ""
    extra: dict[str, Any] = field(default_factory=dict)
    data_file: Path | None = None


def check_name(name: str) -> str:
    """Return ``name`` if it can name a behaviour folder, else raise LibraryError."""
    if not isinstance(name, str) or not NAME_RE.match(name) or name in (".", ".."):
        raise LibraryError(
            f"behaviour name {name!r} is not usable as a folder name: use 1-64 ASCII letters, "
            "digits, '_', '-' or '.', starting with a letter or digit")
    return name


def read_demonstration(path: str | Path) -> np.ndarray:
    """Read a demonstration CSV; returns (n, 7) in :data:`COLUMNS` order (extra columns ignored).

    Raises LibraryError naming the file and line for a missing file, a missing column, a value
    that is not a finite number, fewer than two rows, times that do not strictly increase or a
    position beyond ``frames.MAX_POSITION_M``.
    """
    try:
        header, data, lines = read_csv_lines(path, required=COLUMNS, what="demonstration",
                                             min_rows=2, max_bytes=MAX_DEMONSTRATION_BYTES)
        check_increasing(data[:, header.index("t")], path, lines=lines)
        check_positions(data, header, POSITIONS, path, lines=lines)
    except FileFormatError as exc:
        raise LibraryError(str(exc)) from None
    return data[:, [header.index(c) for c in COLUMNS]]


def demonstration_csv(demo: np.ndarray) -> str:
    """CSV text of a demonstration (n, 7) with the standard header, full precision."""
    a = np.asarray(demo, dtype=float)
    if a.ndim != 2 or a.shape[1] != len(COLUMNS):
        raise LibraryError(f"demonstration has shape {a.shape}, expected (rows, {len(COLUMNS)})")
    bad = np.argwhere(~np.isfinite(a))
    if bad.size:
        r, c = (int(i) for i in bad[0])
        raise LibraryError(f"demonstration row {r + 1} of {len(a)}: {COLUMNS[c]} is {a[r, c]}; "
                           "a demonstration with values that are not finite numbers is not saved")
    return format_csv(COLUMNS, a.tolist())


def recorded_source(name: str, params: Mapping[str, Any], demonstration: np.ndarray
                    ) -> dict[str, Any]:
    """What a behaviour was trained from as a recording keeps it (a hot reload's, replayed by
    :func:`tabletop.studio.reloader.trained_from`): its name, parameters and the
    demonstration's float64 bytes in base64."""
    demo = np.ascontiguousarray(demonstration, dtype="<f8")
    return {"name": name, "parameters": dict(params), "shape": list(demo.shape),
            "demonstration": base64.b64encode(demo.tobytes()).decode("ascii")}


def _read_yaml(path: Path) -> Any:
    return read_yaml(path, LibraryError, missing=f"not found (a behaviour folder needs a "
                     f"{BEHAVIOR_FILE})", problem="corrupt YAML",
                     max_bytes=MAX_DESCRIPTION_BYTES, kind=BEHAVIOR_FILE)


def read_description(folder: str | Path) -> dict[str, Any]:
    """Read and validate ``<folder>/behavior.yaml`` (not the data); returns it with defaults."""
    folder = Path(folder)
    if not folder.is_dir():
        raise LibraryError(f"{folder}: behaviour folder not found")
    path = folder / BEHAVIOR_FILE
    data = _read_yaml(path)
    if not isinstance(data, dict):
        raise LibraryError(f"{path}: expected a mapping with format, version, kind, parameters "
                           f"and data, got {type(data).__name__}")
    try:
        desc = _schema().validate(data, "", Context(file=str(path), base=folder.resolve()))
    except ConfigError as exc:
        raise LibraryError(str(exc)) from None
    _check_parameter_names(desc["parameters"], path)
    return desc


def parameter_refused(stored: StoredBehavior, exc: Exception,
                      overridden: tuple[str, ...] = ()) -> str | None:
    """Training's refusal ``exc`` of a parameter ``stored``'s behavior.yaml gives (not one of
    ``overridden``, set by the config), said at its key: ``FOLDER/behavior.yaml:
    parameters.NAME: ...``; None for any other refusal."""
    return refused_at_key(stored.folder, stored.parameters, exc, overridden)


def refused_at_key(folder: Path, parameters: Mapping[str, Any], exc: Exception,
                   overridden: Iterable[str] = ()) -> str | None:
    """:func:`parameter_refused` of the behaviour in ``folder`` whose behavior.yaml gives
    ``parameters``."""
    name = getattr(exc, "name", None)
    if name is None or name not in parameters or name in overridden:
        return None
    said = str(exc).removeprefix(f"behaviour parameter {name}: ")
    return f"{Path(folder) / BEHAVIOR_FILE}: parameters.{name}: {said}"


def _check_parameter_names(parameters: Mapping[str, Any], path: Path) -> None:
    """A parameter Puppet Master's training has not (a typo) refused at its key in
    behavior.yaml (training named the folder only)."""
    from dataclasses import fields

    from behaviors.puppet_master.params import Params, unknown_names
    known = sorted(f.name for f in fields(Params))
    for name in parameters:
        if name not in known:
            raise LibraryError(f"{path}: parameters.{unknown_names([name], set(known))}: "
                               f"unknown parameter (known: {', '.join(known)})")


def _data_file(folder: Path, value: str | Path, key: str) -> Path:
    p = Path(value)
    p = p if p.is_absolute() else folder / p
    if folder.resolve() not in p.resolve().parents:
        raise LibraryError(f"{folder / BEHAVIOR_FILE}: data.{key}: {str(value)!r} is outside the "
                           "behaviour folder; data files live beside behavior.yaml")
    return p


def _same(fd: int, folder: Path) -> bool:
    """Does ``folder`` still name the directory open as ``fd``? (Held open, its inode cannot
    be freed and given to a later version.)"""
    try:
        a, b = os.fstat(fd), os.stat(folder)
    except OSError:
        return False
    return (a.st_dev, a.st_ino) == (b.st_dev, b.st_ino)


def load_behavior(folder: str | Path, tries: int = 20) -> StoredBehavior:
    """Read a behaviour folder: its description and its demonstration, both of one version.

    A save swaps a whole new folder in (:func:`save_behavior`); a read it overtook (the folder
    held open at the start no longer the one named at the end, or missing while the save
    holds its lock) is read again, up to ``tries`` times, 10 ms apart while the folder is
    missing. An interrupted save is first recovered (logged). The folder is held open while it
    is read, so its inode cannot be freed and given to a later version and compared equal.
    A folder that cannot be opened is read by name only for the error that says why; if that
    read succeeds (the folder was put back meanwhile), the loop reads it again."""
    folder = Path(folder)
    recover(folder)
    for attempt in range(1, tries + 1):
        try:
            fd = os.open(folder, os.O_RDONLY | os.O_DIRECTORY)
        except OSError as exc:
            if exc.errno in (errno.EACCES, errno.EPERM) and folder.is_dir():
                # its files may read one by one (execute only), but it cannot be held open:
                # read by name alone, it looked changed by a save every time (20 tries)
                raise LibraryError(f"{folder}: behaviour folder cannot be opened "
                                   f"({exc.strerror}); it must be readable as a folder "
                                   f"(chmod a+rx)") from None
            if attempt < tries and saving(folder):
                time.sleep(0.01)
                continue
            _load(folder)                        # not found or not a folder: says which
            continue                             # (it reappeared: not known whole)
        try:
            try:
                stored = _load(folder)
            except LibraryError:
                if attempt == tries or _same(fd, folder):
                    raise
                continue
            if _same(fd, folder):
                return stored
        finally:
            os.close(fd)
    raise LibraryError(f"{folder}: changed while it was read, {tries} times; not loaded")


def _load(folder: Path) -> StoredBehavior:
    desc = read_description(folder)
    data_file = _data_file(folder, desc["data"]["demonstration"], "demonstration")
    demo = read_demonstration(data_file)
    if desc["samples"] and len(demo) != desc["samples"]:   # a file cut short at a whole number
        raise LibraryError(                                 # (e.g. "-2.") reads as whole
            f"{data_file}: {len(demo)} samples where {BEHAVIOR_FILE} says {desc['samples']}: "
            f"cut short? (edited by hand: set its samples to the rows, or remove the key)")
    return StoredBehavior(folder=folder, name=folder.name, kind=desc["kind"],
                          parameters=dict(desc["parameters"]), demonstration=demo,
                          description=desc["description"], source=desc["source"],
                          extra={"samples": desc["samples"], "duration_s": desc["duration_s"]},
                          data_file=data_file)


def describe_yaml(name: str, demo: np.ndarray, parameters: Mapping[str, Any],
                  kind: str = "puppet_master", description: str = "", source: str = "") -> str:
    """The text of a behavior.yaml for this behaviour (deterministic)."""
    a = np.asarray(demo, dtype=float)
    doc = {
        "format": FORMAT,
        "version": VERSION,
        "kind": kind,
        "name": name,
        "description": description,
        "parameters": {k: (float(v) if isinstance(v, (float, np.floating)) else int(v))
                       for k, v in parameters.items()},
        "data": {"demonstration": DEMONSTRATION_FILE},
        "samples": int(a.shape[0]),
        "duration_s": round(float(a[-1, 0] - a[0, 0]), 6) if a.shape[0] else 0.0,
        "source": source,
    }
    return yaml.safe_dump(doc, sort_keys=False, default_flow_style=False, allow_unicode=True)


def write_name(folder: str | Path, name: str) -> tuple[str, str] | None:
    """Set the ``name`` line of ``<folder>/behavior.yaml`` to ``name`` (written atomically),
    the rest of the file as it is (comments too). Loading names a behaviour by its folder; this
    keeps the file saying the same after a rename. A file without a top-level ``name`` line, or
    one that does not read as a mapping, is left untouched. Returns the text before and after
    (None: not written)."""
    path = Path(folder) / BEHAVIOR_FILE
    try:
        text = read_text_within(path, MAX_DESCRIPTION_BYTES, BEHAVIOR_FILE)
    except UnreadableText:   # not text, or larger than any behavior.yaml: not ours to edit
        return None
    line = yaml.safe_dump({"name": name}, default_flow_style=False, allow_unicode=True,
                          width=1000).rstrip("\n")
    new, n = re.subn(r"^name:[^\n]*$", lambda _: line, text, flags=re.MULTILINE)
    try:
        doc = yaml.safe_load(new)
    except yaml.YAMLError:
        return None
    if n != 1 or not isinstance(doc, dict) or doc.get("name") != name or new == text:
        return None
    atomic_write_text(path, new)
    return text, new


def save_behavior(library: str | Path, name: str, demo: np.ndarray,
                  parameters: Mapping[str, Any], kind: str = "puppet_master",
                  description: str = "", source: str = "", replace: bool = False) -> Path:
    """Save a behaviour as ``<library>/<name>/``; returns the folder.

    A new folder appears whole or not at all. With ``replace`` an existing behaviour is
    replaced whole (the new folder swapped in by renames, any other file it held copied along),
    but only if its ``behavior.yaml`` reads cleanly: a corrupt one is refused and left
    byte-identical. Without ``replace`` an existing folder is refused (see :func:`free_name`).
    Saves of one name, with or without ``replace``, run one at a time (:func:`swap.locked`); a
    folder named through a symbolic link is replaced at the link's target, the link kept."""
    check_name(name)
    if kind not in KINDS:
        raise LibraryError(f"behaviour kind {kind!r} is unknown (known: {', '.join(KINDS)})")
    csv_text = demonstration_csv(demo)
    yaml_text = describe_yaml(name, demo, parameters, kind, description, source)
    lib = Path(library)
    target = lib / name
    try:
        lib.mkdir(parents=True, exist_ok=True)
        if target.is_symlink():
            target = real(target)                  # the link is kept, its folder replaced
        with locked(target):                       # one save of a name at a time
            _save(target, csv_text, yaml_text, replace)
    except OSError as exc:
        raise LibraryError(f"{target}: cannot save behaviour: {folder_failure(target, exc)}") \
            from None
    return lib / name


def _save(target: Path, csv_text: str, yaml_text: str, replace: bool) -> None:
    """The body of :func:`save_behavior`, its lock held."""
    files = {DEMONSTRATION_FILE: csv_text, BEHAVIOR_FILE: yaml_text}
    if not target.exists():
        new_folder(target, files, marker=MARKER)
        return
    if not replace:
        raise NameTakenError(f"{target}: a behaviour of that name already exists")
    if (target / BEHAVIOR_FILE).exists():
        read_description(target)   # refuses (and keeps) a corrupt file
    elif any(target.iterdir()):
        raise LibraryError(f"{target}: folder holds files but no {BEHAVIOR_FILE}; "
                           "not a behaviour, left untouched")
    replace_folder(target, files)


def list_behaviors(library: str | Path) -> list[str]:
    """Names of the behaviour folders (those holding a behavior.yaml) in ``library``, sorted;
    LibraryError naming it if it cannot be listed."""
    lib = Path(library)
    if not lib.is_dir():
        return []
    recover_all(lib)
    try:
        entries = [p for p in lib.iterdir() if not p.name.startswith(".")]
    except OSError as exc:   # execute only: a behaviour named in a config still loads by name
        raise LibraryError(f"{lib}: the library folder cannot be listed ({exc.strerror}); its "
                           "behaviours are not offered: it must be readable as a folder "
                           "(chmod a+rx)") from None
    for p in entries:                  # a folder named through a link keeps its leftovers
        if p.is_symlink():             # beside its target
            recover(p)
    return sorted(p.name for p in entries if (p / BEHAVIOR_FILE).is_file())


def free_name(library: str | Path, name: str) -> str:
    """``name`` if ``<library>/<name>`` does not exist, else the first free ``name-2``,
    ``name-3``..., the name shortened to leave room for its number (a designer name of 64
    characters was kept once, and every later keep of it refused as too long)."""
    check_name(name)
    lib = Path(library)
    recover(lib / name)                  # an interrupted save's old version is put back first
    if not (lib / name).exists():
        return name
    i = 2
    while (lib / numbered(name, i)).exists():
        i += 1
    return check_name(numbered(name, i))


def save_new(library: str | Path, name: str, demo: np.ndarray, parameters: Mapping[str, Any],
             **description: str) -> Path:
    """Save a behaviour under ``name`` or the first free ``name-2``, ``name-3``... at the
    moment it is saved (a name taken meanwhile: the next); returns its folder. So two studios
    keeping one name in one library both keep their takes: a name looked up before the save
    can be taken by the other studio first, and the save refused ("already exists")."""
    for _ in range(1000):
        try:
            return save_behavior(library, free_name(library, name), demo, parameters,
                                 **description)
        except NameTakenError:
            continue                       # taken meanwhile by another saver: the next one
    raise LibraryError(f"{Path(library) / name}: no free name for it after 1000 tries")


def numbered(name: str, i: int) -> str:
    """``name-i`` within the longest name :data:`NAME_RE` takes (64 characters)."""
    suffix = f"-{i}"
    return name[:NAME_MAX - len(suffix)] + suffix
