"""pytest's rewritten byte-code of every test module, written ahead of a parallel run
(``python -m tests.rewritten``, what ``make test`` does before pytest).

Every xdist worker imports every test module, and pytest rewrites each one's asserts on
import (about 6 of a worker's 9.5 CPU seconds of collection) unless its cached rewrite is
there; the workers start together, so without this none finds it (and none writes it where
``PYTHONDONTWRITEBYTECODE`` is set). Here the files are rewritten once, on every core, into
the cache pytest itself reads (``__pycache__/NAME.cpython-3X-pytest-V.pyc``, checked against
the source's hash). It uses pytest's own rewriting functions, which are not public: where they
are missing or fail, nothing is written and the run only collects more slowly.

The installed pytest plugins' modules (hypothesis, pytest-xdist: every package of a
distribution with a ``pytest11`` entry point) are rewritten here too: pytest rewrites them in
every process that imports them, and where ``PYTHONDONTWRITEBYTECODE`` is set none keeps its
rewrite, so each worker and the controller rewrote the 81 a collection imports (1.0 CPU s a
process; 0.25 s with them cached). Those already cached (their source unchanged) are left.
"""

from __future__ import annotations

import importlib.util
import os
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

HERE = Path(__file__).resolve().parent


class _Quiet:
    """The part of pytest's assertion state that writing a cached file uses."""

    @staticmethod
    def trace(*_args: object) -> None:
        pass


def files_rewritten(root: Path = HERE) -> list[Path]:
    """The files pytest rewrites here: every ``test_*.py`` and ``conftest.py`` (the project's
    ``python_files`` is pytest's default), in name order."""
    return sorted(p for p in root.rglob("*.py")
                  if (p.name.startswith("test_") or p.name == "conftest.py")
                  and "__pycache__" not in p.parts)


def plugin_files() -> list[Path]:
    """The installed pytest plugins' modules pytest rewrites as it imports them (the packages
    and modules ``_pytest.config`` marks for rewriting: those of every distribution with a
    ``pytest11`` entry point), less those whose cached rewrite is current; [] where pytest's
    functions are missing."""
    try:
        import importlib.metadata as metadata

        from _pytest.assertion import rewrite
        from _pytest.config import _iter_rewritable_modules
    except ImportError:
        return []
    out = []
    for dist in metadata.distributions():
        if not any(ep.group == "pytest11" for ep in dist.entry_points):
            continue
        names = set(_iter_rewritable_modules(str(f) for f in dist.files or ()))
        for f in dist.files or ():
            if f.suffix == ".py" and (f.parts[0] in names or Path(f).stem in names):
                fn = Path(dist.locate_file(f))
                pyc = rewrite.get_cache_dir(fn) / (fn.name[:-3] + rewrite.PYC_TAIL)
                if fn.is_file() and rewrite._read_pyc(fn, pyc, _Quiet.trace) is None:
                    out.append(fn)
    return sorted(out)


def write(path: str) -> bool:
    """Rewrite one file and write its cached byte-code; False where pytest's functions are
    missing or the file cannot be rewritten or written. The rewritten code is kept in the
    machine's cache of byte-code (tabletop/bytecode_cache.py), keyed by the source's contents
    and pytest's version: a fresh clone rewrote its 294 test modules, 10.6 CPU s, where only
    those changed since the machine last saw them are rewritten now."""
    try:
        import marshal

        import pytest
        from _pytest.assertion import rewrite

        from tabletop import bytecode_cache
        fn = Path(path)
        source = fn.read_bytes()
        name = bytecode_cache.key(source, f"pytest {pytest.__version__} rewrite")
        data = bytecode_cache.fetch(name)
        if data is not None:
            source_hash, code = importlib.util.source_hash(source), marshal.loads(data)
        else:
            source_hash, code = rewrite._rewrite_test(fn, None)
            bytecode_cache.store(name, marshal.dumps(code))
        cache = rewrite.get_cache_dir(fn)
        cache.mkdir(exist_ok=True)
        return rewrite._write_pyc(_Quiet(), code, source_hash,
                                  cache / (fn.name[:-3] + rewrite.PYC_TAIL))
    except Exception:   # an optimisation only: pytest rewrites the file itself on import
        return False


def main() -> int:
    files = [str(p) for p in files_rewritten()]
    plugins = [str(p) for p in plugin_files()]
    with ProcessPoolExecutor(os.cpu_count() or 1) as pool:
        done = list(pool.map(write, files + plugins, chunksize=8))
    if sum(done[:len(files)]) < len(files):
        print(f"tests.rewritten: {len(files) - sum(done[:len(files)])} of {len(files)} test "
              "files not pre-rewritten (pytest rewrites them itself)", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
