"""How the drawing's shape kernels are compiled (numba) and cached: one stamp for all their files.

numba caches a compiled function beside its source and trusts the cache while that one file is
unchanged, but a kernel compiles into itself every compiled function it calls, from other files
too: a figure's kernel holds its own copy of the limbs', discs' and polygons' code. With numba's
own stamp, a change to ``limbs.py`` would leave the figure drawn by the old limbs until
``character_kernel.py`` changed. Kernels made with :func:`kernel` are stamped with the contents of
every file in :data:`FILES` instead: a change to any of them compiles them all again (about 20 s
of CPU, once; ``make kernels`` does it). Everything else is numba's in-tree cache (or its
user-wide one where the package's ``__pycache__`` cannot be written), through numba's own
cache classes (``numba.core.caching``: the version is pinned in pyproject.toml;
``tests/tabletop/test_kernel_cache.py`` checks every kernel is stamped so).
"""

from __future__ import annotations

import functools
import hashlib
import os
from typing import Callable

import numba
from numba.core import caching

# the files whose compiled functions call one another (shapes, characters, trails)
FILES = ("kernel_cache.py", "blend.py", "discs.py", "polygons.py", "limbs.py",
         "character_kernel.py", "trail_kernel.py")
_HERE = os.path.dirname(os.path.abspath(__file__))


@functools.lru_cache(maxsize=8)
def _stamp(here: str, stats: tuple) -> bytes:
    h = hashlib.sha256()
    for name in FILES:
        with open(os.path.join(here, name), "rb") as f:
            h.update(f.read())
    return h.digest()


def stamp() -> bytes:
    """The digest of every file in :data:`FILES` (read again only when one's size or time
    changed)."""
    return _stamp(_HERE, tuple((st.st_mtime_ns, st.st_size) for st in
                               (os.stat(os.path.join(_HERE, n)) for n in FILES)))


class _Stamped:
    def get_source_stamp(self) -> bytes:
        return stamp()


class _InTree(_Stamped, caching.InTreeCacheLocator):
    pass


class _UserWide(_Stamped, caching.UserWideCacheLocator):
    pass


class _Impl(caching.CompileResultCacheImpl):
    _locator_classes = [_InTree, _UserWide]


class _Cache(caching.FunctionCache):
    _impl_class = _Impl


def kernel(fn: Callable | None = None, **options) -> Callable:
    """``numba.njit(nogil=True, **options)`` with the cache stamped by :func:`stamp`; no
    fastmath: the kernels' NaN checks must stay. Use bare (``@kernel``) or with options."""
    if fn is None:
        return functools.partial(kernel, **options)
    disp = numba.njit(nogil=True, **options)(fn)
    disp._cache = _Cache(disp.py_func)     # (what ``cache=True`` sets, with numba's own stamp)
    return disp
