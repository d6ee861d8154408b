"""Pucks: a halo ring of light around each physical puck (its centre left dark, so the marker
and the hand on it are not painted), coloured by state, with a short fading trail."""

from __future__ import annotations

import math
from typing import Callable

import numpy as np
import pygame

from tabletop.drawing import primitives as P
from tabletop.drawing.life import PuckTrace
from tabletop.drawing.palette import PUCK_STATES, TABLE, Color, fade, lighten

Mapper = Callable[[np.ndarray], np.ndarray]


def halo_radius(puck_radius_px: float) -> float:
    """The ring's radius for a puck of ``puck_radius_px`` pixels: just outside its rim."""
    return puck_radius_px * 1.35 + 3.0


def state_color(state: str) -> Color:
    """The halo colour of a puck state (``seen``, ``coasting`` or ``lost``)."""
    return PUCK_STATES.get(state, PUCK_STATES["seen"])


def draw_trail(surf: pygame.Surface, trace: PuckTrace, to_px: Mapper, color: Color,
               t: float, alpha: float, span_s: float) -> None:
    """The puck's recent path as a line that fades with age (newest brightest)."""
    path = list(trace.path)
    if len(path) < 2:
        return
    xy = to_px(np.array([(p[0], p[1]) for p in path] + [(trace.puck.x, trace.puck.y)]))
    ages = [t - p[2] for p in path] + [0.0]
    for i in range(len(xy) - 1):
        k = (1.0 - min(1.0, max(ages[i], 0.0) / span_s)) * alpha
        if k <= 0.04:
            continue
        col = fade(color, 0.55 * k, TABLE)
        w = max(1, int(round(1 + 2.5 * k)))
        a, b = xy[i].tolist(), xy[i + 1].tolist()
        if w > 1:
            pygame.draw.line(surf, col, a, b, w)
        pygame.draw.aaline(surf, col, a, b)


def draw_halo(surf: pygame.Surface, center: tuple[float, float], r_px: float, angle_px: float,
              state: str, alpha: float, t: float, label: pygame.Surface | None = None) -> None:
    """A ring of light around a puck at ``center`` (px) of radius ``r_px``, a bright notch along
    its heading (``angle_px``, screen radians), coloured by ``state``; the centre stays dark."""
    color = state_color(state)
    R = halo_radius(r_px)
    if state == "coasting":   # a prediction: the ring breathes quickly, an operator sees it
        alpha *= 0.7 + 0.3 * math.sin(t * 9.0)
    if state == "lost":
        R *= 1.0 + 0.4 * (1.0 - alpha)
    P.ring(surf, center, R, max(1.5, 0.16 * r_px), color, 0.75 * alpha)
    ring_col = fade(lighten(color, 0.25), alpha)
    x, y = int(round(center[0])), int(round(center[1]))
    rr = int(round(R))
    pygame.draw.circle(surf, ring_col, (x, y), rr, width=2)
    import pygame.gfxdraw as gfx
    gfx.aacircle(surf, x, y, rr, ring_col)
    gfx.aacircle(surf, x, y, rr - 1, ring_col)
    if state != "lost":
        n = (center[0] + math.cos(angle_px) * R, center[1] + math.sin(angle_px) * R)
        P.disc(surf, fade((255, 255, 255), alpha), n, max(2.5, 0.14 * r_px))
    if label is not None:
        surf.blit(label, (x + rr * 0.75, y - rr - label.get_height() * 0.6))
