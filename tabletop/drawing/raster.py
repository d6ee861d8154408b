"""A surface's pixels for the drawing's compiled kernels, and the kernels warmed.

The kernels rasterise anti-aliased shapes straight into a surface's 32-bit pixels (indexed
``[x, y]`` as ``pygame.surfarray.pixels2d``), colours packed ``0xRRGGBB`` and blended by
coverage (:mod:`~tabletop.drawing.blend`): discs (:mod:`~tabletop.drawing.discs`), strokes and
tapered limbs (:mod:`~tabletop.drawing.limbs`), filled polygons by their exact area
(:mod:`~tabletop.drawing.polygons`), each character kind whole
(:mod:`~tabletop.drawing.character_kernel`) and the pucks' trails
(:mod:`~tabletop.drawing.trail_kernel`). :func:`draw` runs one on a surface. They are compiled
once into the cache beside their files (:mod:`~tabletop.drawing.kernel_cache`; the Makefile's
``kernels`` target runs :func:`warm`).
"""

from __future__ import annotations

import ctypes
import math
import weakref
from typing import TYPE_CHECKING, Any, Callable

import numpy as np

if TYPE_CHECKING:
    import pygame

_formats: dict[tuple, np.ndarray] = {}


def surface_format(surf: pygame.Surface) -> np.ndarray:
    """The red, green, blue and alpha shifts of a 32-bit surface's pixels (alpha -1 when it
    has no alpha channel), as the kernels take them."""
    shifts, amask = surf.get_shifts(), surf.get_masks()[3]
    key = (shifts, amask)
    fmt = _formats.get(key)
    if fmt is None:
        fmt = _formats[key] = np.array([shifts[0], shifts[1], shifts[2],
                                        shifts[3] if amask else -1], dtype=np.int64)
    return fmt


_views: dict[int, tuple] = {}   # id of a surface -> (weak reference, layout, pixels, format)


def pixels(surf: pygame.Surface) -> tuple[np.ndarray, np.ndarray] | None:
    """``surf``'s 32-bit pixels (indexed ``[x, y]``, column-major as the kernels are compiled
    for) and format, or None for a surface of another depth, a subsurface (strided rows) or one
    that must be locked. The view is made once per surface and pixel memory (address, pitch,
    size) and holds no lock, unlike ``pygame.surfarray.pixels2d``, so the surface can be
    blitted between two kernels' draws (a frame's glows between its characters): ~5 us per
    drawing call less."""
    try:
        now = (surf._pixels_address, surf.get_pitch(), surf.get_size())
    except Exception:              # (a display surface after the display quit)
        return None
    known = _views.get(id(surf))
    if known is not None and known[0]() is surf and known[1] == now:
        return known[2], known[3]
    addr, pitch, (w, h) = now
    if surf.get_bytesize() != 4 or pitch != 4 * w or surf.mustlock() or not addr or not w * h:
        return None
    buf = (ctypes.c_uint32 * (w * h)).from_address(addr)
    pix = np.frombuffer(buf, np.uint32).reshape(h, w).T
    if len(_views) >= 64:          # (surfaces gone long ago)
        _views.clear()
    fmt = surface_format(surf)
    _views[id(surf)] = (weakref.ref(surf), now, pix, fmt)
    return pix, fmt


def draw(surf: pygame.Surface, kernel: Callable[..., None], *args: Any) -> None:
    """Run a drawing ``kernel(pixels, format, *args)`` on ``surf``'s pixels (see
    :func:`pixels`; a surface of another depth, or a subsurface, is drawn through a 32-bit
    copy)."""
    view = pixels(surf)
    if view is not None:
        kernel(view[0], view[1], *args)
        return
    import pygame
    tmp = pygame.Surface(surf.get_size(), 0, 32)
    tmp.blit(surf, (0, 0))
    kernel(pygame.surfarray.pixels2d(tmp), surface_format(tmp), *args)
    surf.blit(tmp, (0, 0))


_warm = False


def warm() -> None:
    """Compile (or load from the cache) every kernel by drawing each kind once, offscreen (once
    per process)."""
    global _warm
    if _warm:
        return
    _warm = True
    import os
    os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
    import pygame

    from tabletop.drawing.character_kernel import CREATURE, face, figure, reactor
    from tabletop.drawing.discs import discs, uncover, uncover_drawn
    from tabletop.drawing.trail_kernel import trails
    surf = pygame.Surface((64, 64), 0, 32)
    q = np.array([(10.0, 10.0), (20.0, 30.0), (30.0, 20.0)])
    uv = np.array([(0.5, 0.0), (0.0, 0.3), (-0.5, 0.0), (0.0, -0.3)])
    m = np.array([20.0, 0.0, 0.0, 20.0])
    tp = np.array([2, 1, 1, 1, 0, 2, 0, 1, 0, 2, 2, 0, 0, 2], dtype=np.int64)
    lp = np.array([2, 7, 3, 1, 10, 2, 0, 0, 1, 2, 1, 2], dtype=np.int64)
    draw(surf, reactor, uv, uv[:2].copy(), m, 1.0, 30.0, 30.0, 20.0, 1.0, 0.0, 0.0, 1, 2, 3, 4,
         0.5, 0.0, 0.0, 5, 6)
    # characters drawn as themselves (no spans) and as hinted poses (their rows' spans marked)
    for spans in (None, np.zeros((64, 2), dtype=np.int64)):
        draw(surf, figure, q, np.full(3, 1.0), tp, CREATURE, 2.0, 2.0, 30.0, True, 1, 2, 3,
             0.0, 0.0, 1.0, 4, 5, 0.0, 0.0, math.nan, spans)
        draw(surf, face, q, lp, 1.5, 1, 2, 3, 4, 1.0, 0.0, 0.0, 3, spans)
        draw(surf, discs, q, 2.0, 1, spans)
    draw(surf, discs, q, 2.0, 1)
    bare = pygame.Surface((64, 64), 0, 32)
    draw(surf, uncover, *pixels(bare), np.array([(30.0, 30.0, 5.0)]))
    draw(surf, uncover_drawn, *pixels(bare), np.array([(0.3, 0.3)]), np.eye(3) * 100.0, 0.05,
         np.array([(20, 20, 5, 5)], dtype=np.int64))
    path = np.array([(0.1, 0.1, 0.0), (0.2, 0.3, 0.5), (0.3, 0.2, 1.0)])
    draw(surf, trails, path, np.array([0, 3], dtype=np.int64), np.eye(3) * 100.0,
         np.array([(30.0, 30.0)]), np.array([5.0]), np.ones((1, 3), dtype=np.int64), 0.6, 0.3,
         np.zeros((1, 4), dtype=np.int64))

