"""Limbs, compiled (numba): strokes of constant width (capsules: segments with round ends) and
tapered limbs (the hull of the discs at their two joints, so joints need no discs of their own),
anti-aliased by each pixel centre's distance from the shape.

Each row is walked only where the limb crosses it (its chord found from the round ends and the
band between them), full pixels are filled without a distance, and distances are measured only
near the sides.
"""

from __future__ import annotations

import math

import numpy as np

from tabletop.drawing.blend import fill, mark, pen, put
from tabletop.drawing.discs import disc
from tabletop.drawing.kernel_cache import kernel


@kernel(inline="always")
def _slab(lo: float, hi: float, c: float, slope: float, inv: float, a: float,
          b: float) -> tuple:
    """(lo, hi) narrowed to the x where a <= c + slope * x <= b (``inv`` = 1 / slope)."""
    if abs(slope) < 1e-9:
        if c < a or c > b:
            return 1.0, 0.0
        return lo, hi
    u, v = (a - c) * inv, (b - c) * inv
    if u > v:
        u, v = v, u
    return max(lo, u), min(hi, v)


@kernel(inline="always")
def _chords(y: float, ax: float, ay: float, ra: float, bx: float, by: float,
            rb: float) -> tuple:
    """(lo, hi): the x of row ``y`` inside the circle of radius ``ra`` around a or ``rb``
    around b (lo > hi: none)."""
    lo, hi = 1e9, -1e9
    d = y - ay
    if d * d < ra * ra:
        h = math.sqrt(ra * ra - d * d)
        lo, hi = ax - h, ax + h
    d = y - by
    if d * d < rb * rb:
        h = math.sqrt(rb * rb - d * d)
        lo, hi = min(lo, bx - h), max(hi, bx + h)
    return lo, hi


@kernel(inline="always")
def _row(y: float, ax: float, ay: float, bx: float, by: float, vx: float, vy: float, ll: float,
         ux: float, uy: float, ivx: float, iuy: float, r: float) -> tuple:
    """(lo, hi): the x of row ``y`` within ``r`` px of the segment (a, b) (lo > hi: none);
    (vx, vy) = b - a, ``ll`` its squared length, (ux, uy) its direction, ``ivx`` = 1 / vx,
    ``iuy`` = 1 / uy."""
    lo, hi = _chords(y, ax, ay, r, bx, by, r)          # the round ends
    if ll > 1e-12:                                       # the band between them
        py = y - ay
        s0, s1 = _slab(-1e9, 1e9, -ax * vx + py * vy, vx, ivx, 0.0, ll)
        s0, s1 = _slab(s0, s1, -ax * uy - py * ux, uy, iuy, -r, r)
        if s0 <= s1:
            lo, hi = min(lo, s0), max(hi, s1)
    return lo, hi


@kernel
def capsule(pix: np.ndarray, fmt: np.ndarray, ax: float, ay: float, bx: float, by: float,
            w: float, col: int, spans: np.ndarray | None = None) -> None:
    """A limb from (ax, ay) to (bx, by): every pixel within ``w`` px of the segment (round
    ends), its sides anti-aliased. Each row is walked only where the limb crosses it, and
    distances are measured only near its sides; each row's pixels marked in ``spans``
    (:func:`tabletop.drawing.blend.mark`)."""
    if not (w > 0.0 and -30000.0 < ax < 30000.0 and -30000.0 < ay < 30000.0
            and -30000.0 < bx < 30000.0 and -30000.0 < by < 30000.0):
        return
    W, H = pix.shape[0], pix.shape[1]
    e = w + 0.5
    y0, y1 = max(0, int(math.floor(min(ay, by) - e))), min(H - 1, int(math.ceil(max(ay, by) + e)))
    vx, vy = bx - ax, by - ay
    ll = vx * vx + vy * vy
    inv = 1.0 / ll if ll > 1e-12 else 0.0
    ln = math.sqrt(ll)
    ux, uy = (vx / ln, vy / ln) if ln > 1e-9 else (1.0, 0.0)
    ivx = 1.0 / vx if abs(vx) >= 1e-9 else 0.0
    iuy = 1.0 / uy if abs(uy) >= 1e-9 else 0.0
    inner = max(0.0, w - 0.5)
    ink = pen(fmt, col)
    for y in range(y0, y1 + 1):
        lo, hi = _row(y, ax, ay, bx, by, vx, vy, ll, ux, uy, ivx, iuy, e)
        xa, xb = max(0, int(math.ceil(lo))), min(W - 1, int(math.floor(hi)))
        if xa > xb:
            continue
        mark(spans, y, xa, xb)
        ia, ib = xb + 1, xb
        if inner > 0.0:
            lo, hi = _row(y, ax, ay, bx, by, vx, vy, ll, ux, uy, ivx, iuy, inner)
            if lo <= hi:
                ia, ib = max(xa, int(math.ceil(lo))), min(xb, int(math.floor(hi)))
        py = y - ay
        if ia <= ib:
            fill(pix, y, ia, ib, ink)
        for x in range(xa, min(ia, xb + 1)):
            _side(pix, x, y, ink, x - ax, py, vx, vy, inv, e)
        for x in range(max(ib + 1, xa), xb + 1):
            _side(pix, x, y, ink, x - ax, py, vx, vy, inv, e)


@kernel(inline="always")
def _side(pix: np.ndarray, x: int, y: int, ink: tuple, px: float, py: float, vx: float,
          vy: float, inv: float, e: float) -> None:
    """A pixel near a limb's side: covered by how far inside ``e`` px of the segment from
    (0, 0) to (vx, vy) it lies (at (px, py) from the segment's start)."""
    t = min(1.0, max(0.0, (px * vx + py * vy) * inv))
    dx, dy = px - t * vx, py - t * vy
    d2 = dx * dx + dy * dy
    if d2 < e * e:
        put(pix, x, y, ink, e - math.sqrt(d2))


@kernel(inline="always")
def _quad(ax: float, ay: float, ra: float, bx: float, by: float, rb: float) -> tuple:
    """The corners (x, y) x 4 where the lines touching both circles (radius ``ra`` around a,
    ``rb`` around b) touch them, in order around; all at a when one circle holds the other."""
    dx, dy = bx - ax, by - ay
    d = math.sqrt(dx * dx + dy * dy)
    if d <= abs(ra - rb) + 1e-9:
        return ax, ay, ax, ay, ax, ay, ax, ay
    ux, uy = dx / d, dy / d
    k = (ra - rb) / d
    s = math.sqrt(max(0.0, 1.0 - k * k))
    px, py = ux * k - uy * s, uy * k + ux * s      # the touching lines' normals
    mx, my = ux * k + uy * s, uy * k - ux * s
    return (ax + ra * px, ay + ra * py, bx + rb * px, by + rb * py,
            bx + rb * mx, by + rb * my, ax + ra * mx, ay + ra * my)


@kernel(inline="always")
def _slopes(qd: tuple) -> tuple:
    """dx/dy of the two touching lines of a :func:`_quad` (0 where one is level)."""
    x1, y1, x2, y2, x3, y3, x4, y4 = qd
    return ((x2 - x1) / (y2 - y1) if y1 != y2 else 0.0,
            (x4 - x3) / (y4 - y3) if y3 != y4 else 0.0)


@kernel(inline="always")
def _cross(lo: float, hi: float, y: float, x0: float, y0: float, y1: float,
           dxdy: float) -> tuple:
    """(lo, hi) widened to where the segment from (x0, y0) to height ``y1`` (``dxdy`` its
    dx/dy) crosses row ``y``."""
    if (y0 - y) * (y1 - y) <= 0.0 and y0 != y1:
        x = x0 + (y - y0) * dxdy
        lo, hi = min(lo, x), max(hi, x)
    return lo, hi


@kernel(inline="always")
def _cone_row(y: float, ax: float, ay: float, ra: float, bx: float, by: float, rb: float,
              qd: tuple, sl: tuple) -> tuple:
    """(lo, hi): the x of row ``y`` inside the hull of the circles (radius ``ra`` around a,
    ``rb`` around b; ``qd`` from :func:`_quad`) (lo > hi: none). The hull is convex: its row
    is the union of the circles' chords and the touching quadrilateral's (``sl``: its sides'
    :func:`_slopes`)."""
    lo, hi = _chords(y, ax, ay, ra, bx, by, rb)
    x1, y1, x2, y2, x3, y3, x4, y4 = qd
    lo, hi = _cross(lo, hi, y, x1, y1, y2, sl[0])
    lo, hi = _cross(lo, hi, y, x3, y3, y4, sl[1])
    return lo, hi


@kernel(inline="always")
def _cone_sd(px: float, py: float, vx: float, vy: float, l2: float, a2: float, sa2: float,
             il2: float, rr: float, ra: float, rb: float) -> float:
    """Signed distance (px) from (px, py) (from a) to the hull of the circles of radius ``ra``
    around a and ``rb`` around b = a + (vx, vy) (``l2`` = |v|^2, ``rr`` = ra - rb, ``a2`` =
    l2 - rr^2, ``sa2`` its square root, ``il2`` = 1 / l2): the round cone's distance after
    Inigo Quilez. Beside the limb (most of its edge pixels) no square root is taken: there
    Quilez's sqrt(x2 a2 / l2) is |p x v| sqrt(a2)."""
    y = px * vx + py * vy
    z = y - l2
    qx, qy = px * l2 - vx * y, py * l2 - vy * y
    x2 = qx * qx + qy * qy
    k = rr * abs(rr) * x2
    if math.copysign(a2 * z * z * l2, z) > k:
        return math.sqrt(x2 + z * z * l2) * il2 - rb
    if math.copysign(a2 * y * y * l2, y) < k:
        return math.sqrt(x2 + y * y * l2) * il2 - ra
    return (abs(px * vy - py * vx) * sa2 + y * rr) * il2 - ra


@kernel
def cone(pix: np.ndarray, fmt: np.ndarray, ax: float, ay: float, ra: float, bx: float,
         by: float, rb: float, col: int, spans: np.ndarray | None = None) -> None:
    """A tapered limb: every pixel within the hull of the discs of radius ``ra`` px around
    (ax, ay) and ``rb`` around (bx, by), its sides anti-aliased by their distance (a joint's
    disc is the limb's own round end). Rows are walked only where the limb crosses them and
    distances measured only near its sides; each row's pixels marked in ``spans``
    (:func:`tabletop.drawing.blend.mark`)."""
    if not (-30000.0 < ax < 30000.0 and -30000.0 < ay < 30000.0 and -30000.0 < bx < 30000.0
            and -30000.0 < by < 30000.0 and 0.0 < ra < 30000.0 and 0.0 < rb < 30000.0):
        return
    vx, vy = bx - ax, by - ay
    l2 = vx * vx + vy * vy
    rr = ra - rb
    if l2 <= rr * rr + 1e-9:                   # one disc holds the other
        if rb > ra:
            disc(pix, fmt, bx, by, rb, col, spans)
        else:
            disc(pix, fmt, ax, ay, ra, col, spans)
        return
    W, H = pix.shape[0], pix.shape[1]
    ea, eb = ra + 0.5, rb + 0.5
    y0 = max(0, int(math.floor(min(ay - ea, by - eb))))
    y1 = min(H - 1, int(math.ceil(max(ay + ea, by + eb))))
    outer = _quad(ax, ay, ea, bx, by, eb)
    ia_, ib_ = max(0.0, ra - 0.5), max(0.0, rb - 0.5)
    inner = _quad(ax, ay, ia_, bx, by, ib_)
    so, si = _slopes(outer), _slopes(inner)
    # the signed distance to the hull (a round cone), one square root per pixel
    a2 = l2 - rr * rr
    sa2 = math.sqrt(a2)
    il2 = 1.0 / l2
    ink = pen(fmt, col)
    for y in range(y0, y1 + 1):
        lo, hi = _cone_row(y, ax, ay, ea, bx, by, eb, outer, so)
        xa, xb = max(0, int(math.ceil(lo))), min(W - 1, int(math.floor(hi)))
        if xa > xb:
            continue
        mark(spans, y, xa, xb)
        ia, ib = xb + 1, xb
        if ia_ > 0.0 or ib_ > 0.0:
            lo, hi = _cone_row(y, ax, ay, ia_, bx, by, ib_, inner, si)
            if lo <= hi:
                ia, ib = max(xa, int(math.ceil(lo))), min(xb, int(math.floor(hi)))
        if ia <= ib:
            fill(pix, y, ia, ib, ink)
        py = y - ay
        for x in range(xa, min(ia, xb + 1)):
            put(pix, x, y, ink, 0.5 - _cone_sd(x - ax, py, vx, vy, l2, a2, sa2, il2, rr, ra, rb))
        for x in range(max(ib + 1, xa), xb + 1):
            put(pix, x, y, ink, 0.5 - _cone_sd(x - ax, py, vx, vy, l2, a2, sa2, il2, rr, ra, rb))

