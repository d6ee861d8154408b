"""A figure drawn as a camera sees it (a touch-posed humanoid, ``CharacterState.facing``) shows
its face as seen: two eyes from the front, one in profile, none from behind."""

import numpy as np
import pygame
import pytest

from tabletop.frames import CharacterState
from tabletop.view import Renderer

from tests.tabletop.test_view import TABLE

pytestmark = pytest.mark.usefixtures("pygame_display")

# a stick figure standing up the table (metres): pelvis, chest, neck, head; two legs
POINTS = np.array([[0.6, 0.30], [0.6, 0.40], [0.6, 0.46], [0.6, 0.50], [0.57, 0.20],
                   [0.63, 0.20]])
BONES = ((0, 1), (1, 2), (2, 3), (0, 4), (0, 5))


def eyes(facing: tuple[float, float, float] | None) -> tuple[float, float]:
    """The eye whites and pupils (white or black: every channel within 40 of the others, their
    mean above 180 or below 70; the figure's glow on the red ground is a mid grey) of the
    figure facing ``facing``, drawn at 1280x720: (their area in px, the mean x of their
    pixels less the head's, px)."""
    c = CharacterState("poser", 0.6, 0.3, 0.0, kind="humanoid", size=0.3, points=POINTS,
                       bones=BONES, color=(120, 220, 255), facing=facing)
    surf = pygame.Surface((1280, 720))
    surf.fill((150, 30, 0))
    r = Renderer(TABLE, (1280, 720))
    r.draw_character(surf, c)
    img = pygame.surfarray.array3d(surf).astype(int)
    mean = img.mean(axis=2)
    grey = (img.max(axis=2) - img.min(axis=2) <= 40) & ((mean > 180) | (mean < 70))
    xs, _ = np.nonzero(grey)
    head_x = r.map.point(*POINTS[3])[0]
    return float(grey.sum()), float(xs.mean() - head_x) if len(xs) else 0.0


def test_a_profile_shows_one_eye_on_the_side_it_faces():
    """Measured: 143 px of eyes from the front; 69 / 71 in profile, 9.9 px toward the face
    (both eyes, 143 px, centred on the head before)."""
    front, _ = eyes((0.0, 0.0, 1.0))
    right, rx = eyes((1.0, 0.0, 0.0))
    left, lx = eyes((-1.0, 0.0, 0.0))
    assert 0.35 * front < right < 0.65 * front and 0.35 * front < left < 0.65 * front
    assert rx > 5 and lx < -5


def test_the_back_of_the_head_shows_no_eyes():
    assert eyes((0.0, 0.0, -1.0))[0] == 0.0
    assert eyes((0.7, 0.0, -0.7))[0] == 0.0


def test_from_the_front_it_is_drawn_as_before():
    """Measured: 143 px against 145 seen from above (the pupils look at the viewer)."""
    assert eyes((0.0, 0.0, 1.0))[0] == pytest.approx(eyes(None)[0], rel=0.1)
