"""A colour blended into a 32-bit pixel by coverage: what every shape kernel of the drawing
writes with (compiled, numba; inlined into each kernel).

Pixels are indexed ``[x, y]`` as ``pygame.surfarray.pixels2d`` (see
:func:`tabletop.drawing.raster.pixels`); colours are packed ``0xRRGGBB`` and the surface's
channel shifts (its format, :func:`tabletop.drawing.raster.surface_format`) say where each goes.
"""

from __future__ import annotations

import numpy as np

from tabletop.drawing.kernel_cache import kernel


@kernel(inline="always")
def pen(fmt: np.ndarray, col: int) -> tuple:
    """What :func:`put` needs of packed colour ``col`` (0xRRGGBB) on a surface of format
    ``fmt`` (red, green, blue, alpha shifts; alpha < 0: none): (red, green, blue, shifts,
    the bits a blend keeps, the bits it sets)."""
    rs, gs, bs, al = fmt[0], fmt[1], fmt[2], fmt[3]
    rgb = (np.int64(255) << rs) | (np.int64(255) << gs) | (np.int64(255) << bs)
    keep, opaque = ~rgb, np.int64(0)
    if al >= 0:                    # drawn pixels become opaque
        keep, opaque = ~(rgb | (np.int64(255) << al)), np.int64(255) << al
    return ((col >> 16) & 255, (col >> 8) & 255, col & 255, rs, gs, bs, keep, opaque)


@kernel(inline="always")
def put(pix: np.ndarray, x: int, y: int, ink: tuple, cov: float) -> None:
    """Blend ``ink`` (from :func:`pen`) over pixel (x, y) with coverage ``cov`` (0..1)."""
    c = np.int64(cov * 256.0 + 0.5)
    if c <= 0:
        return
    sr, sg, sb, rs, gs, bs, keep, opaque = ink
    old = np.int64(pix[x, y])
    if c >= 256:
        pix[x, y] = np.uint32((sr << rs) | (sg << gs) | (sb << bs) | (old & keep) | opaque)
        return
    dr, dg, db = (old >> rs) & 255, (old >> gs) & 255, (old >> bs) & 255
    r = dr + (((sr - dr) * c + 128) >> 8)
    g = dg + (((sg - dg) * c + 128) >> 8)
    b = db + (((sb - db) * c + 128) >> 8)
    pix[x, y] = np.uint32((r << rs) | (g << gs) | (b << bs) | (old & keep) | opaque)



@kernel(inline="always")
def fill(pix: np.ndarray, y: int, x0: int, x1: int, ink: tuple) -> None:
    """Pixels x0..x1 (inclusive, on the surface) of row ``y`` fully covered by ``ink``: what
    :func:`put` writes at coverage 1, in a loop the compiler vectorises (a row's run, not a
    pixel at a time)."""
    sr, sg, sb, rs, gs, bs, keep, opaque = ink
    col = np.uint32((sr << rs) | (sg << gs) | (sb << bs) | opaque)
    k = np.uint32(keep & 0xFFFFFFFF)
    row = pix[x0:x1 + 1, y]
    for x in range(row.shape[0]):
        row[x] = (row[x] & k) | col


@kernel(inline="always")
def mark(spans: np.ndarray | None, y: int, x0: int, x1: int) -> None:
    """Pixels x0..x1 of row ``y`` drawn: row ``y``'s span in ``spans`` (rows x (first, last)
    px; empty: first > last) widened to hold them (x0 > x1: none). None: no spans kept (the
    branch is compiled away: a drawing without spans pays nothing)."""
    if spans is not None:
        if x0 <= x1:
            spans[y, 0] = min(spans[y, 0], x0)
            spans[y, 1] = max(spans[y, 1], x1)
