"""Characters drawn as images (``view.sprites``: a character's name -> a PNG facing +x, drawn
instead of its vector shape): each turned to the character's heading in 2-degree steps and
scaled to its size and breath, under a faint glow of its colour, mirrored where the calibration
mirrors the table; the turned images kept between frames."""

from __future__ import annotations

import math
from pathlib import Path

import pygame

from tabletop.drawing import primitives as P
from tabletop.drawing.characters import Pose
from tabletop.frames import CharacterState
from tabletop.table_map import TableToScreen

#: Turned images kept (by name, heading and size in px) before they are all let go.
CACHE_MAX = 2048


class Sprites:
    """The sprite images by character name, and their turned and scaled renders."""

    def __init__(self, files: dict[str, Path] | None = None) -> None:
        self.images = {name: pygame.image.load(str(p)) for name, p in (files or {}).items()}
        self._cache: dict[tuple[str, int, int], pygame.Surface] = {}

    def __contains__(self, name: str) -> bool:
        return name in self.images

    def draw(self, target: pygame.Surface, c: CharacterState, pose: Pose,
             table_map: TableToScreen) -> pygame.Rect | None:
        """Character ``c``'s image at ``pose`` on ``target``, with its glow; the area drawn."""
        img = self.images[c.name]
        px_size = c.size * pose.ppm * pose.scale * pose.breath
        # Screen y points down: a counter-clockwise table heading is a counter-clockwise rotation
        # on screen when the table's y axis points up the screen (the uncalibrated fit).
        deg = int(round(-math.degrees(pose.angle) / 2.0)) * 2
        key = (c.name, deg % 360, int(px_size))
        surf = self._cache.get(key)
        if surf is None:
            zoom = px_size / max(img.get_width(), 1)
            if table_map.reading().mirrored:   # mirrored across its heading: the table mirrors
                img = pygame.transform.flip(img, False, True)     # it back the right way round
            surf = pygame.transform.rotozoom(img, deg, zoom)
            if len(self._cache) > CACHE_MAX:
                self._cache.clear()
            self._cache[key] = surf
        g = P.glow(target, pose.center, 0.8 * c.size * pose.ppm, pose.color, 0.28 * pose.alpha)
        surf.set_alpha(int(255 * pose.alpha))
        return P.union([g, target.blit(surf, surf.get_rect(center=(int(pose.center[0]),
                                                                    int(pose.center[1]))))])
