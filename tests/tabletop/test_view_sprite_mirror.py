"""A sprite (``view.sprites``: a picture facing +x) reads the right way round on the table
whatever the projector's calibration does to the window: mirrored (rear projection), turned
half round or a quarter, or turned and mirrored, its left side stays on its left. Real pygame
surfaces, offscreen."""

import numpy as np
import pygame
import pytest

from tabletop.frames import CharacterState, Frame
from tabletop.renderer import Renderer

TABLE, SIZE = (1.2, 0.8), (1280, 720)
PLAIN_H = np.array([[840.0, 0.0, 136.0], [0.0, -840.0, 696.0], [0.0, 0.0, 1.0]])
# name: window pixel move of the plain calibration, the moved window's size
TURNS = {"plain": ([[1, 0, 0], [0, 1, 0]], SIZE),
         "mirrored": ([[-1, 0, 1280], [0, 1, 0]], SIZE),
         "half round": ([[-1, 0, 1280], [0, -1, 720]], SIZE),
         "quarter": ([[0, 1, 0], [-1, 0, 1280]], (720, 1280)),
         "quarter, mirrored": ([[0, 1, 0], [1, 0, 0]], (720, 1280))}
GREEN = (0, 255, 0)


pytestmark = pytest.mark.usefixtures("pygame_display")


@pytest.fixture(scope="module")
def sprite(tmp_path_factory):
    """Facing +x: back half blue, front half red, a green stripe along its left side (the top
    rows of the picture: its left, seen from above with the table's +y up)."""
    img = pygame.Surface((40, 20))
    img.fill((0, 0, 255))
    img.fill((255, 0, 0), pygame.Rect(20, 0, 20, 20))
    img.fill(GREEN, pygame.Rect(0, 0, 40, 5))
    path = tmp_path_factory.mktemp("sprites") / "bug.png"
    pygame.image.save(img, str(path))
    return path


@pytest.mark.parametrize("turn", list(TURNS))
@pytest.mark.parametrize("heading", [0.0, 2.0])
def test_a_sprite_keeps_its_left_side_on_its_left_on_the_table(sprite, turn, heading):
    """The green stripe is found 1.8 cm to the sprite's left on the table and not 1.8 cm to
    its right (a mirrored window drew it on the right: the picture was not mirrored back)."""
    move, size = TURNS[turn]
    H = np.vstack([np.array(move, dtype=float), [0.0, 0.0, 1.0]]) @ PLAIN_H
    r = Renderer(TABLE, size, margin=24, homography=H, sprites={"bug": sprite})
    c = CharacterState("bug", 0.6, 0.4, heading, size=0.1)
    surface = pygame.Surface(size)
    for k in range(7):
        r.draw(surface, Frame(seq=k, t=k / 6, characters=(c,)))
    front = np.array([np.cos(heading), np.sin(heading)]) * 0.02
    left = np.array([-np.sin(heading), np.cos(heading)]) * 0.018

    def color(d):
        x, y = (int(round(v)) for v in r.map.point(*(np.array([0.6, 0.4]) + front + d)))
        return tuple(surface.get_at((x, y))[:3])
    on_left, on_right = color(left), color(-left)
    assert on_left[1] > 200 and on_left[0] < 80, on_left          # green
    assert on_right[0] > 200 and on_right[1] < 80, on_right       # the red front
