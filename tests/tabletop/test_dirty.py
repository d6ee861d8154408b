"""Dirty tiles (tabletop/drawing/dirty.py): the rectangles a frame repaints and presents cover
every pixel drawn, never overlap, and cover little more than what was drawn."""

import numpy as np
import pygame

from tabletop.drawing import dirty

SIZE = (640, 360)


def coverage(rects, size=SIZE):
    """How many of the given rectangles cover each pixel (rows x columns)."""
    n = np.zeros((size[1], size[0]), dtype=int)
    for r in rects:
        c = pygame.Rect(r).clip(pygame.Rect((0, 0), size))
        n[c.top:c.bottom, c.left:c.right] += 1
    return n


def test_tiles_cover_every_drawn_pixel_once_and_little_else():
    rng = np.random.default_rng(4)
    for trial in range(20):
        drawn = [pygame.Rect(int(x), int(y), int(w), int(h)) for x, y, w, h in
                 zip(rng.integers(-60, 620, 6), rng.integers(-60, 340, 6),
                     rng.integers(1, 90, 6), rng.integers(1, 90, 6))] + [None]
        boxes = dirty.rectangles(dirty.mark(SIZE, drawn), SIZE)
        cover = coverage(boxes)
        painted = coverage([r.inflate(2 * dirty.PAD, 2 * dirty.PAD) for r in drawn if r])
        if boxes == [pygame.Rect((0, 0), SIZE)]:
            assert np.count_nonzero(painted) > 0.2 * SIZE[0] * SIZE[1]
            continue
        assert cover.max() <= 1, f"trial {trial}: rectangles overlap"
        assert np.all(cover[painted > 0] == 1), f"trial {trial}: a drawn pixel is not repainted"
        # whole tiles: at most a tile's width around what was drawn
        grown = coverage([r.inflate(2 * dirty.PAD + 2 * dirty.TILE, 2 * dirty.PAD + 2 * dirty.TILE)
                          for r in drawn if r])
        assert np.all(grown[cover > 0] > 0), f"trial {trial}: a far pixel is repainted"


def test_two_rectangles_crossing_are_not_repainted_as_their_bounding_box():
    a, b = pygame.Rect(40, 40, 400, 40), pygame.Rect(40, 40, 40, 280)   # an L
    boxes = dirty.rectangles(dirty.mark(SIZE, [a, b]), SIZE)
    area = sum(r.w * r.h for r in boxes)
    drawn = np.count_nonzero(coverage([a, b]))
    assert area < 0.45 * a.union(b).w * a.union(b).h      # not the 400 x 280 box
    assert area < 2.0 * drawn


def test_more_than_half_the_target_is_presented_whole():
    boxes = dirty.rectangles(dirty.mark(SIZE, [pygame.Rect(0, 0, 500, 300)]), SIZE)
    assert boxes == [pygame.Rect((0, 0), SIZE)]
    assert dirty.rectangles(dirty.mark(SIZE, []), SIZE) == []


def test_a_glow_repaints_the_tiles_of_its_disc_not_its_dark_corners():
    from tabletop.drawing import primitives as P
    for (x, y), radius in (((200.3, 150.6), 120.0), ((30.0, 340.0), 70.0), ((333.0, 20.0), 9.0)):
        surf = pygame.Surface(SIZE)
        lit = P.glow(surf, (x, y), radius, (255, 255, 255), 1.0)
        changed = pygame.surfarray.array3d(surf).max(axis=2).T > 0
        boxes = dirty.rectangles(dirty.mark(SIZE, [P.union([lit, None])]), SIZE)
        cover = coverage(boxes)
        assert np.all(cover[changed] == 1), f"glow at {(x, y)}: a lit pixel is not repainted"
        square = np.count_nonzero(coverage(dirty.rectangles(dirty.mark(
            SIZE, [pygame.Rect(lit)]), SIZE)))
        if radius > 50:      # (a small glow's disc touches its square's every tile)
            assert np.count_nonzero(cover) < 0.92 * square


def test_joined_rectangles_still_cover_every_tile_once_and_add_little():
    rng = np.random.default_rng(7)
    fewer = 0
    for trial in range(20):
        drawn = [pygame.Rect(int(x), int(y), int(w), int(h)) for x, y, w, h in
                 zip(rng.integers(-20, 600, 9), rng.integers(-20, 330, 9),
                     rng.integers(1, 60, 9), rng.integers(1, 60, 9))]
        grid = dirty.mark(SIZE, drawn)
        tiles = dirty.rectangles(grid, SIZE)
        joined = dirty.rectangles(grid, SIZE, 2000)
        if tiles == [pygame.Rect((0, 0), SIZE)]:
            continue
        cover, was = coverage(joined), coverage(tiles)
        assert cover.max() <= 1, f"trial {trial}: joined rectangles overlap"
        assert np.all(cover[was > 0] == 1), f"trial {trial}: a tile is not presented"
        assert len(joined) <= len(tiles)
        fewer += len(joined) < len(tiles)
        # each join adds at most the slack
        assert np.count_nonzero(cover) - np.count_nonzero(was) <= 2000 * (len(tiles) - len(joined))
    assert fewer >= 10


def test_a_light_is_blitted_without_a_dark_border():
    """Glows and halo rings are pre-rendered as the square of their lit pixels: no row or
    column of black around them to blend and repaint every frame, their centre still the
    square's centre pixel, the ramp the same."""
    from tabletop.drawing import primitives as P
    lights = [P.glow_surface(r, (240, 170, 60), 0.3) for r in (9.0, 55.0, 110.0)]
    lights += [P.ring_surface(r, w, (90, 200, 255), 0.8) for r, w in ((45, 6.2), (60, 8.0))]
    for g in lights:
        v = pygame.surfarray.array3d(g).max(axis=2)
        n = v.shape[0]
        assert v.shape == (n, n) and n % 2 == 1
        for edge in (v[0], v[-1], v[:, 0], v[:, -1]):
            assert edge.max() > 0, "a dark row or column around the light"
        assert np.array_equal(v, v[::-1]) and np.array_equal(v, v[:, ::-1])   # centred
    glow = pygame.surfarray.array3d(lights[2]).max(axis=2)
    c = glow.shape[0] // 2
    assert glow[c, c] == glow.max()               # brightest in the middle, fading out
    assert glow[c, 0] < 0.05 * glow.max()
