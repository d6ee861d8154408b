"""A compiled kernel that calls compiled functions of another file is rebuilt when that file
changes (behaviors/kernel_cache.compiled, as the Puppet Master's kernels are built): numba's own
cache checks only the kernel's file and would keep the old callee built into it."""

import subprocess
import sys
import textwrap
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

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
    code = f"import sys; sys.path[:0] = [{str(folder)!r}, {str(ROOT)!r}]; import caller; " \
           "print(caller.twice_bumped(1.0))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=120)
    assert out.returncode == 0, out.stderr
    return float(out.stdout.strip().splitlines()[-1])


def _case(folder: Path, calls_into: str) -> tuple[float, float]:
    folder.mkdir()
    (folder / "caller.py").write_text(textwrap.dedent(CALLER.format(calls_into=calls_into)))
    (folder / "callee.py").write_text(textwrap.dedent(CALLEE.format(amount="1.0")))
    first = _run(folder)                       # built and cached
    (folder / "callee.py").write_text(textwrap.dedent(CALLEE.format(amount="2.0")))
    return first, _run(folder)                 # from the cache, or rebuilt


def test_a_kernel_is_rebuilt_when_a_file_it_calls_into_changes(tmp_path):
    # (numba's cache alone gives 4.0 both times: the old callee stays built into the caller)
    assert _case(tmp_path / "named", "callee") == (4.0, 6.0)
