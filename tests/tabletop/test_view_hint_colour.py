"""A hinted pose (MOP early feedback) keeps its character's hue on the navy table, faint all over
(its eyes too), and clearly fainter than the character acting: drawn by the renderer on a real
surface for every example character's colour."""

import math

import numpy as np
import pygame
import pytest

from tabletop.drawing.palette import TABLE as TABLE_RGB, vivid
from tabletop.frames import CharacterState, Frame
from tabletop.view import Renderer

from tests.tabletop.test_view import SIZE, TABLE, rgb
from tests.tabletop.test_view_puck_id_colors import GROUNDS, XYZ, lab, linear

pytestmark = pytest.mark.usefixtures("pygame_display")

BONES = ((0, 1), (1, 2))
BODY = np.array([[0.45, 0.3], [0.6, 0.3], [0.75, 0.3]])
AWAY = (0.0, 0.25)         # the hinted pose, clear of the body and its glow (12.6 cm)


def creature(color: tuple, p: float | None) -> CharacterState:
    """A creature along x at y = 0.3 m: acting (``p`` None) or suspected of an action of
    probability ``p``, whose pose lies 25 cm away."""
    extra = {} if p is None else dict(hints=(("wave", p, 0.4),), hint_points=BODY + AWAY)
    return CharacterState("c", 0.6, 0.3, 0.0, kind="creature", size=0.3, points=BODY,
                          bones=BONES, color=color, valid=p is None, **extra)


def drawn(color: tuple, p: float | None) -> tuple[Renderer, np.ndarray]:
    r = Renderer(TABLE, SIZE)
    s = pygame.Surface(SIZE)
    # 1.5 s: the figure grown in, the hint faded in (0.15 s); drawn every 0.1 s (the last
    # image is the one every 30 Hz frame makes, to the pixel, for every colour and p)
    for k in (*range(0, 44, 3), 44):
        r.draw(s, Frame(seq=k, t=1.0 + k / 30, characters=(creature(color, p),)))
    return r, rgb(s)


def limb(r: Renderer, img: np.ndarray, xy: np.ndarray) -> np.ndarray:
    """The colour in the middle of the first limb of the figure at ``xy`` (table metres)."""
    x, y = r.map.points(((xy[0] + xy[1]) / 2)[None])[0]
    patch = img[int(y) - 1:int(y) + 2, int(x) - 1:int(x) + 2].reshape(-1, 3)
    return np.median(patch, axis=0)


def outline(r: Renderer, img: np.ndarray, xy: np.ndarray) -> np.ndarray:
    """The colour of the hinted figure at ``xy``'s outline (it is drawn outlined, its inside
    faint): across the middle of its first limb, the brightest pixel's row within 20 px, the
    median of the 5 px along the limb there."""
    x, y = (int(v) for v in r.map.points(((xy[0] + xy[1]) / 2)[None])[0])
    col = img[y - 20:y + 21, x].astype(int).sum(axis=1)
    yy = y - 20 + int(np.argmax(col))
    return np.median(img[yy, x - 2:x + 3].reshape(-1, 3), axis=0)


def luminance(c: np.ndarray) -> float:
    return float(linear(c) @ XYZ[1])


def hue_chroma(c: np.ndarray) -> tuple[float, float]:
    _, a, b = lab(linear(c))
    return math.degrees(math.atan2(b, a)), math.hypot(a, b)


@pytest.mark.parametrize("color", GROUNDS)
def test_a_hint_keeps_its_characters_hue_and_is_fainter_than_it_acting(color):
    r, acting = drawn(color, None)
    body = limb(r, acting, BODY)
    table = np.array(TABLE_RGB, dtype=float)
    own, _ = hue_chroma(np.array(vivid(color), dtype=float))
    for p in (0.5, 1.0):
        r, img = drawn(color, p)
        hint = outline(r, img, BODY + AWAY)
        h, chroma = hue_chroma(hint)
        turn = abs((h - own + 180.0) % 360.0 - 180.0)
        # measured, worst of the seven colours (lightened 30 % toward white before): 72 deg
        # off the character's hue, chroma 1.8 (the pale bird's: grey) at p = 0.5; after,
        # saturated, 24 deg (the humanoid's cyan, bluer on the navy), chroma 13 (the dancer's)
        assert turn < 26.0 and chroma > 12.0, (color, p, turn, chroma)
        # it shows on the table (CIELAB distance: 28 before, 30 after, at p = 0.5) ...
        assert np.linalg.norm(lab(linear(hint)) - lab(linear(table))) > 25.0, (color, p)
        # ... and is clearly fainter than the character acting (its luminance over the
        # hint's, WCAG, at p = 1: 1.63 (the pink lover's) before, 2.00 (the salamander's) after)
        ratio = (luminance(body) + 0.05) / (luminance(hint) + 0.05)
        assert ratio > 1.9, (color, p, ratio)


def test_a_hinted_figures_eyes_are_faint_not_dark_holes():
    from scipy import ndimage   # (not at the top: each test worker imports every module)
    r, img = drawn((240, 170, 60), 1.0)
    px = r.map.points(BODY + AWAY)
    x0, y0 = (px.min(axis=0) - 40).astype(int)
    x1, y1 = (px.max(axis=0) + 40).astype(int)
    region = img[y0:y1, x0:x1].astype(int)
    ground = np.median(np.concatenate([region[0], region[-1]]), axis=0)
    light = (region - ground).sum(axis=2)             # what the hint adds (of 765)
    inside = ndimage.binary_erosion(ndimage.binary_fill_holes(light > 40), iterations=2)
    dark = inside & (light < 0.5 * np.median(light[inside]))
    # its soft edges left out; a pupil of no light showed the table through the faint
    # figure (29 px darker than half its light before, 0 after)
    assert inside.sum() > 2000 and dark.sum() == 0, (inside.sum(), dark.sum())
