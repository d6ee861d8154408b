"""How the Puppet Master's compiled kernels are built (numba): no fast-math (each value's
arithmetic is fixed, so a kernel gives the Python definition's bits), the interpreter lock
released, the machine code cached beside the source so that neither the installation's start
nor a test worker compiles it (``make kernels`` builds the caches).

numba's cache checks only a function's own file, yet a compiled function it calls from another
file is built into it: after that file changed, the cache would keep the old callee.
:func:`compiled` also keeps the stamps of the named modules' files in the cache's index, so a
change to any of them rebuilds the caller (tests/puppet_master/test_pm_kernels.py).
"""

from __future__ import annotations

import hashlib
from types import ModuleType
from typing import Any, Callable

import numba


def source_stamp(module: ModuleType) -> str:
    """SHA-256 of a module's source file."""
    with open(module.__file__, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def compiled(signature: Any, *calls_into: ModuleType) -> Callable[[Callable], Any]:
    """``numba.njit(signature, cache=True, nogil=True)``, its cache also kept fresh against
    the source files of ``calls_into``: every module whose compiled functions it calls,
    directly or through another (numba 0.68's cache index: the stamp it compares)."""
    def build(fn: Callable) -> Any:
        dispatcher = numba.njit(cache=True, nogil=True)(fn)
        if calls_into:
            index = dispatcher._cache._cache_file
            index._source_stamp = (index._source_stamp,
                                   *(source_stamp(m) for m in calls_into))
        dispatcher.compile(signature)
        dispatcher.disable_compile()
        return dispatcher
    return build
