"""A puck's id beside its ring (the overlay's) is drawn in its id's colour: the first eight ids'
colours stay apart as a deuteranope or a protanope sees them (about 1 man in 12 has one of these
red-green deficiencies), and each reads on the dark table."""

import itertools
import math

import numpy as np
import pygame
import pytest

from tabletop.drawing.palette import TABLE as TABLE_RGB
from tabletop.view import Renderer

from tests.tabletop.test_view import TABLE, rgb

pytestmark = pytest.mark.usefixtures("pygame_display")

# Machado, Oliveira and Fernandes (2009), severity 1, on linear RGB
SEEN_AS = {
    "deuteranope": np.array([[0.367322, 0.860646, -0.227968], [0.280085, 0.672501, 0.047413],
                             [-0.011820, 0.042940, 0.968881]]),
    "protanope": np.array([[0.152286, 1.052583, -0.204868], [0.114503, 0.786281, 0.099216],
                           [-0.003882, -0.048116, 1.051998]]),
}
XYZ = np.array([[0.4124, 0.3576, 0.1805], [0.2126, 0.7152, 0.0722], [0.0193, 0.1192, 0.9505]])


def linear(c: np.ndarray) -> np.ndarray:
    """sRGB (0..255) to linear light (0..1)."""
    c = np.asarray(c, dtype=float) / 255.0
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def lab(lin: np.ndarray) -> np.ndarray:
    """Linear RGB (0..1) to CIELAB (D65)."""
    x = (lin @ XYZ.T) / np.array([0.95047, 1.0, 1.08883])
    f = np.where(x > 216 / 24389, np.cbrt(x), (24389 / 27 * x + 16) / 116)
    return np.stack([116 * f[..., 1] - 16, 500 * (f[..., 0] - f[..., 1]),
                     200 * (f[..., 1] - f[..., 2])], axis=-1)


def drawn_colors(n: int = 8) -> np.ndarray:
    """The colour of each of the ids 0..n-1 as drawn on the table: the brightest pixel of its
    label blitted on a table-coloured pygame surface (n x 3, 0..255)."""
    r = Renderer(TABLE, (1280, 720))
    out = []
    for puck_id in range(n):
        img = r._label(puck_id)
        s = pygame.Surface(img.get_size())
        s.fill(TABLE_RGB)
        s.blit(img, (0, 0))
        px = rgb(s).reshape(-1, 3)
        out.append(px[px.sum(axis=1).argmax()])
    return np.array(out)


def test_the_first_eight_puck_ids_colours_stay_apart_to_a_red_green_colour_blind_eye():
    colors = drawn_colors()
    for kind, m in SEEN_AS.items():
        seen = lab(np.clip(linear(colors) @ m.T, 0.0, 1.0))
        gap = min(np.linalg.norm(seen[i] - seen[j])
                  for i, j in itertools.combinations(range(len(seen)), 2))
        # measured: 0.5 (deuteranope: blue and violet, ids 0 and 4; red and green, ids 1
        # and 2, 13.1) and 9.5 (protanope) before; 17.0 and 16.8 after
        assert gap > 15.0, (kind, gap)


def test_every_puck_ids_colour_reads_on_the_dark_table():
    y = linear(drawn_colors()) @ XYZ[1]
    ground = float(linear(np.array(TABLE_RGB)) @ XYZ[1])
    # contrast ratio (WCAG) to the table: 6.2 .. 15.1 before, 4.5 .. 15.8 after
    assert ((y + 0.05) / (ground + 0.05)).min() >= 4.4


# the shipped examples' character colours, as drawn (vivid): a puck's id often lies on one
GROUNDS = [(240, 110, 150), (240, 170, 60), (90, 220, 120), (120, 180, 255), (200, 140, 230),
           (250, 250, 200), (120, 220, 255)]


def test_every_puck_id_reads_over_every_example_characters_colour():
    from scipy import ndimage

    from tabletop.drawing.palette import vivid
    r = Renderer(TABLE, (1280, 720))
    worst = math.inf
    for puck_id, ground in itertools.product(range(8), GROUNDS):
        img = r._label(puck_id)
        s = pygame.Surface(img.get_size())
        s.fill(vivid(ground))
        s.blit(img, (0, 0))
        px = rgb(s).astype(float)
        color = drawn_colors(puck_id + 1)[puck_id].astype(float)
        glyph = np.abs(px - color).sum(axis=2) < 40       # the digit's own colour
        edge = ndimage.binary_dilation(glyph) & ~glyph    # the pixels just around it
        y = linear(px) @ XYZ[1]
        ratio = (y[glyph].mean() + 0.05) / (np.median(y[edge]) + 0.05)
        worst = min(worst, max(ratio, 1 / ratio))
    # the contrast of a digit's light to what rings it (WCAG), the worst of the 56 pairs:
    # 1.02 before (the orange "1" on the pink lover 1.25), each digit on the character itself;
    # after, on its dark rim, 2.84 (id 5's blue) to 11.4, whatever the character's colour
    assert worst >= 2.5, worst
