"""Byte-code compiled once per machine: the environment's packages and the project's modules
get their ``.pyc`` files from a cache of compiled code shared by every copy of the project
(:data:`SHARED`, ``~/.cache/tabletop/bytecode``), keyed by the contents of each source.

Every process imports byte-code, never compiling a module it imports (the machines set
``PYTHONDONTWRITEBYTECODE``, so a module left uncompiled is compiled again by every process
that imports it): ``make`` compiles the environment after each install step and the project
before the tests (``python -m tabletop.bytecode_cache FOLDER...``, what ``compileall`` did).
A fresh clone (CI's: each run is one) compiled its new environment's 3,571 modules, about 20
CPU s; the same packages' sources give the same code, which is now compiled only where a
source's contents are new to the machine. A cached module is written as ``compileall`` writes
it (a timestamp ``.pyc`` of its own file's time and size, that the interpreter checks as ever;
the file name stored in the code is set to the module's own as it is imported). An entry is
marked used at each use; one unused for :data:`MIN_AGE_S` is removed.
"""

from __future__ import annotations

import functools
import hashlib
import importlib.util
import marshal
import os
import re
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from typing import Iterable, Iterator

#: The shared cache: one folder per interpreter's byte-code (its magic number, the
#: optimisation level), one file per source's contents (marshalled code).
SHARED = os.path.join(os.environ.get("XDG_CACHE_HOME") or os.path.expanduser("~/.cache"),
                      "tabletop", "bytecode",
                      f"{importlib.util.MAGIC_NUMBER.hex()}-o{sys.flags.optimize}")
MIN_AGE_S = 7 * 86400.0     # an entry not used for this long (s) is removed
_TMP = ".tmp-"              # a file being written (renamed into place when whole)
_MARK_S = 86400.0           # an entry used is marked so (its time) if last marked before this
_FOLDERS: set[str] = set()  # the folders made (or found) by this process


def key(source: bytes, kind: str = "") -> str:
    """The cache's name of ``source`` compiled as ``kind`` ("" plain compile)."""
    return hashlib.sha256(kind.encode() + b"\0" + source).hexdigest()[:40]


def fetch(name: str, root: str | None = None) -> bytes | None:
    """The cached marshalled code ``name`` in ``root`` (:data:`SHARED`), marked used; or
    None."""
    path = os.path.join(root or SHARED, name)
    try:
        with open(path, "rb") as f:
            data = f.read()
            if os.fstat(f.fileno()).st_mtime < time.time() - _MARK_S:
                os.utime(path)
    except OSError:
        return None
    return data


def store(name: str, data: bytes, root: str | None = None) -> None:
    """``data`` cached as ``name`` in ``root`` (:data:`SHARED`): whole or not at all, nothing
    where it cannot be written."""
    write_whole(os.path.join(root or SHARED, name), data)


def write_whole(path: str, data: bytes) -> bool:
    """``data`` written to ``path`` through a temporary file renamed into place: a reader finds
    the whole file or none. False where it cannot be written."""
    folder = os.path.dirname(path)
    tmp = os.path.join(folder, f"{_TMP}{os.getpid()}-{os.path.basename(path)}")
    try:
        if folder not in _FOLDERS:
            os.makedirs(folder, exist_ok=True)
            _FOLDERS.add(folder)
        with open(tmp, "wb") as f:
            f.write(data)
        os.replace(tmp, path)
    except OSError:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        return False
    return True


def _header(st: os.stat_result) -> bytes:
    """A timestamp ``.pyc`` header for a source of ``st`` (as py_compile writes it)."""
    return (importlib.util.MAGIC_NUMBER + b"\0\0\0\0"
            + (int(st.st_mtime) & 0xFFFFFFFF).to_bytes(4, "little")
            + (st.st_size & 0xFFFFFFFF).to_bytes(4, "little"))


def compile_one(path: str, root: str | None = None) -> str:
    """``path``'s ``.pyc`` written unless current, through the cache ``root``: "current",
    "cached", "compiled", or "failed" (a source that does not compile, or a folder that cannot
    be written, as compileall skips it)."""
    pyc = importlib.util.cache_from_source(path)
    try:
        st = os.stat(path)
        with open(pyc, "rb") as f:
            if f.read(16) == _header(st):
                return "current"
    except OSError:
        pass
    try:
        with open(path, "rb") as f:
            source = f.read()
        st = os.stat(path)
    except OSError:
        return "failed"
    name = key(source)
    data = fetch(name, root)
    outcome = "cached"
    if data is None:
        try:
            data = marshal.dumps(compile(source, path, "exec", dont_inherit=True))
        except (SyntaxError, ValueError):
            return "failed"
        store(name, data, root)
        outcome = "compiled"
    return outcome if write_whole(pyc, _header(st) + data) else "failed"


def sources(folders: Iterable[str], exclude: str | None = None) -> Iterator[str]:
    """The ``.py`` files under ``folders`` whose path ``exclude`` (a regular expression) does
    not match, as compileall's ``-x``."""
    skip = re.compile(exclude) if exclude else None
    for folder in folders:
        for top, dirs, names in os.walk(folder):
            dirs[:] = sorted(d for d in dirs if d != "__pycache__")
            for n in sorted(names):
                path = os.path.join(top, n)
                if n.endswith(".py") and not (skip and skip.search(path)):
                    yield path


def prune(root: str | None = None, min_age_s: float = MIN_AGE_S) -> int:
    """Entries of ``root`` unused for ``min_age_s`` removed (and temporary files as old): how
    many."""
    cut, gone = time.time() - min_age_s, 0
    try:
        entries = list(os.scandir(root or SHARED))
    except OSError:
        return 0
    for e in entries:
        try:
            if e.stat().st_mtime < cut:
                os.unlink(e.path)
                gone += 1
        except OSError:
            pass
    return gone


def compile_all(folders: Iterable[str], exclude: str | None = None, root: str | None = None,
                workers: int | None = None) -> dict[str, int]:
    """Every source under ``folders`` (see :func:`sources`) given its current ``.pyc``, on
    every core: how many were current, cached, compiled and failed."""
    paths = list(sources(folders, exclude))
    counts = dict.fromkeys(("current", "cached", "compiled", "failed"), 0)
    with ProcessPoolExecutor(workers or os.cpu_count() or 1) as pool:
        for outcome in pool.map(functools.partial(compile_one, root=root), paths, chunksize=64):
            counts[outcome] += 1
    return counts


def main(argv: list[str]) -> int:
    """``python -m tabletop.bytecode_cache [-x REGEX] FOLDER...``."""
    exclude = None
    if argv[:1] == ["-x"]:
        exclude, argv = argv[1], argv[2:]
    compile_all(argv, exclude)
    prune()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
