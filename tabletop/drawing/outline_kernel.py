"""A hinted pose's outline added onto the view in one compiled pass (numba).

The pose is painted on a black scratch surface (:class:`tabletop.drawing.light.AddedLight`);
what is added onto the view is the pose less a share of itself eroded ``rim`` px (the least of
itself moved ``rim`` px four ways): its edges keep their light, its inside a fraction of it.
Seven pygame passes over the pose's whole rectangle did this (a white fill, four least-of
blits, a multiplying fill, a subtracting blit) and two more added it and cleared the scratch;
here one pass reads only the pixels the pose lit (an unlit pixel adds nothing: its erosion is
no more than itself) and clears the scratch behind it. Compiled once into the shared cache
(``warm``; :data:`KERNEL`); it calls no compiled function of another file.
"""

from __future__ import annotations

import numba
import numpy as np

from behaviors.kernel_cache import compiled

# numba's ``njit(cache=True, nogil=True)`` in the shared cache (see tabletop.drawing.dirty.KERNEL)
KERNEL = compiled(None, error_model="python")


@KERNEL
def add_outline(scratch: np.ndarray, target: np.ndarray, fmt: np.ndarray, x0: int, y0: int,
                x1: int, y1: int, rim: int, keep: int, kept: np.ndarray,
                keeping: bool) -> None:
    """Add ``scratch``'s light in x0..x1-1, y0..y1-1 (px) onto ``target`` (both 32-bit pixels
    indexed ``[x, y]``, of format ``fmt``: red, green, blue shifts) cut to its outline: each
    channel less ``keep``/256 of its least over its four neighbours ``rim`` px away (``rim``
    0: added whole), rounded as pygame's multiplying fill and saturating blits round; the
    scratch's red, green and blue in the rectangle are black after. ``keeping``: what is
    added is also written into ``kept`` (pixels as ``target``'s, black in the rectangle
    before), so that adding it again adds the same (:class:`tabletop.drawing.light.AddedLight`
    keeps a hint's light)."""
    W, H = scratch.shape[0], scratch.shape[1]
    rs, gs, bs = np.uint32(fmt[0]), np.uint32(fmt[1]), np.uint32(fmt[2])
    ff = np.uint32(255)
    lit = (ff << rs) | (ff << gs) | (ff << bs)
    unlit = ~lit
    k = np.uint32(keep if rim > 0 else 0)
    beyond = np.full(W, lit, dtype=np.uint32)     # (a neighbour beyond the surface: none)
    for y in range(y0, y1):
        row, into = scratch[:, y], target[:, y]
        up = scratch[:, y - rim] if y - rim >= 0 else beyond
        down = scratch[:, y + rim] if y + rim < H else beyond
        for x in range(x0, x1):
            s = row[x]
            if s & lit == 0:       # unlit: adds nothing
                continue
            left = row[x - rim] if x >= rim else lit
            right = row[x + rim] if x + rim < W else lit
            u, d, t = up[x], down[x], into[x]
            out = added = np.uint32(0)
            for sh in (rs, gs, bs):
                m = min(min((left >> sh) & ff, (right >> sh) & ff),
                        min((u >> sh) & ff, (d >> sh) & ff))
                m = (m * k + ff) >> np.uint32(8) if m > 0 else np.uint32(0)
                c = (s >> sh) & ff
                a = c - m if c > m else np.uint32(0)
                v = ((t >> sh) & ff) + a
                out |= (v if v < ff else ff) << sh
                added |= a << sh
            into[x] = (t & unlit) | out
            if keeping:
                kept[x, y] = (kept[x, y] & unlit) | added
        if y - rim >= y0:          # no row below needs this one's light any more
            _black(scratch[x0:x1, y - rim], unlit)
    for y in range(max(y0, y1 - rim), y1):
        _black(scratch[x0:x1, y], unlit)


@numba.njit(inline="always")
def _black(row: np.ndarray, unlit: np.uint32) -> None:
    for i in range(row.shape[0]):
        row[i] &= unlit


def warm() -> None:
    """Compile (or load from the cache) the kernel for the pixels it is given: a surface's, seen
    ``[x, y]`` (column-major, :func:`tabletop.drawing.raster.pixels`). Warmed on row-major
    arrays, the first hint of a run loaded a second version from the cache: 33-58 ms in that
    frame (examples/mop.yaml, headless)."""
    px = np.zeros((8, 8), dtype=np.uint32).T
    px[3:5, 3:5] = 0x808080
    into = np.zeros((8, 8), dtype=np.uint32).T
    add_outline(px, into, np.array([16, 8, 0, -1]), 0, 0, 8, 8, 1, 204, into, False)
