"""Library folders as the studio changes them: renamed in place, deleted into
``<library>/.trash``, so that undo restores them."""

from __future__ import annotations

import os
import time
from pathlib import Path
from typing import Callable

from tabletop import library
from tabletop.files import fsync_folder
from tabletop.frames import InputError


def named_folder(folder: Path, base: Path | None = None) -> str:
    """``folder`` as the status line names it, with a trailing separator: relative to
    ``base`` (the config's folder, which the config's paths are relative to; the working folder
    when None) when it lies within it, else absolute. A replay, whose config's folder is a
    temporary one, names it as the run did."""
    rel = os.path.relpath(folder, base if base is not None else os.curdir)
    outside = Path(rel).parts[:1] == (os.pardir,)   # "..x" is a folder within base
    return os.path.join(str(folder) if outside else rel, "")


def not_config_named(folder: Path, named: dict[Path, str]) -> None:
    """InputError when ``folder`` is one the config names (``named``: resolved folder -> its
    key): renamed or deleted, the next start fails ("does not exist")."""
    key = named.get(folder.resolve())
    if key is not None:
        raise InputError(f"the config names {folder.name} ({key}), so the next start would "
                         "fail without it; change the config first")


def trash(folder: Path) -> Callable[[], None]:
    """Move ``folder`` into its library's ``.trash``; returns the function that puts it back
    (once: called again, as an undo that failed after it is, it does nothing)."""
    bin_ = folder.parent / ".trash"
    bin_.mkdir(exist_ok=True)
    dest = bin_ / f"{folder.name}.{time.time_ns()}"
    os.rename(folder, dest)
    fsync_folder(folder.parent)
    done = [False]

    def restore() -> None:
        if done[0]:
            return
        if folder.exists():
            raise InputError(f"{folder}: exists again; not restored over it")
        os.rename(dest, folder)
        done[0] = True
    return restore


def rename_folder(lib: Path, old: str, new: str, check: bool = True) -> None:
    """Rename ``lib/old`` to ``lib/new``; ``check``: ``new`` must be a usable name (an undo
    gives back the name a folder had, also one made by hand: "my lover")."""
    if check:
        library.check_name(new)
    if (lib / new).exists():
        raise InputError(f"{lib / new}: already exists")
    os.rename(lib / old, lib / new)
    fsync_folder(lib)
