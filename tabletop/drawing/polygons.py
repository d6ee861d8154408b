"""Filled polygons, compiled (numba), anti-aliased by the exact area they cover in each pixel:
each edge leaves a signed area in the pixels it crosses, accumulated along the row (non-zero
winding); a run of pixels no edge touched has the coverage of the pixel before it and is
filled at once (found eight columns at a time); ellipses as polygons.
"""

from __future__ import annotations

import math

import numpy as np

from tabletop.drawing.blend import fill, mark, pen, put
from tabletop.drawing.kernel_cache import kernel


@kernel
def _edge(acc: np.ndarray, X0: int, Y0: int, x0: float, y0: float, x1: float, y1: float,
          xmax: float) -> None:
    """Accumulate the signed area the edge (x0, y0) -> (x1, y1) leaves in each pixel of
    ``acc`` (rows Y0.., columns X0..; pixel i covers [i, i + 1)); x clamped to the buffer."""
    if y0 == y1:
        return
    d = 1.0
    if y0 > y1:
        d = -1.0
        x0, y0, x1, y1 = x1, y1, x0, y0
    rows = acc.shape[0]
    dxdy = (x1 - x0) / (y1 - y0)
    ys, ye = max(y0, float(Y0)), min(y1, float(Y0 + rows))
    if ys >= ye:
        return
    x = x0 + (ys - y0) * dxdy
    for yi in range(int(math.floor(ys)), int(math.ceil(ye))):
        r = yi - Y0
        if r < 0 or r >= rows:
            continue
        top, bot = max(float(yi), ys), min(float(yi + 1), ye)
        dy = bot - top
        if dy <= 0.0:
            continue
        xn = x + dxdy * dy
        xa = min(max(min(x, xn) - X0, 0.0), xmax)
        xb = min(max(max(x, xn) - X0, 0.0), xmax)
        dd = dy * d
        ia = int(xa)
        ib = int(math.ceil(xb))
        if ib <= ia + 1:                       # within one pixel (or on its border)
            xm = 0.5 * (xa + xb) - ia
            acc[r, ia] += dd * (1.0 - xm)
            acc[r, ia + 1] += dd * xm
        else:                                  # across pixels: a triangle, then trapezoids
            s = 1.0 / (xb - xa)
            fa = xa - ia
            a0 = 0.5 * s * (1.0 - fa) * (1.0 - fa)
            fb = xb - ib + 1.0
            am = 0.5 * s * fb * fb
            acc[r, ia] += dd * a0
            if ib == ia + 2:
                acc[r, ia + 1] += dd * (1.0 - a0 - am)
            else:
                a1 = s * (1.5 - fa)
                acc[r, ia + 1] += dd * (a1 - a0)
                for xi in range(ia + 2, ib - 1):
                    acc[r, xi] += dd * s
                a2 = a1 + (ib - ia - 3) * s
                acc[r, ib - 1] += dd * (1.0 - a2 - am)
            acc[r, ib] += dd * am
        x = xn


@kernel
def polygon(pix: np.ndarray, fmt: np.ndarray, xs: np.ndarray, ys: np.ndarray, n: int,
            col: int, spans: np.ndarray | None = None) -> None:
    """A filled polygon (first ``n`` points of ``xs``, ``ys``, px), its edges anti-aliased by
    the exact area covered (non-zero winding); each row's pixels marked in ``spans``
    (:func:`tabletop.drawing.blend.mark`)."""
    if n < 3:
        return
    W, H = pix.shape[0], pix.shape[1]
    lx, hx, ly, hy = xs[0], xs[0], ys[0], ys[0]
    for i in range(n):
        if not (-30000.0 < xs[i] < 30000.0 and -30000.0 < ys[i] < 30000.0):
            return                             # NaN, infinity or far off screen
        lx, hx = min(lx, xs[i]), max(hx, xs[i])
        ly, hy = min(ly, ys[i]), max(hy, ys[i])
    # pixel centres on integers: pixel x covers [x - 0.5, x + 0.5)
    X0, X1 = max(0, int(math.floor(lx + 0.5))), min(W - 1, int(math.floor(hx + 0.5)))
    Y0, Y1 = max(0, int(math.floor(ly + 0.5))), min(H - 1, int(math.floor(hy + 0.5)))
    if X0 > X1 or Y0 > Y1:
        return
    cols = X1 - X0 + 1
    acc = np.zeros((Y1 - Y0 + 1, cols + 2), np.float32)
    xmax = cols + 0.999
    ink = pen(fmt, col)
    for i in range(n):
        j = i + 1 if i + 1 < n else 0
        _edge(acc, X0, Y0, xs[i] + 0.5, ys[i] + 0.5, xs[j] + 0.5, ys[j] + 0.5, xmax)
    nw = (cols + 8) // 8
    hit = np.zeros(8 * nw, np.bool_)     # the row's columns an edge touched, and an end mark
    words = hit.view(np.uint64)
    for r in range(acc.shape[0]):
        y, s, c = Y0 + r, 0.0, 0
        lo, hi = X1 + 1, X0 - 1        # the row's pixels drawn (for spans)
        row = acc[r]
        for x in range(cols):
            hit[x] = row[x] != 0.0
        hit[cols] = True
        while c < cols:
            s += row[c]
            e = c + 1                  # the columns after c that no edge touched: same cover
            while not hit[e]:
                if e & 7 == 0 and words[e >> 3] == 0:
                    e += 8
                else:
                    e += 1
            cov = abs(s)
            k = np.int64(cov * 256.0 + 0.5)      # (as put rounds it)
            if k >= 256:
                fill(pix, y, X0 + c, X0 + e - 1, ink)
            elif k > 0:
                for x in range(X0 + c, X0 + e):
                    put(pix, x, y, ink, cov)
            if spans is not None:
                if k > 0:
                    lo, hi = min(lo, X0 + c), X0 + e - 1
            c = e
        mark(spans, y, lo, hi)


@kernel
def ellipse(pix: np.ndarray, fmt: np.ndarray, cx: float, cy: float, rx: float, ry: float,
            angle: float, n: int, col: int, spans: np.ndarray | None = None) -> None:
    """A filled ellipse as an ``n``-gon: semi-axes ``rx`` along ``angle`` (screen radians) and
    ``ry`` across it (``spans``: :func:`polygon`)."""
    xs, ys = np.empty(n), np.empty(n)
    ca, sa = math.cos(angle), math.sin(angle)
    for i in range(n):
        u, v = math.cos(2 * math.pi * i / n), math.sin(2 * math.pi * i / n)
        xs[i] = cx + ca * rx * u - sa * ry * v
        ys[i] = cy + sa * rx * u + ca * ry * v
    polygon(pix, fmt, xs, ys, n, col, spans)

