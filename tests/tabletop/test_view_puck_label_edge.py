"""A puck's id (the overlay's, beside its ring) stays in the window: with a calibration whose
table fills the projector's image, a puck by the table's far or right edge had its id drawn
out of the window, a ring without its id; now it stands at another side of the ring."""

import numpy as np
import pygame
import pytest

from tabletop.frames import Frame, Puck
from tabletop.view import Renderer

from tests.tabletop.test_view import rgb

pytestmark = pytest.mark.usefixtures("pygame_display")

TABLE, SIZE = (1.2, 0.8), (1280, 720)
FILLED_H = np.array([[1280 / 1.2, 0.0, 0.0], [0.0, -720 / 0.8, 720.0], [0.0, 0.0, 1.0]])
IN = 0.032     # a puck's centre this far (m) from the edges: its rim at the table's edge


def label_pixels(x: float, y: float) -> tuple[np.ndarray, tuple[float, float]]:
    """The window pixels (bool, rows x columns) a puck's id changes with the puck at (x, y)
    table metres, and the puck's window pixel: the view drawn twice with the overlay, once
    with the id blank."""
    shots = []
    for blank in (False, True):
        r = Renderer(TABLE, SIZE, homography=FILLED_H)
        if blank:
            real = r._label
            r._label = lambda pid: pygame.Surface(real(pid).get_size(), pygame.SRCALPHA)
        surface = pygame.Surface(SIZE)
        for i in range(12):
            r.draw(surface, Frame(i, i / 30, pucks=(Puck(5, x, y, 0.0),)), ["tick"])
        shots.append(rgb(surface).astype(int))
    return np.abs(shots[0] - shots[1]).sum(axis=2) > 30, r.map.point(x, y)


@pytest.mark.parametrize("x, y", [(IN, 0.8 - IN), (0.6, 0.8 - IN), (1.2 - IN, 0.8 - IN),
                                  (1.2 - IN, 0.4), (1.2 - IN, IN), (0.6, 0.4)])
def test_a_pucks_id_is_drawn_whole_beside_its_ring_wherever_the_puck_is(x, y):
    shown, (px, py) = label_pixels(x, y)
    rows, cols = np.nonzero(shown)
    # measured: by the far or the right edge the id "5" changed no pixel before (out of the
    # window), 58-60 after; 56-80 wherever it was whole before; all within 70 px of the puck
    assert len(rows) >= 40
    assert np.hypot(cols - px, rows - py).max() < 90


def test_an_id_about_a_whole_pixel_is_placed_as_worked_out_there():
    """The sides worked out once about pixel (0, 0) and moved to a puck's whole pixel place
    every id as working them out at its place does (a float centre: worked out there), in
    every orientation, in and out of the window: 20,000 random placements."""
    import random

    from tabletop.drawing.pucks import label_place
    from tabletop.drawing.reading import _ORIENTATIONS, Reading
    rnd = random.Random(5)
    moved = 0
    for _ in range(20000):
        reading = Reading(*rnd.choice(_ORIENTATIONS))
        size, r = (rnd.randint(5, 60), rnd.randint(5, 60)), rnd.randint(0, 80)
        x, y = rnd.randint(-100, 1400), rnd.randint(-100, 800)
        window = pygame.Rect(0, 0, rnd.choice([1280, 800, 100]), rnd.choice([720, 600, 90]))
        at = label_place(reading, size, (x, y), r, window)
        assert at == label_place(reading, size, (float(x), float(y)), r, window)
        moved += not window.contains(at)
    assert moved < 20000
