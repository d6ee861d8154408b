"""The mouse finger's ring and the operator overlay's text are sized with the view: at
1920x1080 they were the pixels they are at 1280x720, two thirds of their size on the table."""

import numpy as np
import pygame
import pytest

from tabletop.frames import Frame
from tabletop.pointer import PointerFingers
from tabletop.view import Renderer

from tests.tabletop.test_view import TABLE, rgb

pytestmark = pytest.mark.usefixtures("pygame_display")


def ring(size: tuple[int, int]) -> tuple[float, float]:
    """A held mouse finger's ring at the table's middle in a ``size`` window: its radius (px,
    the mean distance of its lit pixels from the finger) and its line's width (px, lit pixels
    over its circumference)."""
    r = Renderer(TABLE, size)
    r.pointer = held = PointerFingers()
    held.press(0.6, 0.4)
    s = pygame.Surface(size)
    r.draw(s, Frame(seq=0, t=0.0, touches=held.touches()))
    bare = pygame.Surface(size)
    Renderer(TABLE, size).draw(bare, Frame(seq=0, t=0.0))
    lit = np.argwhere((rgb(s) - rgb(bare)).sum(axis=2) > 150)
    cx, cy = r.map.point(0.6, 0.4)
    d = np.hypot(lit[:, 1] - cx, lit[:, 0] - cy)
    return float(d.mean()), len(lit) / (2 * np.pi * d.mean())


def test_the_finger_ring_is_the_same_size_on_the_table_at_any_resolution():
    small, large = ring((1280, 720)), ring((1920, 1080))
    # measured (the lit pixels' mean distance): 7.9 px, line 1.9 px, at both sizes before;
    # after, the same at 1280x720 and 12.5 px, line 2.9 px at 1920x1080
    assert 7.0 <= small[0] <= 9.0
    assert 1.4 <= large[0] / small[0] <= 1.6
    assert large[1] >= 1.3 * small[1]


def text_height(size: tuple[int, int]) -> int:
    """The tallest run of lit rows of one overlay line (px) in a ``size`` window."""
    r = Renderer(TABLE, size)
    s = pygame.Surface(size)
    rect = r.draw_overlay(s, ["Tabletop 30.0 fps"], avoid=[], must=[])
    lit = (rgb(s)[rect.top:rect.bottom, rect.left:rect.right].sum(axis=2) > 300).any(axis=1)
    return int(np.ptp(np.flatnonzero(lit))) + 1


def test_the_overlay_text_grows_with_the_window():
    small, large = text_height((1280, 720)), text_height((1920, 1080))
    # measured: 12 rows at both before; after 12 and 19
    assert 1.4 <= large / small <= 1.6
    assert text_height((640, 360)) == small         # a small window's as it was


def label_height(size: tuple[int, int]) -> int:
    """The lit rows of puck 7's id (designer mode: the overlay on) in a ``size`` window."""
    r = Renderer(TABLE, size)
    return int(np.ptp(np.flatnonzero(pygame.surfarray.array3d(r._label(7)).sum(axis=2)
                                     .max(axis=0) > 300))) + 1


def test_a_pucks_id_grows_with_the_window_as_the_overlay_does():
    small, large = label_height((1280, 720)), label_height((1920, 1080))
    # measured: 17 rows at both before (a 22 px font); after 17 and 24 (33 px)
    assert 1.3 <= large / small <= 1.6
