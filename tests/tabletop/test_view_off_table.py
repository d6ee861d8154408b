"""The projector view of pucks beyond the table (a serial or TUIO sender's coordinates past its
edge): drawn inside the edge, in the off-table colour, the notch pointing where they went;
nothing lit in the margin around the table."""

import numpy as np
import pygame

from tabletop.drawing.palette import PUCK_OFF
from tabletop.frames import Frame, Puck
from tests.tabletop.test_view import TABLE, SIZE, display, new_renderer, rgb  # noqa: F401


def test_a_puck_beyond_the_table_is_drawn_inside_its_edge_pointing_where_it_went():
    r = new_renderer()
    s = pygame.Surface(SIZE)
    for k in range(12):      # puck 1 slides off the right edge, puck 2 sits below the table
        r.draw(s, Frame(k, k / 30, pucks=(Puck(1, 1.05 + 0.03 * k, 0.4, 0.0),
                                          Puck(2, 0.3, -0.1, 0.0))))
    img = rgb(s)
    (x0, y1), (x1, y0) = r.map.point(0, TABLE[1]), r.map.point(TABLE[0], 0)
    margin = np.ones(img.shape[:2], bool)
    margin[int(y1) - 1:int(y0) + 2, int(x0) - 1:int(x1) + 2] = False
    lit = img.sum(axis=2) > 60
    assert not lit[margin].any(), lit[margin].sum()      # 1296 pixels lit there before
    violet = (np.abs(img - np.array(PUCK_OFF)).sum(axis=2) < 60)
    for pid, (x, y), out in ((1, (TABLE[0] - 0.06, 0.4), (1, 0)), (2, (0.3, 0.06), (0, 1))):
        cx, cy = r.map.point(x, y)                       # two radii inside the edge
        box = (slice(int(cy) - 40, int(cy) + 41), slice(int(cx) - 40, int(cx) + 41))
        assert violet[box].sum() > 100, (pid, violet[box].sum())
        notch = img[box].min(axis=2) > 200               # the white notch
        ys, xs = np.nonzero(notch)
        assert len(xs), pid
        at = np.array([xs.mean() - 40, ys.mean() - 40])  # from the halo's centre, px
        assert at @ np.array(out) > 15, (pid, at)        # toward the edge it went out of
