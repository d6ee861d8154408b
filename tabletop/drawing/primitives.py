"""Anti-aliased shapes in projector pixels, and cached soft light (glows) and shadows.

Filled shapes are drawn filled, then their outline anti-aliased, so their edges blend into the
table. Glows and shadows are pre-rendered once per (size, colour, strength) bucket and blitted
with additive or multiplicative blending: they cost one blit each per frame.

The few shapes drawn here (the table and its grid) go through pygame.gfxdraw; characters
and trails are rasterised by compiled calls (:mod:`tabletop.drawing.raster`). OpenCV's batched
drawing was measured slower than pygame's for them (bench/view.py's busy 1280x720 frame in an
X window, interleaved A/B, this thread's CPU per frame, median): a figure's limbs as
``cv2.polylines`` 6.72 -> 10.41 ms; the reactor's three polygons as ``cv2.fillPoly`` 6.24 ->
6.82 ms; every trail with ``cv2.polylines`` 6.21 -> 6.77 ms; a face's head polygons as
``cv2.fillPoly`` 6.54 -> 6.84 ms: its anti-aliased shapes cost more per shape here.
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np
import pygame
import pygame.gfxdraw as gfx

from tabletop.drawing.palette import Color, remember

_CACHE_MAX = 512
_glows: dict[tuple, pygame.Surface] = {}
_shadows: dict[tuple, pygame.Surface] = {}
_rings: dict[tuple, pygame.Surface] = {}


def polygon(surf: pygame.Surface, color: Color, pts: np.ndarray | list) -> None:
    """A filled polygon with an anti-aliased edge (pixels: N x 2 array, or a list of (x, y)
    pairs, which few points cost less as plain floats than as an array)."""
    if len(pts) < 3:
        return
    if isinstance(pts, list):
        if not all(-30000 < x < 30000 and -30000 < y < 30000 for x, y in pts):
            return
        ip = [(round(x), round(y)) for x, y in pts]
    else:
        if not np.abs(pts).max() < 30000:
            return   # NaN, infinity or far off screen (a NaN makes the max NaN)
        ip = np.rint(pts).astype(np.int32).tolist()
    gfx.filled_polygon(surf, ip, color)
    gfx.aapolygon(surf, ip, color)


def disc(surf: pygame.Surface, color: Color, c: Sequence[float], r: float) -> None:
    """A filled anti-aliased disc of radius ``r`` pixels."""
    x, y = c[0], c[1]
    if not (-30000 < x < 30000 and -30000 < y < 30000):
        return
    xi, yi, ri = int(x + 0.5), int(y + 0.5), int(r + 0.5)
    if ri < 1:
        return
    gfx.filled_circle(surf, xi, yi, ri, color)
    gfx.aacircle(surf, xi, yi, ri, color)


def _radial(radius: int, profile) -> np.ndarray:
    """(2r+1, 2r+1) values of ``profile(distance / radius)`` in 0..1."""
    n = 2 * radius + 1
    x = np.arange(n, dtype=np.float32) - np.float32(radius)   # (an open grid: one row and
    d = np.hypot(x[None, :], x[:, None]) / max(radius, 1)    # column, not two full planes)
    return np.clip(profile(d), 0.0, 1.0)


_glow_bases: dict[int, pygame.Surface] = {}


def _glow_base(radius: int) -> pygame.Surface:
    """A white glow of ``radius`` pixels at full strength (remembered): every colour and
    strength of that size is a copy of it, tinted, so a character fading in costs a copy and a
    fill per new light, not the whole ramp."""
    surf = _glow_bases.get(radius)
    if surf is None:
        vals = _radial(radius, lambda d: (1.0 - d * d) ** 2 * (d < 1))
        surf = _remember(_glow_bases, radius, _white_light(vals))
    return surf


def _bucket(v: float, step: float) -> float:
    return max(step, round(v / step) * step)


MAX_LIGHT_PX = 480     # the largest glow or ring radius pre-rendered (pixels)


def _size_bucket(v: float) -> int:
    """Sizes in steps of about 6 % (few cached surfaces, differences too small to see), at most
    :data:`MAX_LIGHT_PX`."""
    v = min(v, MAX_LIGHT_PX)
    if v <= 8:
        return max(1, int(round(v)))
    return int(round(8 * 1.06 ** round(math.log(v / 8) / math.log(1.06))))


def _remember(cache: dict, key: tuple, surf: pygame.Surface) -> pygame.Surface:
    """Keep ``surf`` under ``key`` (:func:`~tabletop.drawing.palette.remember`, at most
    :data:`_CACHE_MAX` surfaces)."""
    return remember(cache, key, surf, _CACHE_MAX)


def fast(surf: pygame.Surface) -> pygame.Surface:
    """``surf`` in the display's pixel format when a display is open (blits then copy rows
    instead of converting every pixel), else as it is."""
    return surf.convert() if pygame.display.get_surface() is not None else surf


def _white_light(values: np.ndarray) -> pygame.Surface:
    """A white light's square from its ramp ``values`` (0..1, odd side, its centre the centre
    pixel) without its dark border: the edge of the ramp rounds to black, and every pixel
    blitted costs (a glow's square is ~7 %, a halo's ring ~15 % smaller; a tint keeps black
    black). The border is found on the grey values before the surface is made, not on the
    surface's pixels: the table's 480 px glow, drawn in a run's first frame, took 0.46 s that
    way, most of it reading the pixels back."""
    grey = (values * np.float32(255)).astype(np.uint8)   # as the surface's channels round
    rows, cols = np.flatnonzero(grey.any(axis=1)), np.flatnonzero(grey.any(axis=0))
    if len(rows):
        c = grey.shape[0] // 2
        k = int(max(np.abs(rows - c).max(), np.abs(cols - c).max()))
        grey = grey[c - k:c + k + 1, c - k:c + k + 1]
    rgb = np.repeat(grey.T[..., None], 3, axis=2)
    return fast(pygame.surfarray.make_surface(rgb))


def prepare_glow(radius: float) -> None:
    """Make the white glow a light of ``radius`` pixels is tinted from (:func:`glow_surface`)."""
    _glow_base(_size_bucket(radius))


def glow_surface(radius: float, color: Color, strength: float) -> pygame.Surface:
    """A soft round light (blit with BLEND_ADD): ``color`` x ``strength`` at the centre, falling
    smoothly to nothing at ``radius`` pixels."""
    exact = (radius, color, strength)     # a settled character asks for the same light
    surf = _glow_calls.get(exact)
    if surf is not None:
        return surf
    r = _size_bucket(radius)
    s = _bucket(strength, 0.05)
    key = (r, color, s)
    surf = _glows.get(key)
    if surf is None:
        surf = _glow_base(r).copy()
        surf.fill(tuple(int(round(v * s)) for v in color), special_flags=pygame.BLEND_MULT)
        surf = _remember(_glows, key, surf)
    return _remember(_glow_calls, exact, surf)


_glow_calls: dict[tuple, pygame.Surface] = {}


class Disc(pygame.Rect):
    """A rectangle of which only the disc ``disc`` (centre x, y and radius px) was drawn on: a
    glow's square has dark corners, and :mod:`tabletop.drawing.dirty` repaints the disc."""

    disc: tuple[int, int, int]


def disc_rect(x: int, y: int, r: int) -> Disc:
    """The square around the disc of radius ``r`` px about pixel (``x``, ``y``), as a
    :class:`Disc`."""
    out = Disc(x - r, y - r, 2 * r + 1, 2 * r + 1)
    out.disc = (x, y, r)
    return out


class Parts(pygame.Rect):
    """A rectangle made of ``parts`` (rectangles and :class:`Disc` ones)."""

    parts: list[pygame.Rect]


GLOW_SHOWN = 0.02        # a glow of this strength or less is not drawn


def glow(surf: pygame.Surface, c: Sequence[float], radius: float, color: Color,
         strength: float) -> Disc | None:
    """Add a soft light of ``radius`` pixels around ``c``; returns the rectangle touched."""
    if strength <= GLOW_SHOWN or radius < 2 or not math.isfinite(c[0] + c[1]):
        return None
    g = glow_surface(radius, color, strength)
    w, h = g.get_size()                  # (centred on the rounded point, as get_rect(center=))
    x, y = int(round(c[0])), int(round(c[1]))
    out = Disc(surf.blit(g, (x - w // 2, y - h // 2), None, pygame.BLEND_ADD))
    out.disc = (x, y, w // 2)
    return out


def shadow_surface(rx: float, ry: float, depth: float) -> pygame.Surface:
    """A soft elliptic shadow (blit with BLEND_MULT): the ground times (1 - ``depth``) at the
    centre, untouched at the rim; semi-axes ``rx``, ``ry`` pixels."""
    rx_i, ry_i = int(_bucket(min(rx, MAX_LIGHT_PX), 3)), int(_bucket(min(ry, MAX_LIGHT_PX), 3))
    dq = _bucket(depth, 0.05)
    key = (rx_i, ry_i, dq)
    surf = _shadows.get(key)
    if surf is None:
        y, x = np.mgrid[-ry_i:ry_i + 1, -rx_i:rx_i + 1].astype(np.float32)
        d = np.hypot(x / rx_i, y / ry_i)
        k = 1.0 - dq * np.clip((1.0 - d * d), 0.0, 1.0) ** 1.5
        vals = np.repeat((k * 255)[..., None], 3, axis=2).astype(np.uint8)
        surf = _remember(_shadows, key, fast(pygame.surfarray.make_surface(
            np.ascontiguousarray(vals.transpose(1, 0, 2)))))
    return surf


def shadow(surf: pygame.Surface, c: Sequence[float], rx: float, ry: float, depth: float) -> None:
    """Darken the ground in a soft ellipse around ``c`` (axis-aligned)."""
    if depth <= 0.02 or rx < 2 or ry < 2 or not math.isfinite(c[0] + c[1]):
        return
    s = shadow_surface(rx, ry, depth)
    surf.blit(s, s.get_rect(center=(int(round(c[0])), int(round(c[1])))),
              special_flags=pygame.BLEND_MULT)


def ring_surface(radius: float, width: float, color: Color, strength: float) -> pygame.Surface:
    """A soft ring of light (blit with BLEND_ADD): brightest at ``radius`` pixels, ``width``
    pixels wide (Gaussian), dark at the centre."""
    exact = (radius, width, color, strength)     # a settled puck asks for the same ring each frame
    surf = _ring_calls.get(exact)
    if surf is not None:
        return surf
    r, w = int(_bucket(min(radius, MAX_LIGHT_PX), 1)), _bucket(min(width, 50.0), 0.5)
    s = _bucket(strength, 0.05)
    key = (r, w, color, s)
    surf = _rings.get(key)
    if surf is None:
        surf = _ring_base(r, w).copy()
        surf.fill(tuple(int(round(v * s)) for v in color), special_flags=pygame.BLEND_MULT)
        surf = _remember(_rings, key, surf)
    return _remember(_ring_calls, exact, surf)


_ring_calls: dict[tuple, pygame.Surface] = {}
_ring_bases: dict[tuple, pygame.Surface] = {}


def _ring_base(r: int, w: float) -> pygame.Surface:
    """A white ring of radius ``r`` and width ``w`` pixels at full strength (remembered): every
    colour and strength of it is a tinted copy, so a lost puck's widening ring or a coasting
    puck's pulse costs a copy and a fill per new step, not the whole ramp (~1-2 ms)."""
    surf = _ring_bases.get((r, w))
    if surf is None:
        outer = int(r + 2.5 * w + 2)
        vals = _radial(outer, lambda d: np.exp(-((d * outer - r) / (0.45 * w)) ** 2)
                       + 0.35 * np.exp(-((d * outer - r) / w) ** 2))
        surf = _remember(_ring_bases, (r, w), _white_light(vals))
    return surf


def box(bounds: tuple[float, float, float, float], pad: float) -> pygame.Rect:
    """The pixel rectangle around ``bounds`` (x0, y0, x1, y1 px, finite) grown by ``pad`` on
    every side."""
    x0, y0, x1, y1 = bounds
    x0, y0, x1, y1 = x0 - pad - 1, y0 - pad - 1, x1 + pad + 2, y1 + pad + 2
    return pygame.Rect(int(x0), int(y0), int(x1 - x0) + 1, int(y1 - y0) + 1)


def union(rects: Sequence[pygame.Rect | None]) -> pygame.Rect | None:
    """The rectangle covering every given rectangle (None ones ignored), or None."""
    rs = [r for r in rects if r is not None]
    if not rs:
        return None
    out = Parts(rs[0].unionall(rs[1:]))
    out.parts = [q for r in rs for q in getattr(r, "parts", (r,))]
    return out
