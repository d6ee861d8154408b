"""Filled anti-aliased discs, compiled (numba): one, or one at each of many points.

A disc keeps pygame.gfxdraw's look: a disc of radius ``r`` is filled out to ``r + 0.5`` px (gfx
fills every pixel centre within ``r``), its rim covered by each pixel centre's distance inside
that edge. Pixel centres sit on integer coordinates, as for pygame's own drawing.
"""

from __future__ import annotations

import math

import numpy as np

from tabletop.drawing.blend import fill, mark, pen, put
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


@kernel(inline="always")
def mapped(H: np.ndarray, x: float, y: float) -> tuple[float, float]:
    """Table point (``x``, ``y``) metres in pixels by the homography ``H`` (3 x 3), as
    :meth:`tabletop.table_map.TableToScreen.points` maps it, to the bit."""
    w = H[2, 0] * x + H[2, 1] * y + H[2, 2]
    return (H[0, 0] * x + H[0, 1] * y + H[0, 2]) / w, (H[1, 0] * x + H[1, 1] * y + H[1, 2]) / w


@kernel(inline="always")
def disc_rows(pix: np.ndarray, cy: float, r: float) -> tuple[int, int, int, float, float, float]:
    """The rows a disc of radius ``r`` px around height ``cy`` touches on ``pix``: (W, y0, y1,
    e, inner2, outer2): the surface's width, the first and last row, the outer radius ``e`` and
    the squares of the fully covered and outer radii (for :func:`row_span`)."""
    W, H = pix.shape[0], pix.shape[1]
    e = r + 0.5
    y0, y1 = max(0, int(math.floor(cy - e))), min(H - 1, int(math.ceil(cy + e)))
    inner = max(0.0, r - 0.5)
    return W, y0, y1, e, inner * inner, e * e


@kernel
def disc(pix: np.ndarray, fmt: np.ndarray, cx: float, cy: float, r: float, col: int,
         spans: np.ndarray | None = None) -> None:
    """A filled disc of radius ``r`` px around (cx, cy), its rim anti-aliased; each row's
    pixels marked in ``spans`` (:func:`tabletop.drawing.blend.mark`)."""
    if not (r > 0.0 and -30000.0 < cx < 30000.0 and -30000.0 < cy < 30000.0):
        return
    W, y0, y1, e, inner2, outer2 = disc_rows(pix, cy, r)
    ink = pen(fmt, col)
    for y in range(y0, y1 + 1):
        dy = y - cy
        xa, xb, ia, ib = row_span(cx, dy, inner2, outer2, W)
        mark(spans, y, xa, xb)
        for x in range(xa, min(ia, xb + 1)):
            dx = x - cx
            put(pix, x, y, ink, e - math.sqrt(dx * dx + dy * dy))
        if ia <= ib:
            fill(pix, y, ia, ib, ink)
        for x in range(max(ib + 1, xa), xb + 1):
            dx = x - cx
            put(pix, x, y, ink, e - math.sqrt(dx * dx + dy * dy))


@kernel
def discs(pix: np.ndarray, fmt: np.ndarray, q: np.ndarray, r: float, col: int,
          spans: np.ndarray | None = None) -> None:
    """A disc of radius ``r`` px at each point of ``q`` (N x 2, px) (``spans``: :func:`disc`)."""
    for i in range(q.shape[0]):
        disc(pix, fmt, q[i, 0], q[i, 1], r, col, spans)


@kernel(inline="always")
def _bare(pix: np.ndarray, fmt: np.ndarray, bare: np.ndarray, bare_fmt: np.ndarray, x: int,
          y: int, cov: float) -> None:
    """Pixel (x, y) of ``bare`` blended over ``pix``'s with coverage ``cov`` (0..1)."""
    b = np.int64(bare[x, y])
    col = (((b >> bare_fmt[0]) & 255) << 16) | (((b >> bare_fmt[1]) & 255) << 8) \
        | ((b >> bare_fmt[2]) & 255)
    put(pix, x, y, pen(fmt, col), cov)


@kernel(inline="always")
def _uncover(pix: np.ndarray, fmt: np.ndarray, bare: np.ndarray, bare_fmt: np.ndarray,
             same: bool, cx: float, cy: float, r: float) -> None:
    """The bare table put back in the disc of radius ``r`` px around (cx, cy) (see
    :func:`uncover`; ``same``: ``pix`` and ``bare`` have one format)."""
    if not (r > 0.0 and -30000.0 < cx < 30000.0 and -30000.0 < cy < 30000.0):
        return
    W, y0, y1, e, inner2, outer2 = disc_rows(pix, cy, r)
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


@kernel(inline="always")
def _same(fmt: np.ndarray, bare_fmt: np.ndarray) -> bool:
    return (fmt[0] == bare_fmt[0] and fmt[1] == bare_fmt[1] and fmt[2] == bare_fmt[2]
            and fmt[3] == bare_fmt[3])


@kernel
def uncover(pix: np.ndarray, fmt: np.ndarray, bare: np.ndarray, bare_fmt: np.ndarray,
            q: np.ndarray) -> None:
    """The bare table (``bare``: pixels of the same size, format ``bare_fmt``) put back in a
    disc at each row of ``q`` (N x 3: centre x, y and radius, px), filled as :func:`disc`
    fills, its rim blended by coverage: what was drawn there is gone, a puck's top left dark."""
    same = _same(fmt, bare_fmt)
    for i in range(q.shape[0]):
        _uncover(pix, fmt, bare, bare_fmt, same, q[i, 0], q[i, 1], q[i, 2])


@kernel
def uncover_drawn(pix: np.ndarray, fmt: np.ndarray, bare: np.ndarray, bare_fmt: np.ndarray,
                  at: np.ndarray, H: np.ndarray, radius_m: float, drawn: np.ndarray) -> None:
    """:func:`uncover` for pucks at ``at`` (N x 2 table metres; ``H``: table metres -> px), each
    a disc of its rim (``radius_m`` metres, in px as the map scales it there), where its square
    (1 px more on every side) meets a rectangle of ``drawn`` (M x 4: x, y, width, height px;
    met as a pygame Rect is: an empty one meets nothing): the others lie on the bare table
    already. Mapped and tested in Python (two mappings, a Rect and ``collidelist`` per puck)
    this was half of the pucks' uncovering time (0.30 of 0.59 ms a frame, bench/view.py's busy
    table under load); the mapping is the one :meth:`tabletop.table_map.TableToScreen.points`
    makes, to the bit (bench/view.py's scenes: the same pixels)."""
    same = _same(fmt, bare_fmt)
    for i in range(at.shape[0]):
        x, y = at[i, 0], at[i, 1]
        cx, cy = mapped(H, x, y)
        ex, ey = mapped(H, x + 0.01, y)
        r = radius_m * math.hypot(ex - cx, ey - cy) / 0.01
        if not (r > 0.0 and -30000.0 < cx < 30000.0 and -30000.0 < cy < 30000.0):
            continue
        x0, y0, n = int(cx - r) - 1, int(cy - r) - 1, int(2 * r) + 3
        for k in range(drawn.shape[0]):
            dx, dy, dw, dh = drawn[k, 0], drawn[k, 1], drawn[k, 2], drawn[k, 3]
            if dw != 0 and dh != 0 and x0 < max(dx, dx + dw) and min(dx, dx + dw) < x0 + n \
                    and y0 < max(dy, dy + dh) and min(dy, dy + dh) < y0 + n:
                _uncover(pix, fmt, bare, bare_fmt, same, cx, cy, r)
                break
