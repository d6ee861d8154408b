"""Pucks: a halo ring of light around each physical puck (its centre left dark, so the marker
and the hand on it are not painted), coloured by state, with a short fading trail."""

from __future__ import annotations

import math
from typing import Callable

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
    # age steps (as min(2, max(0, int(v)))): 2 newest, 1, 0 oldest and anything older
    for e in path:
        q = px.get(e)
        if q is None:
            q = px[e] = to_px(e[0], e[1])
        if (q[0] - cx) ** 2 + (q[1] - cy) ** 2 <= hole2:
            continue
        v = 3.0 * (1.0 - (t - e[2]) / span_s)
        k = 2 if v >= 2.0 else 1 if v >= 1.0 else 0
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
    xs, ys = [], []
    for k, q in enumerate(parts):
        if len(q) < 2:
            continue
        col = fade(color, alpha * (0.18, 0.32, 0.5)[k], TABLE)
        if k:
            pygame.draw.lines(surf, col, False, q, 1 + k)
        pygame.draw.aalines(surf, col, False, q)
        xs += [p[0] for p in q]
        ys += [p[1] for p in q]
    if not xs:
        return None
    x0, y0 = int(min(xs)) - 4, int(min(ys)) - 4
    return pygame.Rect(x0, y0, int(max(xs)) + 5 - x0, int(max(ys)) + 5 - y0)


def draw_halo(surf: pygame.Surface, center: tuple[float, float], r_px: float, angle_px: float,
              state: str, alpha: float, t: float,
              label: pygame.Surface | None = None) -> pygame.Rect | None:
    """A ring of light around a puck at ``center`` (px) of radius ``r_px``, a bright notch along
    its heading (``angle_px``, screen radians), coloured by ``state``; the centre stays dark.
    Returns the rectangle it touched."""
    color = state_color(state)
    R = halo_radius(r_px)
    if state == "coasting":   # a prediction: the ring breathes quickly, an operator sees it
        alpha *= 0.7 + 0.3 * math.sin(t * 9.0)
    if state == "lost":
        R *= 1.0 + 0.4 * (1.0 - alpha)
    touched = P.ring(surf, center, R, max(2.0, 0.2 * r_px), color, alpha)
    x, y = int(round(center[0])), int(round(center[1]))
    rr = int(round(R))
    if state != "lost":
        n = (center[0] + math.cos(angle_px) * R, center[1] + math.sin(angle_px) * R)
        P.disc(surf, fade((255, 255, 255), alpha), n, max(2.5, 0.14 * r_px))
    e = int(R + max(3.0, 0.14 * r_px) + 4)
    touched = P.union([touched, pygame.Rect(x - e, y - e, 2 * e + 1, 2 * e + 1)])
    if label is not None:
        touched = P.union([touched, surf.blit(label, (x + rr * 0.75,
                                                     y - rr - label.get_height() * 0.6))])
    return touched
