"""Pucks: a halo ring of light around each physical puck (its centre left dark, so the marker
and the hand on it are not painted), coloured by state, with a short fading trail."""

from __future__ import annotations

import math
from typing import NamedTuple, Sequence

import numpy as np
import pygame

from tabletop.drawing import primitives as P
from tabletop.drawing import raster
from tabletop.drawing.life import PuckTrace
from tabletop.drawing.palette import PUCK_STATES, TABLE, Color, fade, rgb


def halo_radius(puck_radius_px: float) -> float:
    """The ring's radius for a puck of ``puck_radius_px`` pixels: just outside its rim."""
    return puck_radius_px * 1.35 + 3.0


def state_color(state: str) -> Color:
    """The halo colour of a puck state (``seen``, ``coasting`` or ``lost``)."""
    return PUCK_STATES.get(state, PUCK_STATES["seen"])


def draw_trails(surf: pygame.Surface, trails: Sequence[tuple[PuckTrace, tuple[float, float],
                                                             Color, float, float]],
                H: np.ndarray, t: float, span_s: float) -> list[pygame.Rect]:
    """Every puck's recent path as a line that fades with age (three steps, newest brightest),
    ending at its halo, in one compiled call. ``trails``: (trace, its puck's centre px, colour,
    opacity, radius px around the puck that stays dark) each; ``H``: table metres -> pixels.
    Returns the rectangles touched."""
    if not trails:
        return []
    pts = [e for tr, *_ in trails for e in tr.path]
    if not pts:
        return []
    starts = np.zeros(len(trails) + 1, dtype=np.int64)
    starts[1:] = np.cumsum([len(tr.path) for tr, *_ in trails])
    colors = np.array([[rgb(fade(color, alpha * k, TABLE)) for k in (0.18, 0.32, 0.5)]
                       for _, _, color, alpha, _ in trails], dtype=np.int64)
    rects = np.zeros((len(trails), 4), dtype=np.int64)
    # age steps: 2 newest (v >= 2, with v = 3 (1 - age / span)), 1, 0 oldest and anything older
    raster.draw(surf, raster.trails, np.array(pts, dtype=np.float64), starts, H,
                np.array([c for _, c, *_ in trails], dtype=np.float64),
                np.array([h for *_, h in trails], dtype=np.float64), colors,
                float(t - span_s / 3.0), float(t - 2.0 * span_s / 3.0), rects)
    return [pygame.Rect(x0, y0, x1 - x0 + 1, y1 - y0 + 1) for x0, y0, x1, y1 in rects.tolist()
            if x1 >= x0]


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
