"""The drawing's shape kernels (numba), all cached under one stamp of all their files.

A figure's kernel holds its own copy of the limbs', discs' and polygons' compiled code; with
numba's own stamp, a change to ``limbs.py`` would leave the figure drawn by the old limbs until
``character_kernel.py`` changed. Kernels made with :func:`kernel` are stamped with the contents
of every file in :data:`FILES` (:func:`behaviors.kernel_cache.compiled`): a change to any of them
compiles them all again (about 20 s of CPU, once; ``make kernels`` does it;
``tests/tabletop/test_kernel_cache.py`` checks every kernel is stamped so).
"""

from __future__ import annotations

import functools
import os
from typing import Callable

from behaviors.kernel_cache import compiled
from behaviors.kernel_cache import stamp as stamp_of

# the files whose compiled functions call one another (shapes, characters, trails)
FILES = ("kernel_cache.py", "blend.py", "discs.py", "polygons.py", "limbs.py",
         "character_kernel.py", "trail_kernel.py")
_HERE = os.path.dirname(os.path.abspath(__file__))


def stamp() -> bytes:
    """The stamp every drawing kernel is cached under: the digest of every file in
    :data:`FILES`."""
    return stamp_of(os.path.join(_HERE, n) for n in FILES)


def kernel(fn: Callable | None = None, **options) -> Callable:
    """:func:`behaviors.kernel_cache.compiled` with the stamp of :data:`FILES`, compiled on its
    first call. Use bare (``@kernel``) or with numba options."""
    if fn is None:
        return functools.partial(kernel, **options)
    return compiled(None, *(os.path.join(_HERE, n) for n in FILES), **options)(fn)
