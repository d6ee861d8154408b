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
        h2 = outer2 - dy * dy
        if h2 <= 0.0:
            continue
        h = math.sqrt(h2)
        xa, xb = max(0, int(math.ceil(cx - h))), min(W - 1, int(math.floor(cx + h)))
        i2 = inner2 - dy * dy
        ia, ib = xb + 1, xb
        if i2 > 0.0:
            hi = math.sqrt(i2)
            ia, ib = max(xa, int(math.ceil(cx - hi))), min(xb, int(math.floor(cx + hi)))
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

