"""The compiled shapes cover exactly their area (anti-aliased edges carry the partial pixels), and
draw the same on 24-bit surfaces and subsurfaces as on the 32-bit surfaces they are made for."""

from __future__ import annotations

import math
import os

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")

import numpy as np  # noqa: E402
import pygame  # noqa: E402

from tabletop.drawing import raster  # noqa: E402
from tabletop.drawing.discs import disc  # noqa: E402
from tabletop.drawing.limbs import capsule, cone  # noqa: E402
from tabletop.drawing.polygons import polygon  # noqa: E402

WHITE = 0xFFFFFF


def covered(surf: pygame.Surface) -> np.ndarray:
    """Each pixel's coverage (0..1) by white drawn on black."""
    return pygame.surfarray.array3d(surf)[..., 0] / 255.0


def fresh(size=(200, 160), depth=32) -> pygame.Surface:
    return pygame.Surface(size, 0, depth)


def test_a_polygon_covers_its_exact_area_with_soft_edges():
    s = fresh()
    xs, ys = np.array([30.3, 170.6, 90.1]), np.array([20.7, 60.2, 150.4])
    raster.draw(s, polygon, xs, ys, 3, WHITE)
    cov = covered(s)
    area = 0.5 * abs((xs[1] - xs[0]) * (ys[2] - ys[0]) - (xs[2] - xs[0]) * (ys[1] - ys[0]))
    assert abs(cov.sum() - area) < 0.002 * area
    edge = ((cov > 0.05) & (cov < 0.95)).sum()
    assert edge > 0.8 * (np.hypot(140.3, 39.5) + np.hypot(80.5, 90.2) + np.hypot(60.2, 129.7))
    assert cov[90, 70] == 1.0 and cov[5, 5] == 0.0       # inside, outside


def test_a_disc_and_a_limb_cover_their_areas():
    s = fresh()
    raster.draw(s, disc, 60.4, 70.2, 20.0, WHITE)
    assert abs(covered(s).sum() - math.pi * 20.0 ** 2) < 0.01 * math.pi * 400
    s = fresh()
    raster.draw(s, capsule, 30.2, 40.7, 150.9, 110.3, 6.0, WHITE)
    L = math.hypot(120.7, 69.6)
    area = 2 * 6.0 * L + math.pi * 36.0
    assert abs(covered(s).sum() - area) < 0.015 * area


def test_shapes_off_the_surface_or_not_finite_are_clipped_or_skipped():
    s = fresh()
    raster.draw(s, disc, -5.0, 80.0, 30.0, WHITE)          # half off the left edge
    cov = covered(s)
    assert 0.3 * math.pi * 900 < cov.sum() < 0.7 * math.pi * 900
    s = fresh()
    raster.draw(s, polygon, np.array([10.0, math.nan, 50.0]), np.array([10.0, 20.0, 60.0]),
                3, WHITE)
    raster.draw(s, capsule, 10.0, 10.0, math.inf, 20.0, 3.0, WHITE)
    assert covered(s).sum() == 0.0


def test_24_bit_surfaces_and_subsurfaces_get_the_same_pixels():
    ref = fresh()
    raster.draw(ref, disc, 100.3, 80.6, 25.0, 0xF0A040)
    deep = fresh(depth=24)
    raster.draw(deep, disc, 100.3, 80.6, 25.0, 0xF0A040)
    assert np.array_equal(pygame.surfarray.array3d(deep), pygame.surfarray.array3d(ref))
    big = fresh((300, 260))
    sub = big.subsurface(pygame.Rect(50, 40, 200, 160))
    raster.draw(sub, disc, 100.3, 80.6, 25.0, 0xF0A040)
    assert np.array_equal(pygame.surfarray.array3d(sub), pygame.surfarray.array3d(ref))
    assert pygame.surfarray.array3d(big)[:50].sum() == 0        # nothing outside it


def test_a_tapered_limb_covers_the_hull_of_its_joints():
    s = fresh()
    ra, rb = 12.0, 5.0
    raster.draw(s, cone, 50.3, 60.7, ra, 140.2, 120.9, rb, WHITE)
    cov = covered(s)
    d = math.hypot(140.2 - 50.3, 120.9 - 60.7)
    th = math.acos((ra - rb) / d)          # where the touching lines meet each circle
    area = ra * ra * (math.pi - th) + rb * rb * th + (ra + rb) * d * math.sin(th)
    assert abs(cov.sum() - area) < 0.005 * area
    assert cov[50, 60] == 1.0 and cov[140, 121] == 1.0 and cov[140, 60] == 0.0
    assert cov[50, 60 + 12] > 0.2 and cov[50, 60 - 14] == 0.0    # a's rim, 12 px out
    edge = ((cov > 0.05) & (cov < 0.95)).sum()
    assert edge > 0.8 * (2 * d * math.sin(th) + 2 * ra * (math.pi - th) + 2 * rb * th)
    s2 = fresh()                           # one disc inside the other: that disc
    raster.draw(s2, cone, 80.0, 80.0, 20.0, 84.0, 82.0, 6.0, WHITE)
    assert abs(covered(s2).sum() - math.pi * 400) < 0.01 * math.pi * 400


def test_kernels_draw_through_a_view_that_follows_the_surface_and_leaves_it_unlocked():
    # the same pixels as a kernel run on pixels2d, and the surface can be blitted in between
    ref = fresh()
    disc(pygame.surfarray.pixels2d(ref), raster.surface_format(ref), 100.3, 80.6, 25.0,
                0xF0A040)
    s = fresh()
    raster.draw(s, disc, 100.3, 80.6, 25.0, 0xF0A040)
    assert not s.get_locked()
    assert np.array_equal(pygame.surfarray.array3d(s), pygame.surfarray.array3d(ref))
    spot = pygame.Surface((10, 10), 0, 32)
    spot.fill((0, 0, 255))
    s.blit(spot, (0, 0))                              # (refused while pixels2d locks it)
    raster.draw(s, disc, 150.0, 40.0, 6.0, WHITE)
    assert tuple(s.get_at((5, 5)))[:3] == (0, 0, 255) and covered(s)[150, 40] == 1.0
    # a new surface in the old one's place, and a window whose memory changes, are drawn into
    del s
    again, other = fresh(), fresh((90, 70))
    for k in range(3):                                # two targets in turn: each its own
        raster.draw(again, disc, 30.0 + 40 * k, 30.0, 5.0, WHITE)
        raster.draw(other, disc, 20.0 + 20 * k, 50.0, 3.0, WHITE)
    assert all(covered(again)[30 + 40 * k, 30] == 1.0 for k in range(3))
    assert all(covered(other)[20 + 20 * k, 50] == 1.0 for k in range(3))
    pygame.display.init()
    try:
        for size in ((160, 120), (240, 200)):
            win = pygame.display.set_mode(size)
            win.fill((0, 0, 0))
            raster.draw(win, disc, 100.0, 90.0, 8.0, WHITE)
            lit = pygame.surfarray.array3d(win)[..., 0] > 0
            assert lit[100, 90] and 150 < lit.sum() < 260, size      # pi 8.5^2 ~ 227 px
    finally:
        pygame.display.quit()


def test_runs_filled_at_once_blend_as_pixel_by_pixel_and_keep_what_is_between():
    # A U (concave: rows cross it twice, a notch of untouched pixels between two filled runs)
    # over a translucent ground: inside exactly the colour made opaque, the notch and the
    # outside untouched, the area exact; a tapered limb's and a disc's inner runs likewise.
    s = pygame.Surface((200, 160), pygame.SRCALPHA, 32)
    ground = (20, 40, 60, 64)
    s.fill(ground)
    xs = np.array([20.4, 180.2, 180.2, 130.7, 130.7, 70.3, 70.3, 20.4])
    ys = np.array([140.6, 140.6, 20.2, 20.2, 100.5, 100.5, 20.2, 20.2])
    raster.draw(s, polygon, xs, ys, len(xs), 0xC08040)
    px = pygame.surfarray.pixels3d(s)
    alpha = pygame.surfarray.pixels_alpha(s)
    assert tuple(px[100, 120]) == (0xC0, 0x80, 0x40) and alpha[100, 120] == 255
    assert tuple(px[50, 40]) == (0xC0, 0x80, 0x40) and tuple(px[150, 40]) == (0xC0, 0x80, 0x40)
    assert tuple(px[100, 60]) == ground[:3] and alpha[100, 60] == 64      # the notch
    assert tuple(px[5, 5]) == ground[:3] and alpha[5, 5] == 64
    red = px[..., 0].astype(float)
    cov = (red - ground[0]) / (0xC0 - ground[0])
    area = 160 * 120 - 60 * 80
    assert abs(cov.sum() - area) < 0.002 * area
    del px, alpha
    t = fresh((120, 120))
    t.fill((10, 10, 10))
    raster.draw(t, cone, 20.0, 30.0, 12.0, 100.0, 90.0, 6.0, 0xFFFFFF)
    raster.draw(t, disc, 90.0, 25.0, 15.0, 0xFFFFFF)
    c = covered(t)
    assert c[20, 30] == 1.0 and c[60, 60] == 1.0 and c[90, 25] == 1.0 and c[5, 110] == 10 / 255
