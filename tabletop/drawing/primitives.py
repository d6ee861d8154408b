"""Anti-aliased shapes in projector pixels, and cached soft light (glows) and shadows.

Filled shapes are drawn filled, then their outline anti-aliased, so their edges blend into the
table. Glows and shadows are pre-rendered once per (size, colour, strength) bucket and blitted
with additive or multiplicative blending: they cost one blit each per frame.
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np
import pygame
import pygame.gfxdraw as gfx

from tabletop.drawing.palette import Color

_CACHE_MAX = 512
_glows: dict[tuple, pygame.Surface] = {}
_shadows: dict[tuple, pygame.Surface] = {}
_rings: dict[tuple, pygame.Surface] = {}


def _ipts(pts: np.ndarray | Sequence) -> list[tuple[int, int]]:
    a = np.rint(np.asarray(pts, dtype=float)).astype(int)
    return [(int(x), int(y)) for x, y in a]


def polygon(surf: pygame.Surface, color: Color, pts: np.ndarray) -> None:
    """A filled polygon with an anti-aliased edge (pixels, N x 2)."""
    if len(pts) < 3 or not np.all(np.isfinite(pts)):
        return
    ip = _ipts(pts)
    gfx.filled_polygon(surf, ip, color)
    gfx.aapolygon(surf, ip, color)


def disc(surf: pygame.Surface, color: Color, c: Sequence[float], r: float) -> None:
    """A filled anti-aliased disc of radius ``r`` pixels."""
    if not (math.isfinite(c[0]) and math.isfinite(c[1])):
        return
    x, y, ri = int(round(c[0])), int(round(c[1])), int(round(r))
    if ri < 1:
        surf.set_at((x, y), color) if surf.get_rect().collidepoint(x, y) else None
        return
    gfx.filled_circle(surf, x, y, ri, color)
    gfx.aacircle(surf, x, y, ri, color)


def ellipse(surf: pygame.Surface, color: Color, c: Sequence[float], rx: float, ry: float,
            angle: float = 0.0, n: int = 20) -> None:
    """A filled anti-aliased ellipse, semi-axes ``rx`` along ``angle`` (screen radians, y down)
    and ``ry`` across it."""
    surf_pts = ellipse_points(c, rx, ry, angle, n)
    polygon(surf, color, surf_pts)


def ellipse_points(c: Sequence[float], rx: float, ry: float, angle: float = 0.0,
                   n: int = 20) -> np.ndarray:
    """Outline points (n x 2) of an ellipse in pixels."""
    t = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    ca, sa = math.cos(angle), math.sin(angle)
    ex, ey = rx * np.cos(t), ry * np.sin(t)
    return np.stack([c[0] + ca * ex - sa * ey, c[1] + sa * ex + ca * ey], axis=1)


def limb(surf: pygame.Surface, color: Color, a: Sequence[float], b: Sequence[float],
         wa: float, wb: float | None = None) -> None:
    """A tapered limb (a capsule) from ``a`` to ``b``: half-widths ``wa`` and ``wb`` pixels,
    rounded ends, anti-aliased."""
    wb = wa if wb is None else wb
    ax, ay, bx, by = float(a[0]), float(a[1]), float(b[0]), float(b[1])
    if not all(math.isfinite(v) for v in (ax, ay, bx, by)):
        return
    dx, dy = bx - ax, by - ay
    d = math.hypot(dx, dy)
    if d > 1e-6:
        nx, ny = -dy / d, dx / d
        polygon(surf, color, np.array([(ax + nx * wa, ay + ny * wa), (bx + nx * wb, by + ny * wb),
                                       (bx - nx * wb, by - ny * wb), (ax - nx * wa, ay - ny * wa)]))
    disc(surf, color, (ax, ay), wa)
    disc(surf, color, (bx, by), wb)


def aa_polyline(surf: pygame.Surface, color: Color, pts: np.ndarray, width: int = 2) -> None:
    """A polyline ``width`` pixels wide with anti-aliased sides."""
    if len(pts) < 2:
        return
    ip = pts.tolist()
    if width > 1:
        pygame.draw.lines(surf, color, False, ip, width)
    pygame.draw.aalines(surf, color, False, ip)


def _radial(radius: int, profile) -> np.ndarray:
    """(2r+1, 2r+1) values of ``profile(distance / radius)`` in 0..1."""
    n = 2 * radius + 1
    y, x = np.mgrid[0:n, 0:n].astype(np.float32)
    d = np.hypot(x - radius, y - radius) / max(radius, 1)
    return np.clip(profile(d), 0.0, 1.0)


def _bucket(v: float, step: float) -> float:
    return max(step, round(v / step) * step)


def _remember(cache: dict, key: tuple, surf: pygame.Surface) -> pygame.Surface:
    if len(cache) >= _CACHE_MAX:
        cache.clear()
    cache[key] = surf
    return surf


def _rgb_surface(values: np.ndarray, color: Color) -> pygame.Surface:
    rgb = (values[..., None] * np.asarray(color, dtype=np.float32)).astype(np.uint8)
    return pygame.surfarray.make_surface(np.ascontiguousarray(rgb.transpose(1, 0, 2)))


def glow_surface(radius: float, color: Color, strength: float) -> pygame.Surface:
    """A soft round light (blit with BLEND_ADD): ``color`` x ``strength`` at the centre, falling
    smoothly to nothing at ``radius`` pixels."""
    r = int(_bucket(radius, 4))
    s = _bucket(strength, 0.05)
    key = (r, color, s)
    surf = _glows.get(key)
    if surf is None:
        vals = s * _radial(r, lambda d: (1.0 - d * d) ** 2 * (d < 1))
        surf = _remember(_glows, key, _rgb_surface(vals, color))
    return surf


def glow(surf: pygame.Surface, c: Sequence[float], radius: float, color: Color,
         strength: float) -> None:
    """Add a soft light of ``radius`` pixels around ``c``."""
    if strength <= 0.02 or radius < 2 or not math.isfinite(c[0] + c[1]):
        return
    g = glow_surface(radius, color, strength)
    surf.blit(g, g.get_rect(center=(int(round(c[0])), int(round(c[1])))),
              special_flags=pygame.BLEND_ADD)


def shadow_surface(rx: float, ry: float, depth: float) -> pygame.Surface:
    """A soft elliptic shadow (blit with BLEND_MULT): the ground times (1 - ``depth``) at the
    centre, untouched at the rim; semi-axes ``rx``, ``ry`` pixels."""
    rx_i, ry_i, dq = int(_bucket(rx, 3)), int(_bucket(ry, 3)), _bucket(depth, 0.05)
    key = (rx_i, ry_i, dq)
    surf = _shadows.get(key)
    if surf is None:
        y, x = np.mgrid[-ry_i:ry_i + 1, -rx_i:rx_i + 1].astype(np.float32)
        d = np.hypot(x / rx_i, y / ry_i)
        k = 1.0 - dq * np.clip((1.0 - d * d), 0.0, 1.0) ** 1.5
        vals = np.repeat((k * 255)[..., None], 3, axis=2).astype(np.uint8)
        surf = _remember(_shadows, key, pygame.surfarray.make_surface(
            np.ascontiguousarray(vals.transpose(1, 0, 2))))
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
    r, w, s = int(_bucket(radius, 1)), _bucket(width, 0.5), _bucket(strength, 0.05)
    key = (r, w, color, s)
    surf = _rings.get(key)
    if surf is None:
        outer = int(r + 3 * w + 2)
        vals = s * _radial(outer, lambda d: np.exp(-((d * outer - r) / w) ** 2))
        surf = _remember(_rings, key, _rgb_surface(vals, color))
    return surf


def ring(surf: pygame.Surface, c: Sequence[float], radius: float, width: float, color: Color,
         strength: float) -> None:
    """Add a soft ring of light around ``c``."""
    if strength <= 0.02 or radius < 1 or not math.isfinite(c[0] + c[1]):
        return
    g = ring_surface(radius, width, color, strength)
    surf.blit(g, g.get_rect(center=(int(round(c[0])), int(round(c[1])))),
              special_flags=pygame.BLEND_ADD)
