"""Filled anti-aliased discs, compiled (numba): one, or one at each of many points.

A disc keeps pygame.gfxdraw's look: a disc of radius ``r`` is filled out to ``r + 0.5`` px (gfx
fills every pixel centre within ``r``), its rim covered by each pixel centre's distance inside
that edge. Pixel centres sit on integer coordinates, as for pygame's own drawing.
"""

from __future__ import annotations

import math

import numpy as np

from tabletop.drawing.blend import fill, pen, put
from tabletop.drawing.kernel_cache import kernel


@kernel(inline="always")
def row_span(cx: float, dy: float, inner2: float, outer2: float, W: int) -> tuple:
    """A disc's pixels in the row ``dy`` px from its centre (x ``cx``), ``inner2`` and
    ``outer2`` the squares of its fully covered and outer radii, on a surface ``W`` px wide:
    (xa, xb, ia, ib): the row's pixels xa..xb, of which ia..ib are fully covered (xa > xb:
    none; ia > ib: no full pixel)."""
    h2 = outer2 - dy * dy
    if h2 <= 0.0:
        return 1, 0, 1, 0
    h = math.sqrt(h2)
    xa, xb = max(0, int(math.ceil(cx - h))), min(W - 1, int(math.floor(cx + h)))
    i2 = inner2 - dy * dy
    ia, ib = xb + 1, xb
    if i2 > 0.0:
        hi = math.sqrt(i2)
        ia, ib = max(xa, int(math.ceil(cx - hi))), min(xb, int(math.floor(cx + hi)))
    return xa, xb, ia, ib


@kernel
def disc(pix: np.ndarray, fmt: np.ndarray, cx: float, cy: float, r: float, col: int) -> None:
    """A filled disc of radius ``r`` px around (cx, cy), its rim anti-aliased."""
    if not (r > 0.0 and -30000.0 < cx < 30000.0 and -30000.0 < cy < 30000.0):
        return
    W, H = pix.shape[0], pix.shape[1]
    e = r + 0.5
    y0, y1 = max(0, int(math.floor(cy - e))), min(H - 1, int(math.ceil(cy + e)))
    inner = max(0.0, r - 0.5)
    inner2, outer2 = inner * inner, e * e
    ink = pen(fmt, col)
    for y in range(y0, y1 + 1):
        dy = y - cy
        xa, xb, ia, ib = row_span(cx, dy, inner2, outer2, W)
        for x in range(xa, min(ia, xb + 1)):
            dx = x - cx
            put(pix, x, y, ink, e - math.sqrt(dx * dx + dy * dy))
        if ia <= ib:
            fill(pix, y, ia, ib, ink)
        for x in range(max(ib + 1, xa), xb + 1):
            dx = x - cx
            put(pix, x, y, ink, e - math.sqrt(dx * dx + dy * dy))


@kernel
def discs(pix: np.ndarray, fmt: np.ndarray, q: np.ndarray, r: float, col: int) -> None:
    """A disc of radius ``r`` px at each point of ``q`` (N x 2, px)."""
    for i in range(q.shape[0]):
        disc(pix, fmt, q[i, 0], q[i, 1], r, col)


@kernel(inline="always")
def _bare(pix: np.ndarray, fmt: np.ndarray, bare: np.ndarray, bare_fmt: np.ndarray, x: int,
          y: int, cov: float) -> None:
    """Pixel (x, y) of ``bare`` blended over ``pix``'s with coverage ``cov`` (0..1)."""
    b = np.int64(bare[x, y])
    col = (((b >> bare_fmt[0]) & 255) << 16) | (((b >> bare_fmt[1]) & 255) << 8) \
        | ((b >> bare_fmt[2]) & 255)
    put(pix, x, y, pen(fmt, col), cov)


@kernel
def uncover(pix: np.ndarray, fmt: np.ndarray, bare: np.ndarray, bare_fmt: np.ndarray,
            q: np.ndarray) -> None:
    """The bare table (``bare``: pixels of the same size, format ``bare_fmt``) put back in a
    disc at each row of ``q`` (N x 3: centre x, y and radius, px), filled as :func:`disc`
    fills, its rim blended by coverage: what was drawn there is gone, a puck's top left dark."""
    W, H = pix.shape[0], pix.shape[1]
    same = (fmt[0] == bare_fmt[0] and fmt[1] == bare_fmt[1] and fmt[2] == bare_fmt[2]
            and fmt[3] == bare_fmt[3])
    for i in range(q.shape[0]):
        cx, cy, r = q[i, 0], q[i, 1], q[i, 2]
        if not (r > 0.0 and -30000.0 < cx < 30000.0 and -30000.0 < cy < 30000.0):
            continue
        e = r + 0.5
        y0, y1 = max(0, int(math.floor(cy - e))), min(H - 1, int(math.ceil(cy + e)))
        inner = max(0.0, r - 0.5)
        inner2, outer2 = inner * inner, e * e
        for y in range(y0, y1 + 1):
            dy = y - cy
            xa, xb, ia, ib = row_span(cx, dy, inner2, outer2, W)
            for x in range(xa, min(ia, xb + 1)):
                dx = x - cx
                _bare(pix, fmt, bare, bare_fmt, x, y, e - math.sqrt(dx * dx + dy * dy))
            if same:                             # (the view's own table: its pixels as they are)
                for x in range(ia, ib + 1):
                    pix[x, y] = bare[x, y]
            else:
                for x in range(ia, ib + 1):
                    _bare(pix, fmt, bare, bare_fmt, x, y, 1.0)
            for x in range(max(ib + 1, xa), xb + 1):
                dx = x - cx
                _bare(pix, fmt, bare, bare_fmt, x, y, e - math.sqrt(dx * dx + dy * dy))
