"""pytest's rewritten byte-code of every test module, written ahead of a parallel run
(``python -m tests.rewritten``, what ``make test`` does before pytest).

Every xdist worker imports every test module, and pytest rewrites each one's asserts on
import (about 6 of a worker's 9.5 CPU seconds of collection) unless its cached rewrite is
there; the workers start together, so without this none finds it (and none writes it where
``PYTHONDONTWRITEBYTECODE`` is set). Here the files are rewritten once, on every core, into
the cache pytest itself reads (``__pycache__/NAME.cpython-3X-pytest-V.pyc``, checked against
the source's hash). It uses pytest's own rewriting functions, which are not public: where they
are missing or fail, nothing is written and the run only collects more slowly.
"""

from __future__ import annotations

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


def write(path: str) -> bool:
    """Rewrite one file and write its cached byte-code; False where pytest's functions are
    missing or the file cannot be rewritten or written."""
    try:
        from _pytest.assertion import rewrite
        fn = Path(path)
        source_hash, code = rewrite._rewrite_test(fn, None)
        cache = rewrite.get_cache_dir(fn)
        cache.mkdir(exist_ok=True)
        return rewrite._write_pyc(_Quiet(), code, source_hash,
                                  cache / (fn.name[:-3] + rewrite.PYC_TAIL))
    except Exception:   # an optimisation only: pytest rewrites the file itself on import
        return False


def main() -> int:
    files = [str(p) for p in files_rewritten()]
    with ProcessPoolExecutor(os.cpu_count() or 1) as pool:
        done = sum(pool.map(write, files, chunksize=8))
    if done < len(files):
        print(f"tests.rewritten: {len(files) - done} of {len(files)} test files not "
              "pre-rewritten (pytest rewrites them itself)", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
