"""The operator panel narrowed to end before a character (the MOP example's, 320 px at 1280x720)
keeps each stage row on one line: the figures bare under a head row saying their words once
("ms median", "ms p99"), each column lined up, every figure seen; drawn on real surfaces."""

import numpy as np
import pygame
import pytest

from tabletop.drawing import screens
from tabletop.frames import CharacterState, Frame, SourceHealth
from tabletop.loop import LoopStats
from tabletop.view import overlay_lines

from tests.tabletop.test_view import rgb

pytestmark = pytest.mark.usefixtures("pygame_display")

STAGES = ("capture_age", "inputs", "engines", "sinks", "tick", "engine:mop", "sink:view")
CHARACTERS = ("dancer", "bird", "salamander", "face", "gecko", "mime")


def mop_overlay() -> list[str]:
    """The MOP example's overlay: 7 stage rows, its scripted source and six characters."""
    st = LoopStats()
    for i, stage in enumerate(STAGES):
        for k in range(50):
            st.record(stage, 0.001 * (k % 9 + 1) * (i + 1) + (0.13 if k == 0 else 0.0))
    frame = Frame(seq=231, t=5.7, health=(SourceHealth("performers", True, "scripted visitor",
                                                       0.0),),
                  characters=tuple(CharacterState(n, 0.3, 0.3, 0.0, label="no action")
                                   for n in CHARACTERS))
    return overlay_lines(frame, st)


def rows_of(img: pygame.Surface) -> list[tuple[int, int]]:
    """The text rows of a panel image (top, bottom px): runs of pixel rows holding lit text."""
    lit = (rgb(img).sum(axis=2) > 300).any(axis=1)
    edges = np.flatnonzero(np.diff(np.r_[0, lit.astype(int), 0]))
    return list(zip(edges[::2], edges[1::2]))


@pytest.mark.parametrize("px, width", [(20, 320), (16, 260)])
def test_a_narrowed_panel_keeps_each_stage_row_on_one_line(px, width, monkeypatch):
    lines = mop_overlay()
    img = screens.panel(lines, px, 10, width=width, keep=False)
    # measured at 20 px, 320 px wide: 24 text rows, 426 px tall, when each stage row split in
    # two (name, then figures); now 18 rows (a head row, 7 stage rows, the source's line
    # wrapped in two, the rest), 324 px tall (16 px, 260 px wide: 26 rows -> 18, 354 -> 270 px)
    assert img.get_width() <= width
    assert len(rows_of(img)) == len(lines) + 2, (len(rows_of(img)), len(lines))
    monkeypatch.setattr(screens, "_bare_table", lambda *a: None)
    split = screens.panel(lines, px, 10, width=width, keep=False)
    assert img.get_height() < 0.8 * split.get_height(), (img.get_height(), split.get_height())


def test_the_bare_figures_stand_in_right_aligned_columns_under_their_words():
    lines = mop_overlay()
    img = screens.panel(lines, 20, 10, width=320, keep=False)
    lit = rgb(img).sum(axis=2) > 300
    rows = rows_of(img)
    table = rows[2:3 + len(STAGES)]            # the head row and the stage rows
    ends = [int(np.flatnonzero(lit[a:b].any(axis=0)).max()) for a, b in table]
    assert max(ends) - min(ends) <= 1, ends            # the p99 column ends alike
    assert max(ends) <= img.get_width() - 10           # inside the panel's padding
    # two figure columns in every stage row: a gap of no light between them
    for a, b in table[1:]:
        cols = lit[a:b].any(axis=0)
        runs = np.flatnonzero(np.diff(np.r_[0, cols.astype(int), 0]))[::2]
        assert len(runs) >= 3, runs      # the name, the median, the p99


def test_cells_with_different_words_still_split_each_row():
    """A table whose cells say different words (not the overlay's) keeps the two-line rows."""
    lines = ["head", "  first stage name\t1.00 ms median\t2.00 ms p99",
             "  second stage name\t3.00 frames\t4.00 ms p99"]
    img = screens.panel(lines, 20, 10, width=260, keep=False)
    assert len(rows_of(img)) == 5, len(rows_of(img))    # its two rows in two lines each
