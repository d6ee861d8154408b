"""A hinted pose (MOP early feedback) drawn as the faint light it is: the suspected action's
pose in the character's own lively colour, casting no glow, drawn on black and added onto the
view, so it only brightens what lies under it."""

from __future__ import annotations

import dataclasses
from typing import Callable

import numpy as np
import pygame

from tabletop.drawing.characters import Pose
from tabletop.drawing.palette import Color, vivid

HINT_ALPHA = 0.5         # opacity of a hinted pose (early feedback) at probability 1
HINT_SHOWN = 0.03        # a hinted pose is drawn while its strength (0..1) is above this


def hinted_pose(pose: Pose, color: Color, hint: float) -> Pose:
    """The faint pose of a character's suspected action: ``pose`` at :data:`HINT_ALPHA` times
    the ``hint``'s strength (0..1), in the character's ``color`` at full value and saturation
    0.8, casting no glow, faded toward black (it is added as light, :class:`AddedLight`).
    Lightened toward white instead, a faint pose added onto the navy table read grey for the
    warm and pale characters (the bird's: CIELAB chroma 1.8, its hue 72 degrees off); saturated
    its hue stays within 24 degrees of the character's and it is fainter than the character
    acting (luminance 2.0 to 2.8 times lower at probability 1, 1.6 before)."""
    return dataclasses.replace(pose, alpha=pose.alpha * HINT_ALPHA * hint, light=0.0,
                               color=vivid(tuple(color), 1.0, 0.8, 0.8), ground=(0, 0, 0))


def as_points(hint: tuple[Pose, np.ndarray] | None) -> tuple[Pose, np.ndarray] | None:
    """A hinted pose with its points as the compiled drawing takes them (N x 2 floats)."""
    if hint is None:
        return None
    return hint[0], np.ascontiguousarray(hint[1], dtype=np.float64).reshape(-1, 2)


class AddedLight:
    """A black scratch surface the size of the view: what is drawn on it is added onto the
    view. Painted over the table with the character's inks faded toward the table's colour, a
    faint pose crossing the character's own glow put out its light: a dark shadow of the pose
    on the glow (a salamander's hinted tail, 1024x768), its pupils darker still."""

    def __init__(self) -> None:
        self._scratch: pygame.Surface | None = None

    def add(self, target: pygame.Surface,
            paint: Callable[[pygame.Surface], pygame.Rect | None]) -> pygame.Rect | None:
        """What ``paint`` draws on black (a pose faded toward black, ``Pose.ground``), added
        onto ``target``; returns the rectangle it touched there."""
        scratch = self._scratch
        if scratch is None or scratch.get_size() != target.get_size():
            scratch = self._scratch = pygame.Surface(target.get_size(), 0, target)
            scratch.fill((0, 0, 0))
        r = paint(scratch)
        if r is None:
            return None
        r = r.clip(target.get_rect())
        target.blit(scratch, r, r, pygame.BLEND_RGB_ADD)
        # black again (multiplied by black: a sixth of a plain fill's time here, 0.03 ms for
        # a 300 x 220 px figure)
        scratch.fill((0, 0, 0), r, pygame.BLEND_RGB_MULT)
        return r
