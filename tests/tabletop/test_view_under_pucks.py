"""Characters are drawn on the table under the pucks: where a physical puck stands, its top (the
marker the camera reads, the hand on it) is not painted by a character passing under it, as it
is not by the puck's own halo. Real pygame surfaces, offscreen."""

import numpy as np
import pygame
import pytest

from tabletop.frames import CharacterState, Frame, Puck
from tabletop.renderer import Renderer

TABLE, SIZE = (1.2, 0.8), (1280, 720)
RADIUS_M = 0.03
AT = (0.6, 0.4)


pytestmark = pytest.mark.usefixtures("pygame_display")


def drawn(characters, pucks, renderer=None, steps=6):
    """The settled image (H, W, 3 ints) and the bare table's, and the renderer."""
    r = renderer or Renderer(TABLE, SIZE, margin=24, puck_radius=RADIUS_M)
    surface = pygame.Surface(SIZE)
    for k in range(steps + 1):                      # (characters fade in over ~0.5 s)
        r.draw(surface, Frame(seq=k, t=k / steps, pucks=pucks, characters=characters))
    bare = r._background(surface)
    img = pygame.surfarray.array3d(surface).transpose(1, 0, 2).astype(int)
    return img, pygame.surfarray.array3d(bare).transpose(1, 0, 2).astype(int), r


def lit_over_table(img, table, centre, radius_px):
    """The most light (sum of channels over the bare table) within ``radius_px`` of
    ``centre`` (px)."""
    yy, xx = np.mgrid[0:SIZE[1], 0:SIZE[0]]
    inside = (xx - centre[0]) ** 2 + (yy - centre[1]) ** 2 <= radius_px ** 2
    return int((img.sum(axis=2) - table.sum(axis=2))[inside].max())


REACTOR = CharacterState("lover", *AT, 0.0, size=0.08, color=(240, 110, 150))
LIMB = CharacterState("stick", *AT, 0.0, kind="creature", size=0.3, color=(90, 220, 120),
                      points=np.array([[0.45, 0.4], [0.6, 0.4], [0.75, 0.4]]),
                      bones=((0, 1), (1, 2)))


@pytest.mark.parametrize("character", [REACTOR, LIMB], ids=["reactor", "figure"])
@pytest.mark.parametrize("state", ["seen", "coasting"])
def test_a_character_under_a_puck_leaves_the_pucks_top_dark(character, state):
    """A reactor standing on a puck and a figure's limb crossing it: inside the puck's rim the
    table is bare (drawn over it, the reactor lit the puck's centre 505 over the table, the
    limb 490), and the character is drawn right up to it (outside the halo, unchanged)."""
    img, table, r = drawn((character,), (Puck(1, *AT, 0.5, state=state),))
    cx, cy, ppm, _ = r.map.place(*AT, 0.0)
    rim = RADIUS_M * ppm                                   # the puck's rim, px (25.2)
    assert lit_over_table(img, table, (cx, cy), rim - 1.0) <= 6
    without, _, _ = drawn((character,), ())
    if character is LIMB:                                   # the limb beyond the halo: as ever
        for side in (-1, 1):
            q = (int(round(cx + side * 0.06 * ppm)), int(round(cy)))
            assert img[q[1], q[0]].sum() > table[q[1], q[0]].sum() + 150
            assert np.abs(img[q[1], q[0]] - without[q[1], q[0]]).max() <= 2
    else:                                                   # between the rim and the halo
        q = (int(round(cx - rim - 3.0)), int(round(cy)))
        assert img[q[1], q[0]].sum() > table[q[1], q[0]].sum() + 150


def test_a_puck_over_nothing_and_a_character_away_from_pucks_are_drawn_as_before():
    """Nothing under the puck: its centre is the bare table; a character far from every puck
    is not touched."""
    img, table, r = drawn((REACTOR,), (Puck(1, 0.05, 0.05, 0.0),))  # (beyond its gaze)
    alone, _, _ = drawn((REACTOR,), ())
    cx, cy = r.map.point(*AT)
    box = (slice(int(cy) - 40, int(cy) + 41), slice(int(cx) - 40, int(cx) + 41))
    assert np.array_equal(img[box], alone[box])
    px, py = r.map.point(0.05, 0.05)
    assert lit_over_table(img, table, (px, py), 24.0) == 0


def test_a_puck_past_the_tables_edge_does_not_darken_what_is_drawn_on_the_edge():
    """A puck reported beyond the edge is drawn on the edge (violet): it is not there, so a
    limb along the edge keeps its light inside that ring."""
    c = CharacterState("stick", 0.01, 0.4, 0.0, kind="creature", size=0.3, color=(90, 220, 120),
                       points=np.array([[0.01, 0.3], [0.01, 0.5]]), bones=((0, 1),))
    img, table, r = drawn((c,), (Puck(1, -0.2, 0.4, 0.0),))
    alone, _, _ = drawn((c,), ())
    x, y = (int(round(v)) for v in r.map.point(0.01, 0.4))
    assert img[y, x].sum() > table[y, x].sum() + 150
    assert np.abs(img[y, x] - alone[y, x]).max() <= 2


def test_the_bare_table_is_put_back_through_another_pixel_format():
    """The kernel reads the bare table in its own format: onto a surface with alpha (another
    channel layout) the disc gets the table's colours, the rim a blend, the rest unchanged."""
    from tabletop.drawing import raster
    from tabletop.drawing.discs import uncover
    bare = pygame.Surface((64, 64), 0, 32)
    for y in range(64):
        bare.fill((20 + y, 40, 200 - y), (0, y, 64, 1))
    target = pygame.Surface((64, 64), pygame.SRCALPHA, 32)
    target.fill((250, 10, 10, 255))
    assert raster.surface_format(target)[3] != raster.surface_format(bare)[3]
    raster.draw(target, uncover, *raster.pixels(bare), np.array([(32.0, 30.0, 12.0)]))
    got = pygame.surfarray.array3d(target).transpose(1, 0, 2).astype(int)
    want = pygame.surfarray.array3d(bare).transpose(1, 0, 2).astype(int)
    yy, xx = np.mgrid[0:64, 0:64]
    d = np.hypot(xx - 32.0, yy - 30.0)
    assert np.array_equal(got[d <= 11.4], want[d <= 11.4])
    assert (pygame.surfarray.array_alpha(target).T[d <= 11.4] == 255).all()   # opaque
    assert (got[d >= 12.6] == (250, 10, 10)).all()
    rim = (d > 12.0) & (d < 12.4)
    assert rim.any() and (got[rim][:, 0] < 250).all() and (got[rim][:, 0] > want[rim][:, 0]).all()


def test_a_bare_table_the_kernel_cannot_read_is_put_back_as_its_colour_at_the_puck():
    """A bare table of another depth (a 16-bit display's) is not read pixel by pixel: the
    puck's disc takes its colour at the puck's centre."""
    from tabletop.drawing import pucks
    from tabletop.table_map import TableToScreen
    m = TableToScreen(TABLE, SIZE, 24)
    bare = pygame.Surface(SIZE, 0, 16)
    bare.fill((40, 60, 80))
    target = pygame.Surface(SIZE, 0, 32)
    target.fill((250, 200, 10))
    pucks.under_pucks(target, bare, (Puck(1, *AT, 0.0),), (), m, RADIUS_M, [target.get_rect()])
    cx, cy = (int(round(v)) for v in m.point(*AT))
    want = bare.get_at((cx, cy))[:3]
    assert tuple(target.get_at((cx + 20, cy))[:3]) == tuple(want)
    assert tuple(target.get_at((cx + 30, cy))[:3]) == (250, 200, 10)


def test_a_puck_is_uncovered_where_its_square_meets_a_drawn_rectangle_as_pygame_meets_them():
    """The compiled mapping and test of which pucks to uncover (one call for all of them) meet
    rectangles as pygame's ``Rect.collidelist`` did: 400 random pucks against random rectangles
    (empty, negative, touching edges) uncover exactly the discs whose square meets one."""
    from tabletop.drawing import raster
    from tabletop.drawing.discs import uncover, uncover_drawn
    rng = np.random.default_rng(7)
    bare = pygame.Surface((96, 96), 0, 32)
    bare.fill((20, 40, 90))
    H = np.array([[800.0, 0.0, 12.0], [0.0, -800.0, 90.0], [0.0, 0.0, 1.0]])
    met = 0
    for _ in range(400):
        x, y, radius_m = rng.uniform(-0.03, 0.13), rng.uniform(-0.01, 0.13), rng.uniform(0, 0.015)
        cx, cy = 800.0 * x + 12.0, -800.0 * y + 90.0
        r = radius_m * 800.0
        rects = [pygame.Rect(*rng.integers(-20, 100, 2), *rng.integers(-4, 30, 2))
                 for _ in range(int(rng.integers(1, 4)))]
        want = pygame.Surface((96, 96), 0, 32)
        want.fill((250, 200, 10))
        got = want.copy()
        box = pygame.Rect(int(cx - r) - 1, int(cy - r) - 1, int(2 * r) + 3, int(2 * r) + 3)
        if box.collidelist(rects) >= 0:
            raster.draw(want, uncover, *raster.pixels(bare), np.array([(cx, cy, r)]))
            met += 1
        raster.draw(got, uncover_drawn, *raster.pixels(bare), np.array([(x, y)]), H, radius_m,
                    np.array([tuple(q) for q in rects], dtype=np.int64).reshape(-1, 4))
        assert np.array_equal(pygame.surfarray.array2d(got), pygame.surfarray.array2d(want))
    assert 20 < met < 380
