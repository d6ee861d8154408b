"""The operator panel's words read as words: no gap inside a word as wide as a space (the font's
hinting at the panel's sizes spread "zigzag" to "zig z ag" and "fps" to "f ps")."""

import numpy as np
import pygame
import pytest

from tabletop.drawing import screens

pytestmark = pytest.mark.usefixtures("pygame_display")

LINE = "zigzag fps inputs salamander running median capture"


def gaps(img: pygame.Surface) -> list[int]:
    """The runs of unlit columns (px) between the line's first and last lit columns."""
    lit = pygame.surfarray.array_alpha(img).max(axis=1) >= 40
    cols = np.flatnonzero(lit)
    out, n = [], 0
    for v in lit[cols[0]:cols[-1] + 1]:
        if not v:
            n += 1
        elif n:
            out.append(n)
            n = 0
    return out


# the panel's sizes at 1280x720 and smaller (but its last, 13 px, where a space is 2 px wide)
# and at 1920x1080
SIZES = sorted({*screens.panel_sizes(720)[:-1], *screens.panel_sizes(1080)})


@pytest.mark.parametrize("px", SIZES)
def test_every_gap_inside_a_word_is_narrower_than_a_space(px):
    runs = sorted(gaps(screens.panel_line(LINE, px, keep=False)), reverse=True)
    spaces = LINE.count(" ")
    assert len(runs) > spaces
    # the narrowest of the widest gaps (one per space) against the widest left (in words)
    assert runs[spaces - 1] > runs[spaces], (px, runs)


def test_a_wrapped_line_stays_inside_the_panels_width():
    line = "source performers: ok  scripted visitor  age 0 ms " * 4
    for px in (13, 20, 30):
        img = screens.panel([line], px, 10, width=300, keep=False)
        assert img.get_width() <= 300, (px, img.get_width())
