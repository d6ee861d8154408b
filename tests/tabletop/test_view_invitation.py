"""The idle invitation stands clear of the characters: a tall figure's feet are not drawn over
"touch the table"."""

import functools

import numpy as np
import pygame
import pytest

from tabletop.drawing.screens import INVITATIONS
from tabletop.frames import CharacterState, Frame
from tabletop.view import Renderer

from tests.tabletop.test_view import SIZE, TABLE, rgb

pytestmark = pytest.mark.usefixtures("pygame_display")


def standing(height: float) -> CharacterState:
    """A stick figure standing at the table's middle, ``height`` metres from its feet (at the
    near edge's side, table y smaller) to its head."""
    y0 = 0.4 - height / 2
    pts = np.array([[0.6, y0 + height * k / 4] for k in range(5)])
    return CharacterState("poser", 0.6, 0.4, np.pi / 2, kind="skeleton", size=height,
                          points=pts, bones=((0, 1), (1, 2), (2, 3), (3, 4)),
                          color=(120, 220, 255))


def idle_image(chars: tuple, words: str) -> np.ndarray:
    """The table 6 s after the last touch (the idle look faded in), ``words`` invited."""
    r = Renderer(TABLE, SIZE)
    r.invitation = words
    s = pygame.Surface(SIZE)
    # drawn every 0.3 s over the 6 s: the last image is the one drawn every 0.1 s makes, to the
    # pixel, for the bare table and each figure here with and without the words
    for k in range(0, 61, 3):
        r.draw(s, Frame(seq=k, t=0.1 * k, characters=chars))
    return rgb(s)


@functools.cache
def bare_table() -> np.ndarray:
    """:func:`idle_image` of no character and no words (drawn once; read-only)."""
    img = idle_image((), "")
    img.flags.writeable = False
    return img


def box(mask: np.ndarray) -> pygame.Rect:
    ys, xs = np.nonzero(mask)
    return pygame.Rect(xs.min(), ys.min(), xs.max() - xs.min() + 1, ys.max() - ys.min() + 1)


@pytest.mark.parametrize("height", [0.4, 0.6, 0.7])
def test_the_invitation_does_not_lie_under_a_tall_figure(height):
    fig = (standing(height),)
    quiet = idle_image(fig, "")
    figure = box(np.abs(quiet - bare_table()).sum(axis=2) > 150)   # its body, not glow
    words = np.abs(idle_image(fig, INVITATIONS["touch"]) - quiet).sum(axis=2)
    text = box(words > 40)
    # measured before (always at 0.2 of the table's depth): 1 px under a 0.4 m figure's feet;
    # the words' box (188 x 19 px) 131 x 19 px under a 0.6 m figure's body, all of it under a
    # 0.7 m one's. After: nearer the edge (0.4 m), to the left (0.6 and 0.7 m)
    assert not text.colliderect(figure), (text, figure)
    assert text.w > 150                               # the whole line shows


def test_the_invitation_keeps_its_place_beside_a_small_figure():
    r = Renderer(TABLE, SIZE)
    words = np.abs(idle_image((standing(0.3),), INVITATIONS["touch"])
                   - idle_image((standing(0.3),), "")).sum(axis=2)
    cx, cy = box(words > 40).center
    want = r.map.point(0.6, 0.16)
    assert abs(cx - want[0]) <= 3 and abs(cy - want[1]) <= 4
