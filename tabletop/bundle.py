"""Self-contained configs for recordings: the config as written plus every file it refers to.

A session recording's header carries ``config`` (the config mapping as written, which validates
again) and ``files`` (the content of every file and folder it names: behaviours, templates,
gestures, clips, sprites, calibrations). Paths written relative to the config's folder keep their
names; a path outside it (absolute, or with ``..``) is renamed ``_external/N/NAME`` in the
config. To replay, :func:`extract` writes the files into an empty folder and the config is
validated there, so a recording replays on another machine, from any folder.

Output folders (the recorder's, the snapshots') are not embedded; one outside the config's
folder is renamed ``_outside/N/NAME``, so what a replay writes goes into the replay's temporary
folder, never where the installation wrote. A designer's library is embedded (the studio lists
it and names kept takes after what it holds), and one that does not exist yet is renamed the same
way, so a take kept during the replay never lands in the installation's library. A file larger than
:data:`FILE_LIMIT` (or beyond :data:`TOTAL_LIMIT` in all), such as a camera's video file, is not
embedded either: the config keeps its absolute path and the header lists it under ``external``.
"""

from __future__ import annotations

import base64
import hashlib
import logging
from pathlib import Path, PurePosixPath
from typing import Any

from tabletop.frames import InputError
from tabletop.schema import FileRef

log = logging.getLogger("tabletop")

FILE_LIMIT = 16 * 2**20     # bytes: a larger file is referred to, not embedded
TOTAL_LIMIT = 64 * 2**20    # bytes embedded in one header at most
EXTERNAL = "_external"
OUTSIDE = "_outside"


class BundleError(InputError):
    """The embedded files of a recording are unusable (unsafe name, damaged content)."""


def _join(path: str, key: str) -> str:
    return f"{path}.{key}" if path else key


def rewrite(value: Any, changes: dict[str, str], path: str = "") -> Any:
    """``value`` (a parsed config) with the values at the key paths of ``changes`` replaced.
    Key paths are spelled as validation spells them (``engines[0].actions[1].template``)."""
    if path in changes:
        return changes[path]
    if isinstance(value, dict):
        return {str(k): rewrite(v, changes, _join(path, str(k))) for k, v in value.items()}
    if isinstance(value, list):
        return [rewrite(v, changes, f"{path}[{i}]") for i, v in enumerate(value)]
    return value


def _inside_name(value: str) -> str | None:
    """The bundle name of a path written relative to the config's folder, or None when it
    leaves that folder (absolute, ``~``, ``..``)."""
    text = value.replace("\\", "/")
    pure = PurePosixPath(text)
    if pure.is_absolute() or text.startswith("~") or ".." in pure.parts or not pure.parts:
        return None
    if pure.parts[0] in (EXTERNAL, OUTSIDE):
        return None
    return pure.as_posix()


def _entries(root: Path, name: str) -> list[tuple[str, Path]]:
    """(bundle name, file) for a file, or for every file under a folder (sorted) but hidden
    ones: a library's ``.trash`` (five deleted behaviours made a header 0.85 MB larger, in
    every recording, and counted towards :data:`TOTAL_LIMIT`) and unfinished atomic writes."""
    if root.is_file():
        return [(name, root)]
    out = []
    for f in sorted(root.rglob("*")):
        inside = f.relative_to(root)
        if f.is_file() and not any(part.startswith(".") for part in inside.parts):
            out.append((f"{name}/{inside.as_posix()}", f))
    return out


def _encode(data: bytes) -> dict[str, str]:
    entry = {"sha256": hashlib.sha256(data).hexdigest()}
    try:
        entry["text"] = data.decode("utf-8")
    except UnicodeDecodeError:
        entry["base64"] = base64.b64encode(data).decode("ascii")
    return entry


def _decode(name: str, entry: Any) -> bytes:
    if not isinstance(entry, dict):
        raise BundleError(f"files: {name}: expected a mapping with text or base64")
    try:
        if "text" in entry:
            data = str(entry["text"]).encode("utf-8")
        else:
            data = base64.b64decode(str(entry["base64"]), validate=True)
    except (KeyError, ValueError) as exc:
        raise BundleError(f"files: {name}: damaged content ({exc})") from None
    if "sha256" in entry and hashlib.sha256(data).hexdigest() != entry["sha256"]:
        raise BundleError(f"files: {name}: damaged content (checksum differs)")
    return data


def portable(raw: Any, refs: list[FileRef]) -> tuple[Any, dict[str, dict], list[str]]:
    """(config as written with paths renamed into the bundle, embedded files, key paths of
    files left outside it). ``refs`` come from validating ``raw``."""
    changes: dict[str, str] = {}
    files: dict[str, dict] = {}
    names: dict[Path, str] = {}
    external: list[str] = []
    total = 0
    for ref in refs:
        if not ref.embed:
            # An output folder (a designer's library, snapshots): a replay writes into its own
            # temporary folder, never where the live installation wrote.
            if _inside_name(ref.value) is None:
                changes[ref.key] = f"{OUTSIDE}/{len(changes)}/{ref.resolved.name or 'root'}"
            continue
        if not ref.resolved.exists():
            if _inside_name(ref.value) is None:   # a library made later: never the live one
                changes[ref.key] = f"{OUTSIDE}/{len(changes)}/{ref.resolved.name or 'root'}"
            continue
        name = names.get(ref.resolved)
        if name is None:
            name = _inside_name(ref.value) or (
                f"{EXTERNAL}/{len(names)}/{ref.resolved.name or 'root'}")
            entries = _entries(ref.resolved, name)
            size = sum(f.stat().st_size for _, f in entries)
            if any(f.stat().st_size > FILE_LIMIT for _, f in entries) or total + size > TOTAL_LIMIT:
                log.warning("%s (%s, %.1f MB) is too large to embed in recordings; a replay "
                            "needs it at that path", ref.resolved, ref.key, size / 2**20)
                changes[ref.key] = str(ref.resolved)
                external.append(ref.key)
                continue
            for entry_name, f in entries:
                files[entry_name] = _encode(f.read_bytes())
            total += size
            names[ref.resolved] = name
        if name != ref.value:
            changes[ref.key] = name
    return rewrite(raw, changes), files, external


def _safe_name(name: Any) -> PurePosixPath:
    pure = PurePosixPath(str(name))
    if (not isinstance(name, str) or not name or pure.is_absolute() or ".." in pure.parts
            or "\\" in name or ":" in name):
        raise BundleError(f"files: {name!r} is not a safe relative file name")
    return pure


def extract(files: Any, folder: Path) -> None:
    """Write embedded ``files`` (from a header) under ``folder``; BundleError on a bad entry."""
    if files is None:
        return
    if not isinstance(files, dict):
        raise BundleError("files: expected a mapping of file names to contents")
    for name, entry in files.items():
        pure = _safe_name(name)
        data = _decode(name, entry)
        target = folder.joinpath(*pure.parts)
        try:
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_bytes(data)
        except OSError as exc:
            raise BundleError(f"files: {name}: cannot be written to {folder}: "
                              f"{exc.strerror or exc}") from None
