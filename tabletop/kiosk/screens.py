"""The kiosk's calm screens, drawn by the view."""

from __future__ import annotations

import math
import time

import pygame

from tabletop.studio.draw import font

MESSAGE = "one moment"


def draw_one_moment(target: pygame.Surface, t: float | None = None) -> None:
    """A quiet waiting screen (no error text for visitors): a slowly breathing ring and
    "one moment" in the middle. ``t`` (seconds, default the monotonic clock: frame times stand
    still while the input is gone) drives the breathing, 4 s a breath."""
    if t is None:
        t = time.monotonic()
    target.fill((10, 12, 16))
    w, h = target.get_size()
    k = 0.5 + 0.5 * math.sin(2 * math.pi * t / 4.0)
    r = int(min(w, h) * (0.08 + 0.02 * k))
    shade = int(90 + 80 * k)
    pygame.draw.circle(target, (shade, shade, shade + 20), (w // 2, h // 2 - r // 2), r, width=3)
    img = font(44).render(MESSAGE, True, (200, 200, 210))
    target.blit(img, img.get_rect(center=(w // 2, h // 2 + r)))
