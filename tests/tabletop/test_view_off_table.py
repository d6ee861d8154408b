"""The projector view of pucks beyond the table (a serial or TUIO sender's coordinates past its
edge): drawn on the edge, continuously with the table's inside, violet once a puck radius past
it (a seen puck; a predicted one keeps its amber breathing), the notch pointing where they went;
the margin lit no farther than a ring on the edge reaches."""

import math

import numpy as np
import pygame
import pytest

from tabletop.drawing.palette import PUCK_COASTING, PUCK_OFF, PUCK_SEEN
from tabletop.drawing.pucks import inside_edge
from tabletop.frames import Frame, Puck
from tests.tabletop.test_view import TABLE, SIZE, new_renderer, rgb

pytestmark = pytest.mark.usefixtures("pygame_display")

R = 0.03                 # the renderer's puck radius (m)


def shown(*pucks, table=TABLE):
    drawn, beyond = inside_edge(pucks, table, R)
    return [(p.x, p.y) for p in drawn], beyond


def test_a_puck_on_the_edge_and_just_past_it_is_drawn_in_the_same_place_and_colour():
    w, h = TABLE
    assert shown(Puck(1, w, 0.4, 0.0)) == ([(w, 0.4)], frozenset())
    assert shown(Puck(1, w + 1e-6, 0.4, 0.0)) == ([(w, 0.4)], frozenset())
    assert shown(Puck(1, w + 0.9 * R, 0.4, 0.0)) == ([(w, 0.4)], frozenset())
    (xy,), beyond = shown(Puck(1, w + 1.1 * R, 0.4, 0.0))
    assert xy == (w, 0.4) and beyond == {1}
    (p,), _ = inside_edge([Puck(1, -0.2, 0.4, 1.0)], TABLE, R)
    assert p.angle == math.pi and p.state == "seen"      # its notch toward where it is


def test_a_puck_past_a_corner_is_drawn_on_the_corner_violet_by_its_distance():
    w, h = TABLE
    (p,), beyond = inside_edge([Puck(3, w + 0.1, h + 0.1, 0.0)], TABLE, R)
    assert (p.x, p.y) == (w, h) and beyond == {3}
    assert abs(p.angle - math.pi / 4) < 1e-9
    # 0.8 R past each edge: 1.13 R from the corner, violet; 0.6 R each: 0.85 R, not
    assert shown(Puck(3, w + 0.8 * R, h + 0.8 * R, 0.0))[1] == {3}
    assert shown(Puck(3, -0.6 * R, -0.6 * R, 0.0)) == ([(0.0, 0.0)], frozenset())


def test_not_finite_pucks_are_left_to_the_kernel_and_a_narrow_table_clamps_inside_it():
    nan, inf = Puck(1, math.nan, 0.4, 0.0), Puck(2, math.inf, -math.inf, 0.0)
    drawn, beyond = inside_edge([nan, inf, Puck(3, 0.5, 0.4, 0.0)], TABLE, R)
    assert drawn[0] is nan and drawn[1] is inf and beyond == frozenset()
    narrow = (0.05, 0.8)                     # narrower than two puck radii
    assert shown(Puck(1, 0.3, 0.4, 0.0), table=narrow) == ([(0.05, 0.4)], {1})
    assert shown(Puck(1, -0.3, 0.9, 0.0), table=narrow) == ([(0.0, 0.8)], {1})


def test_a_puck_beyond_the_table_is_drawn_on_its_edge_pointing_where_it_went():
    r = new_renderer()
    s = pygame.Surface(SIZE)
    for k in range(12):      # puck 1 slides off the right edge, puck 2 sits below the table
        r.draw(s, Frame(k, k / 30, pucks=(Puck(1, 1.05 + 0.03 * k, 0.4, 0.0),
                                          Puck(2, 0.3, -0.1, 0.0))))
    img = rgb(s)
    (x0, y1), (x1, y0) = r.map.point(0, TABLE[1]), r.map.point(TABLE[0], 0)
    margin = np.ones(img.shape[:2], bool)
    margin[int(y1):int(y0) + 1, int(x0):int(x1) + 1] = False
    ys, xs = np.nonzero((img.sum(axis=2) > 60) & margin)
    centres = np.array([r.map.point(TABLE[0], 0.4), r.map.point(0.3, 0.0)])
    gone = np.hypot(xs[:, None] - centres[:, 0], ys[:, None] - centres[:, 1]).min(axis=1)
    assert gone.max() < 45, gone.max()     # within a ring's reach (43 px) of the edge's pucks
    violet = (np.abs(img - np.array(PUCK_OFF)).sum(axis=2) < 60)
    for pid, (x, y), out in ((1, (TABLE[0], 0.4), (1, 0)), (2, (0.3, 0.0), (0, 1))):
        cx, cy = r.map.point(x, y)                       # on the edge
        box = (slice(int(cy) - 40, int(cy) + 41), slice(int(cx) - 40, int(cx) + 41))
        assert violet[box].sum() > 100, (pid, violet[box].sum())
        if pid == 2:
            continue                 # (its notch lies below the window's 24 px margin)
        notch = img[box].min(axis=2) > 200               # the white notch
        ys, xs = np.nonzero(notch)
        assert len(xs), pid
        at = np.array([xs.mean() - 40, ys.mean() - 40])  # from the halo's centre, px
        assert at @ np.array(out) > 15, (pid, at)        # toward the edge it went out of


def ring_colour(state, x):
    """Which of the seen, off-table and predicted colours most pixels around a puck at ``x``
    (m, y 0.4) in ``state`` are near, drawn for a few frames."""
    r = new_renderer()
    s = pygame.Surface(SIZE)
    for k in range(4):
        r.draw(s, Frame(k, k / 30, pucks=(Puck(1, x, 0.4, 0.0, state=state),)))
    img = rgb(s).astype(int)
    cx, cy = r.map.point(min(x, TABLE[0]), 0.4)
    box = img[int(cy) - 45:int(cy) + 46, int(cx) - 45:int(cx) + 46]
    counts = {name: (np.abs(box - np.array(c)).sum(axis=2) < 60).sum()
              for name, c in (("seen", PUCK_SEEN), ("off", PUCK_OFF), ("coasting", PUCK_COASTING))}
    return max(counts, key=counts.get)


def test_a_seen_puck_turns_violet_past_the_edge_and_a_predicted_one_stays_amber():
    w = TABLE[0]
    assert ring_colour("seen", w + 0.5 * R) == "seen"
    assert ring_colour("seen", w + 0.2) == "off"
    assert ring_colour("coasting", w + 0.2) == "coasting"
