"""The operator panel over what it keeps clear of: where no corner leaves it clear, the
characters and pucks under it show through (its ground nearly clear, its text kept), the
studio's words excepted (the panel stays dark over them, its own text readable); with nothing
under it, the panel as it is; moved holes redrawn as a panel made afresh draws them, and a
panel the kernels cannot read (a subsurface) drawn alike."""

import numpy as np
import pygame
import pytest

from tabletop.drawing import screens, see_through
from tabletop.frames import CharacterState, Frame
from tabletop.renderer import Renderer
from tests.tabletop.test_view import TABLE, rgb

pytestmark = pytest.mark.usefixtures("pygame_display")

LINES = ["tick 55   running 1.9 s", "30.8 fps   skipped 1   errors 0",
         *(f"  stage{i}\t1.00 ms median\t2.00 ms p99" for i in range(9)),
         "source scripted: ok   scripted visitor   age 0 ms", "lover wave 0.40"]
SMALL = (640, 360)
GREY = (100, 100, 100)


def panel_on_grey(r: Renderer, avoid, must=()):
    """The panel drawn on a grey window; (its pixels as rgb, its rectangle)."""
    s = pygame.Surface(SMALL)
    s.fill(GREY)
    place = r.draw_overlay(s, LINES, list(avoid), list(must))
    return rgb(s).astype(int), place


def text(img):
    return img.min(axis=2) > 180


def test_a_character_under_the_panel_in_a_small_window_shows_through_the_text_kept():
    """At 640x360 the operator's 13 lines make a panel over the table's centre in every corner:
    the character there keeps 85% of its light under it (measured; the panel drawn alike
    everywhere kept 32%) and the panel's text keeps its pixels."""
    r = Renderer(TABLE, SMALL)
    c = CharacterState("lover", TABLE[0] / 2, TABLE[1] / 2, 0.0, size=0.2, color=(240, 110, 150))
    bare = pygame.Surface(SMALL)
    for k in range(30):                                     # faded in
        r.draw(bare, Frame(k, k / 30, characters=(c,)))
    shown = bare.copy()
    panel = r.draw_overlay(shown, LINES)                    # over what the last frame drew
    a, b = rgb(bare).astype(int), rgb(shown).astype(int)
    ys, xs = np.nonzero(a.sum(axis=2) > 200)                # the character's own light
    body = pygame.Rect(xs.min(), ys.min(), xs.max() - xs.min() + 1, ys.max() - ys.min() + 1)
    both = panel.clip(body)
    assert both.w * both.h > 0.2 * body.w * body.h, (panel, body)   # the panel lies over it
    cut = (slice(both.top, both.bottom), slice(both.left, both.right))
    lit = a[cut].sum(axis=2) > 200
    kept = np.minimum(b[cut], a[cut])[lit].sum() / a[cut][lit].sum()
    assert kept > 0.7, kept
    dark = pygame.Surface(SMALL)                            # the same panel over nothing
    plain = Renderer(TABLE, SMALL)
    plain.draw_overlay(dark, LINES, [], [])
    over_nothing = text(rgb(dark).astype(int)[cut]).sum()
    assert over_nothing > 50 and text(b[cut]).sum() >= 0.9 * over_nothing


def everywhere(dx: int, dy: int, w: int, h: int) -> list[pygame.Rect]:
    """A ``w`` x ``h`` rectangle ``dx``, ``dy`` px in from each of the window's corners (so
    every corner of the panel hides as much and it stays top-left)."""
    W, H = SMALL
    return [pygame.Rect(x, y, w, h) for x in (dx, W - dx - w) for y in (dy, H - dy - h)]


def test_with_nothing_under_it_the_panel_is_drawn_as_it_is_and_holes_only_where_asked():
    alone, place = panel_on_grey(Renderer(TABLE, SMALL), [])
    away, _ = panel_on_grey(Renderer(TABLE, SMALL), [pygame.Rect(600, 340, 10, 10)])
    assert (alone == away).all()                            # beside it: nothing changes
    holes = everywhere(40, 30, 120, 80)
    holed, at = panel_on_grey(Renderer(TABLE, SMALL), holes)
    assert at == place
    inside = np.zeros(alone.shape[:2], bool)
    for hole in holes:
        inside[hole.top:hole.bottom, hole.left:hole.right] = True
    assert (holed[~inside] == alone[~inside]).all()
    ground = ~text(alone) & inside
    ground[:place.top] = ground[place.bottom:] = False
    ground[:, :place.left] = ground[:, place.right:] = False
    assert ground.sum() > 5000
    assert (holed[ground].mean() - alone[ground].mean()) > 30    # the grey shows through


def test_over_the_studios_words_the_panel_stays_dark_and_its_text_readable():
    alone, place = panel_on_grey(Renderer(TABLE, SMALL), [])
    # words in every corner and down the middle: no place clear of them (where there is one,
    # the panel stands there: tests/tabletop/test_view_overlay.py)
    words = everywhere(8, 28, 300, 30) + [pygame.Rect(300, 0, 40, SMALL[1])]
    bodies = everywhere(28, 8, 200, 120)                    # characters under them too
    both, at = panel_on_grey(Renderer(TABLE, SMALL), bodies, words)
    assert at == place
    cut = (slice(words[0].top, words[0].bottom), slice(words[0].left, words[0].right))
    assert (both[cut] == alone[cut]).all()
    assert (both[10:26, 40:200] != alone[10:26, 40:200]).any()    # a character shows beside


def test_a_moved_hole_is_drawn_as_a_panel_made_afresh_draws_it():
    kept = Renderer(TABLE, SMALL)
    for k in range(6):                                      # the holes move, grow and part
        holes = [pygame.Rect(200 + 9 * k, 100, 90 + 7 * k, 120),
                 pygame.Rect(30, 40 + 5 * k, 60, 60)]
        words = [pygame.Rect(100, 150 - 4 * k, 200, 24)]
        again, _ = panel_on_grey(kept, holes, words)
        fresh, _ = panel_on_grey(Renderer(TABLE, SMALL), holes, words)
        assert (again == fresh).all(), k


def test_a_panel_the_kernels_cannot_read_is_seen_through_alike():
    img = screens.panel(LINES[:4])
    w, h = img.get_size()
    wide = pygame.Surface((w + 10, h), pygame.SRCALPHA)   # its part: a subsurface, strided rows
    part = wide.subsurface(pygame.Rect(0, 0, w, h))
    part.blit(img, (0, 0), special_flags=pygame.BLEND_RGBA_ADD)
    holes = [pygame.Rect(5, 5, 60, 30), pygame.Rect(40, 10, 60, 30)]
    solid = [pygame.Rect(0, 20, 30, 8)]
    a, b = (see_through.SeeThrough()(s, holes, solid, 150) for s in (img, part))
    assert (pygame.surfarray.array_alpha(a) == pygame.surfarray.array_alpha(b)).all()
    assert (pygame.surfarray.array3d(a) == pygame.surfarray.array3d(b)).all()
    assert pygame.surfarray.array_alpha(a)[30, 15] < pygame.surfarray.array_alpha(img)[30, 15]



def test_over_a_hole_on_the_dark_table_the_panels_text_keeps_its_light():
    """Where the panel fades over a character's rectangle (a bounding box: its glow, empty
    table at its corners), its ground goes nearly clear but its text stays as bright as
    beside it: faded with the ground, the figures read half as bright as their neighbours
    across the rectangle's edge (measured: 0.46 of their light on the table's colour)."""
    def on_table(holes):
        s = pygame.Surface(SMALL)
        s.fill(screens.TABLE)
        place = Renderer(TABLE, SMALL).draw_overlay(s, LINES, holes, [])
        return rgb(s).astype(int), place
    alone, place = on_table([])
    holes = everywhere(40, 30, 120, 80)
    holed, at = on_table(holes)
    assert at == place
    inside = np.zeros(alone.shape[:2], bool)
    for r in holes:
        r = r.clip(place)
        inside[r.top:r.bottom, r.left:r.right] = True
    letters = text(alone) & inside
    assert letters.sum() > 200
    kept = holed[letters].sum() / alone[letters].sum()
    assert kept > 0.95, kept
    ground = (alone.max(axis=2) < 40) & inside              # the ground: still nearly clear
    assert (holed[ground].sum(axis=1) - alone[ground].sum(axis=1)).mean() > 10
