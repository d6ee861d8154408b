"""The sprite-sheet bird's eyes read at projector sizes: seen from above, its head is a bird's
(about a fifth of its length across), its eyes a good part of it."""

import json
from pathlib import Path

import numpy as np
import pygame
import pytest

from tabletop.frames import CharacterState
from tabletop.view import Renderer

from tests.tabletop.test_view import TABLE

pytestmark = pytest.mark.usefixtures("pygame_display")

SHEET = json.loads((Path(__file__).resolve().parents[2] / "examples/mop/bird.json").read_text())


def eye_radius(size: tuple[int, int], heading: float) -> float:
    """The radius (px) of each of the example's bird's eyes (0.15 m, the sheet's first frame,
    heading ``heading``) drawn at the table's middle in a ``size`` window: its whites and
    pupils (grey: every channel within 40 of the others) on a yellow bird and a red ground,
    as two discs."""
    c, s = np.cos(heading), np.sin(heading)
    # the sheet's y runs tail to beak: turned so that the beak points along the heading
    pts = np.array(SHEET["frames"][0]) @ np.array([[s, c], [-c, s]]).T * 0.15 + (0.6, 0.4)
    bird = CharacterState("bird", 0.6, 0.4, heading, kind="sprite", size=0.15, points=pts,
                          bones=tuple(map(tuple, SHEET["bones"])), color=(250, 250, 200))
    surf = pygame.Surface(size)
    surf.fill((150, 30, 0))
    Renderer(TABLE, size).draw_character(surf, bird)
    img = pygame.surfarray.array3d(surf).astype(int)
    eye = img.max(axis=2) - img.min(axis=2) <= 40
    return float(np.sqrt(eye.sum() / 2 / np.pi))


@pytest.mark.parametrize("heading", [0.0, 1.1, -2.5])
def test_the_birds_eyes_are_readable_at_1280x720(heading):
    # measured: 2.8-2.9 px before (head 0.06 of its length, eyes 0.32 of it: specks), 5.2-5.3 after
    assert eye_radius((1280, 720), heading) >= 4.0


def test_the_birds_eyes_grow_with_the_view():
    assert eye_radius((1920, 1080), 0.0) >= 1.4 * eye_radius((1280, 720), 0.0)
