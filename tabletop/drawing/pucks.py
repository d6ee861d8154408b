"""Pucks: a halo ring of light around each physical puck (its centre left dark, so the marker
and the hand on it are not painted), coloured by state, with a short fading trail."""

from __future__ import annotations

import math
from typing import Callable, NamedTuple, Sequence

import pygame

from tabletop.drawing import primitives as P
from tabletop.drawing.life import PuckTrace
from tabletop.drawing.palette import PUCK_STATES, TABLE, Color, fade

Mapper = Callable[[float, float], tuple[float, float]]


def halo_radius(puck_radius_px: float) -> float:
    """The ring's radius for a puck of ``puck_radius_px`` pixels: just outside its rim."""
    return puck_radius_px * 1.35 + 3.0


def state_color(state: str) -> Color:
    """The halo colour of a puck state (``seen``, ``coasting`` or ``lost``)."""
    return PUCK_STATES.get(state, PUCK_STATES["seen"])


def draw_trail(surf: pygame.Surface, trace: PuckTrace, to_px: Mapper, color: Color,
               t: float, alpha: float, span_s: float, hole_px: float = 0.0) -> pygame.Rect | None:
    """The puck's recent path as a line that fades with age (three steps, newest brightest),
    ending at the halo (``hole_px`` around the puck stays dark); ``to_px`` maps one table point
    (x, y) to pixels. Returns the rectangle it touched."""
    path = trace.path
    if len(path) < 2:
        return None
    cx, cy = to_px(trace.puck.x, trace.puck.y)
    parts: tuple[list, list, list] = ([], [], [])
    last = None
    px = trace.px
    if trace.px_map != to_px or len(px) > 2 * len(path) + 8:
        px = trace.px = {} if trace.px_map != to_px else {e: px[e] for e in path if e in px}
        trace.px_map = to_px
    hole2 = hole_px * hole_px
    # age steps: 2 newest (v >= 2, with v = 3 (1 - age / span)), 1, 0 oldest and anything older
    t2, t1 = t - span_s / 3.0, t - 2.0 * span_s / 3.0
    for e in path:
        q = px.get(e)
        if q is None:
            q = px[e] = to_px(e[0], e[1])
        dx, dy = q[0] - cx, q[1] - cy
        if dx * dx + dy * dy <= hole2:
            continue
        te = e[2]
        k = 2 if te >= t2 else 1 if te >= t1 else 0
        part = parts[k]
        if not part and k and parts[k - 1]:
            part.append(parts[k - 1][-1])      # the steps join up
        part.append(q)
        last = (k, q)
    if last is None:
        return None
    k, q = last
    d = math.hypot(q[0] - cx, q[1] - cy)
    parts[k].append((cx + (q[0] - cx) * hole_px / d, cy + (q[1] - cy) * hole_px / d))
    drawn = []
    for k, q in enumerate(parts):
        if len(q) < 2:
            continue
        col = fade(color, alpha * (0.18, 0.32, 0.5)[k], TABLE)
        if k:
            pygame.draw.lines(surf, col, False, q, 1 + k)
        drawn.append(pygame.draw.aalines(surf, col, False, q))
    if not drawn:
        return None
    # the rectangles the draw calls report cover every point (the wider steps stay within 2 px)
    return drawn[0].unionall(drawn[1:]).inflate(8, 8)


class Halo(NamedTuple):
    """One puck's halo, ready to draw: its ring (a cached light and where it goes, or None),
    its heading notch (colour, centre, radius; or None) and the rectangle it all touches."""
    ring: tuple[pygame.Surface, tuple[int, int]] | None
    notch: tuple[Color, tuple[float, float], float] | None
    rect: pygame.Rect
    label_at: tuple[float, float]      # where a label's left edge and baseline-ish top go (px)


def halo(center: tuple[float, float], r_px: float, angle_px: float, state: str, alpha: float,
         t: float) -> Halo | None:
    """The halo of a puck at ``center`` (px) of radius ``r_px``: a ring of light coloured by
    ``state`` with a bright notch along its heading (``angle_px``, screen radians); the centre
    stays dark. The ring is pre-rendered once per (radius, width, colour, strength step)."""
    x, y = center
    if not (-30000 < x < 30000 and -30000 < y < 30000):
        return None
    color = state_color(state)
    R = halo_radius(r_px)
    if state == "coasting":   # a prediction: the ring breathes quickly, an operator sees it
        alpha *= 0.7 + 0.3 * math.sin(t * 9.0)
    if state == "lost":
        R *= 1.0 + 0.4 * (1.0 - alpha)
    xi, yi = int(round(x)), int(round(y))
    e = int(R + max(3.0, 0.14 * r_px) + 4)
    rect = pygame.Rect(xi - e, yi - e, 2 * e + 1, 2 * e + 1)
    ring = None
    if alpha > 0.02 and R >= 1:
        g = P.ring_surface(R, max(2.0, 0.2 * r_px), color, alpha)
        w, h = g.get_size()
        ring = (g, (xi - w // 2, yi - h // 2))
        rect = rect.union((ring[1], (w, h)))
    notch = None
    if state != "lost":
        notch = (fade((255, 255, 255), alpha),
                 (x + math.cos(angle_px) * R, y + math.sin(angle_px) * R), max(2.5, 0.14 * r_px))
    rr = int(round(R))
    return Halo(ring, notch, rect, (xi + rr * 0.75, yi - rr))


def draw_halos(surf: pygame.Surface, halos: Sequence[Halo],
               labels: Sequence[pygame.Surface | None] = ()) -> list[pygame.Rect]:
    """Draw the halos: every ring in one additive blit call, then the notches over them, then
    each label (when given, beside its halo's upper right). Returns the rectangles touched."""
    surf.fblits([h.ring for h in halos if h.ring is not None], pygame.BLEND_ADD)
    out = []
    for h in halos:
        if h.notch is not None:
            P.disc(surf, *h.notch)
        out.append(h.rect)
    for h, label in zip(halos, labels):
        if label is not None:
            x, y = h.label_at
            out.append(surf.blit(label, (x, y - label.get_height() * 0.6)))
    return out


def draw_halo(surf: pygame.Surface, center: tuple[float, float], r_px: float, angle_px: float,
              state: str, alpha: float, t: float,
              label: pygame.Surface | None = None) -> pygame.Rect | None:
    """One puck's halo (see :func:`halo`), drawn now; returns the rectangle it touched."""
    h = halo(center, r_px, angle_px, state, alpha, t)
    if h is None:
        return None
    return P.union(draw_halos(surf, [h], [label]))
