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


def lit_rows(img: pygame.Surface) -> list[tuple[int, int]]:
    """The panel's text rows: (top, bottom) runs of pixel rows holding lit text."""
    a = pygame.surfarray.array3d(img).astype(np.int16).sum(axis=2)     # (x, y)
    on = np.flatnonzero((a > 300).any(axis=0))
    runs, start = [], on[0]
    for y0, y1 in zip(on, on[1:]):
        if y1 > y0 + 1:
            runs.append((start, y0))
            start = y1
    return runs + [(start, on[-1])]


def test_a_line_wraps_between_its_fields_before_inside_one():
    """examples/mop.yaml's overlay, narrowed to 320 px at 1280x720 to end before the dancer:
    its source line read "... scripted visitor  age" over "0 ms" (the figure cut from its
    name); it wraps between its fields, on as many lines. Real surface: the last row's lit
    width 32 -> 60 px (20 px font)."""
    line = "source performers: ok  scripted visitor  age 0 ms"
    assert screens.fit_lines(line, screens.Sampled(20), 300) == [
        "source performers: ok  scripted visitor", "age 0 ms"]
    img = screens.panel([line], 20, 10, width=320)
    rows = lit_rows(img)
    assert len(rows) == 2, rows
    a = pygame.surfarray.array3d(img).astype(np.int16).sum(axis=2)
    cols = np.flatnonzero((a[:, rows[1][0]:rows[1][1] + 1] > 300).any(axis=1))
    assert cols[-1] - cols[0] + 1 > 45, (cols[0], cols[-1])
    # a field wider than a line is still cut at its spaces, from where the line stands
    long = "lover: playing lover  " + "waiting for the nearest of two mains " * 3
    assert all(screens.Sampled(20).size(p)[0] <= 300
               for p in screens.fit_lines(long, screens.Sampled(20), 300))
    assert screens.fit_lines(long, screens.Sampled(20), 300)[0].startswith(
        "lover: playing lover  waiting")
