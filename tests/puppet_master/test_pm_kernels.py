"""A compiled kernel that calls compiled functions of another file is rebuilt when that file
changes (behaviors/kernel_cache.compiled, as the Puppet Master's kernels are built): numba's own
cache checks only the kernel's file and would keep the old callee built into it."""

import importlib
import sys
import textwrap
from pathlib import Path

CALLEE = """
import numba
from behaviors.kernel_cache import compiled

@compiled(numba.float64(numba.float64))
def bump(x):
    return x + {amount}
"""

CALLER = """
import numba
import callee
from behaviors.kernel_cache import compiled

@compiled(numba.float64(numba.float64), {calls_into})
def twice_bumped(x):
    return 2.0 * callee.bump(x)
"""


def _run(folder: Path) -> float:
    """``caller.twice_bumped(1.0)`` of ``folder``'s files imported afresh, as a new process
    imports them: new dispatchers, each looking in its cache on disk (in a process of its own
    each run was 1.2-1.6 CPU s, numba's import 0.4 of it)."""
    importlib.invalidate_caches()
    sys.path.insert(0, str(folder))
    try:
        return float(importlib.import_module("caller").twice_bumped(1.0))
    finally:
        sys.path.remove(str(folder))
        for name in ("caller", "callee"):
            sys.modules.pop(name, None)


def _case(folder: Path, calls_into: str) -> tuple[float, float]:
    folder.mkdir()
    (folder / "caller.py").write_text(textwrap.dedent(CALLER.format(calls_into=calls_into)))
    (folder / "callee.py").write_text(textwrap.dedent(CALLEE.format(amount="1.0")))
    first = _run(folder)                       # built and cached
    (folder / "callee.py").write_text(textwrap.dedent(CALLEE.format(amount="2.0")))
    return first, _run(folder)                 # from the cache, or rebuilt


def test_a_kernel_is_rebuilt_when_a_file_it_calls_into_changes(tmp_path, monkeypatch):
    # no byte-code written: the edited callee has the old one's size and may keep its second
    monkeypatch.setattr(sys, "dont_write_bytecode", True)
    # (numba's cache alone gives 4.0 both times: the old callee stays built into the caller)
    assert _case(tmp_path / "named", "callee") == (4.0, 6.0)
