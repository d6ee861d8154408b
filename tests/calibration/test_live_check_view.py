"""What the projector shows around a live calibration check: the check's image over the whole
window while it is measured, and the whole table again once the show is back."""

import numpy as np
import pygame
import pytest

from tabletop.frames import CharacterState, Frame, Puck
from tabletop.live_check import Showing
from tabletop.renderer import Renderer

SIZE = (640, 400)


pytestmark = pytest.mark.usefixtures("pygame_display")


def frame(seq: int) -> Frame:
    return Frame(seq=seq, t=seq / 60, pucks=(Puck(1, 0.3, 0.3, 0.0),),
                 characters=(CharacterState("lover", 0.5, 0.4, 0.0, size=0.08,
                                            color=(240, 110, 150)),))


def test_the_table_is_whole_again_after_the_check_image():
    """The check's dark image painted the whole window; the view repainted only the tiles its
    characters and pucks had drawn, so the table came back as a few lit patches in black
    (seen in an Xvfb snapshot with ``view.calibration_check: true``)."""
    inner = Renderer((1.2, 0.8), SIZE, margin=24)
    inner.incremental = True
    showing = Showing(inner, clock=lambda: 0.0)
    screen = pygame.Surface(SIZE)
    for k in range(5):
        showing.draw(screen, frame(k))
    before = pygame.surfarray.array3d(screen).astype(int)
    showing.current = (1, pygame.Surface(SIZE))            # the check's image: black
    showing.draw(screen, frame(5))
    # what the window presents is the whole image, not the last show frame's tiles
    assert sum(r.w * r.h for r in showing.dirty) >= SIZE[0] * SIZE[1]
    showing.current = None                                  # back to the show
    showing.draw(screen, frame(6))
    assert sum(r.w * r.h for r in showing.dirty) >= SIZE[0] * SIZE[1]   # presented whole
    after = pygame.surfarray.array3d(screen).astype(int)
    corners = inner._corners()
    inside = np.zeros(SIZE, bool)     # (x, y): the table's area, away from its drawn edge
    x0, y0 = corners.min(axis=0) + 4
    x1, y1 = corners.max(axis=0) - 4
    inside[int(x0):int(x1), int(y0):int(y1)] = True
    lit_before = (before.sum(axis=2) > 0) & inside
    assert lit_before.sum() > 0.9 * inside.sum()     # the table is lit, bar a few grid dots
    black = (after.sum(axis=2) == 0) & lit_before
    assert black.sum() == 0, f"{black.sum()} pixels of the table left black"


def test_the_check_image_is_scaled_to_a_window_of_another_size():
    """The check drew its crosses in view.size pixels (the calibration's) into a window the
    display gave at another size, so they landed away from the pucks the view drew: the image
    is scaled to the window, as the view scales the calibration."""
    from tabletop.live_check import shown_surface
    image = np.zeros((200, 320), np.uint8)
    image[50, 60:141] = 255          # a cross at (100, 50) px of the calibration's 320x200
    image[10:91, 100] = 255
    surface = shown_surface(image, (480, 300))
    assert surface.get_size() == (480, 300)
    grey = pygame.surfarray.array3d(surface)[..., 0].astype(int)      # (x, y)
    assert grey[150, 75] > 120                                      # the centre, 1.5 times out
    assert grey[150, 75 + 12] > 120 and grey[150 + 12, 75] > 120     # its bars
    assert grey[100, 50] < 40                                        # not at the unscaled place
    same = shown_surface(image, (320, 200))
    assert pygame.surfarray.array3d(same)[100, 50, 0] == 255
