"""A hinted pose (MOP early feedback) reads as a hint, not as a second character: drawn as its
outline, its inside faint, with its action's name and a question mark above it; a character
acting is drawn whole. Measured on real surfaces drawn by the renderer."""

import numpy as np
import pygame
import pytest

from tabletop.frames import CharacterState, Frame
from tabletop.view import Renderer

from tests.tabletop.test_view import SIZE, TABLE, rgb

pytestmark = pytest.mark.usefixtures("pygame_display")

BONES = ((0, 1), (1, 2))
BODY = np.array([[0.45, 0.3], [0.6, 0.3], [0.75, 0.3]])
AWAY = (0.0, 0.25)         # the hinted pose, clear of the body and its glow


def creature(hinted: bool, at: np.ndarray = BODY) -> CharacterState:
    extra = dict(hints=(("figure_eight", 1.0, 0.4),), hint_points=BODY + AWAY) if hinted else {}
    return CharacterState("c", 0.6, 0.3, 0.0, kind="creature", size=0.3, points=at,
                          bones=BONES, color=(90, 220, 120), valid=not hinted, **extra)


def drawn(c: CharacterState, frames: int = 45) -> tuple[Renderer, np.ndarray, np.ndarray]:
    """The view after 1.5 s of ``c`` (grown in, its hint faded in), its light over the bare
    table (sum of channels) and the renderer."""
    r = Renderer(TABLE, SIZE)
    s = pygame.Surface(SIZE)
    # drawn every other frame (the last image is the one every frame makes, to the pixel, for
    # each figure here; every third frame is not: a hint's kept light is added again when the
    # frame before had the same points, within 2 levels of painting it anew)
    for k in range(0, frames, 2):
        r.draw(s, Frame(seq=k, t=1.0 + k / 30, characters=(c,)))
    bare = rgb(r._background(pygame.Surface(SIZE))).astype(int).sum(axis=2)
    return r, rgb(s), rgb(s).astype(int).sum(axis=2) - bare


def box(r: Renderer, pts: np.ndarray, margin: int) -> tuple[slice, slice]:
    px = r.map.points(pts)
    (x0, y0), (x1, y1) = px.min(axis=0) - margin, px.max(axis=0) + margin
    return slice(int(y0), int(y1)), slice(int(x0), int(x1))


def solid_share(light: np.ndarray) -> float:
    """Of a figure's silhouette (its light above 40 of 765, holes filled), the share lit at
    least half as much as its brightest tenth: near 1 for a figure drawn whole, low for one
    drawn as its outline."""
    from scipy import ndimage   # (not at the top: each test worker imports every module)
    inside = ndimage.binary_fill_holes(light > 40)
    strong = np.percentile(light[inside], 90)
    return float((light[inside] >= 0.5 * strong).mean())


def test_a_hinted_pose_is_an_outline_and_a_character_acting_is_whole():
    r, _, acting = drawn(creature(False, BODY + AWAY))
    whole = solid_share(acting[box(r, BODY + AWAY, 30)])
    r, _, hinted = drawn(creature(True))
    hint = solid_share(hinted[box(r, BODY + AWAY, 30)])
    # measured: the acting creature 0.61 (its glow in its silhouette); its hinted pose drawn
    # filled (before) 0.97, outlined 0.19 (its 2 px rim whole, its inside at a fifth)
    assert whole > 0.5 and hint < 0.35, (whole, hint)


def test_a_hinted_pose_is_named_above_it_and_a_character_acting_is_not():
    def words_above(hinted: bool) -> int:
        r, _, light = drawn(creature(hinted, BODY))
        ys, xs = box(r, BODY + AWAY, 30)
        band = light[ys.start - 40:ys.start, xs]        # 40 px above the hinted pose's box
        return int((band > 150).sum())
    # measured: "figure eight?" 16 px tall, 266 px lit above the hint (0 before: no name)
    assert words_above(True) > 150 and words_above(False) == 0


def test_the_label_fades_with_its_hint_and_is_gone_with_it():
    r = Renderer(TABLE, SIZE)
    s = pygame.Surface(SIZE)
    ys, xs = box(r, BODY + AWAY, 30)
    bare = rgb(r._background(pygame.Surface(SIZE))).astype(int)[ys.start - 40:ys.start, xs]
    above = pygame.Rect(xs.start, ys.start - 40, xs.stop - xs.start, 40)   # (read alone)
    lit = []
    for k in range(60):          # suspected for a second, then nothing suspected
        c = creature(k < 30)
        if k >= 30:
            c = CharacterState("c", 0.6, 0.3, 0.0, kind="creature", size=0.3, points=BODY,
                               bones=BONES, color=(90, 220, 120), valid=False)
        r.draw(s, Frame(seq=k, t=1.0 + k / 30, characters=(c,)))
        lit.append(int((rgb(s.subsurface(above)) - bare).sum()))
    assert lit[2] < lit[29]              # fades in with the hint (0.15 s)
    assert lit[59] < 0.05 * lit[29]      # and goes with it


def test_a_hint_at_the_tables_far_edge_is_named_on_the_table():
    """The MOP example's bird, hinted with its wings up near the table's far edge, had its
    "wave?" above it beyond the table (1280x720: at y = 11 px, the table's top at 24): named
    below the pose instead, every lit pixel of the name on the table."""
    far = np.array([[0.45, 0.77], [0.6, 0.77], [0.75, 0.77]])

    def light(action: str) -> tuple[Renderer, np.ndarray]:
        c = CharacterState("c", 0.6, 0.3, 0.0, kind="creature", size=0.3, points=BODY,
                           bones=BONES, color=(90, 220, 120), valid=False,
                           hints=((action, 1.0, 0.4),), hint_points=far)
        r, _, lit = drawn(c)
        return r, lit
    r, named = light("wave")
    _, unnamed = light("")             # (a hint without a name: none drawn)
    name = (named - unnamed) > 100     # the name's pixels
    table = r._table_rect()
    on = name[table.top:table.bottom, table.left:table.right]
    # measured before: 148 of the name's 148 px beyond the table's far edge; after 0 of 143
    assert name.sum() > 50 and on.sum() == name.sum(), (name.sum(), on.sum())


def test_two_hints_of_one_name_and_colour_each_keep_their_strength():
    """Two characters of one colour suspected of one action, at probabilities 1.0 and 0.1:
    each name as strong as its own hint (they shared one render, both at the alpha set last)."""
    def pair(k: int) -> tuple[CharacterState, ...]:
        out = []
        for name, y, p in (("a", 0.2, 1.0), ("b", 0.55, 0.1)):
            pts = np.array([[0.2, y], [0.35, y], [0.5, y]])
            out.append(CharacterState(name, 0.35, y, 0.0, kind="creature", size=0.3,
                                      points=pts + (0.45, 0.0), bones=BONES,
                                      color=(90, 220, 120), valid=False,
                                      hints=(("wave", p, 0.4),), hint_points=pts))
        return tuple(out)
    r = Renderer(TABLE, SIZE)
    s = pygame.Surface(SIZE)
    for k in range(45):
        r.draw(s, Frame(seq=k, t=1.0 + k / 30, characters=pair(k)))
    light = rgb(s).astype(int).sum(axis=2) - rgb(r._background(pygame.Surface(SIZE))).astype(
        int).sum(axis=2)
    lit = []
    for y in (0.2, 0.55):
        ys, xs = box(r, np.array([[0.2, y], [0.5, y]]), 30)
        lit.append(int(light[ys.start - 40:ys.start, xs].clip(0).sum()))
    # measured: the names' light 8,788 and 8,888 before (one alpha for both), 44,184 and
    # 8,888 after (alphas 255 and 51)
    assert lit[0] > 3 * lit[1] > 0, lit


def test_a_hints_name_is_made_once_per_strength_and_kept():
    """A hint's name at one strength is the same surface frame after frame (its copy and alpha
    made once: a copy + set_alpha each frame were a third of the name's time), and a second
    strength has its own, at its own alpha."""
    from tabletop.drawing.light import hint_label
    r = Renderer(TABLE, SIZE)
    at, table = pygame.Rect(400, 300, 120, 80), r._table_rect()
    first = hint_label(SIZE, "wave", at, (90, 220, 120), 0.4, r.map.reading(), table)
    again = hint_label(SIZE, "wave", at.move(30, 0), (90, 220, 120), 0.4, r.map.reading(), table)
    faint = hint_label(SIZE, "wave", at, (90, 220, 120), 0.1, r.map.reading(), table)
    assert again[0] is first[0] and again[1] == first[1].move(30, 0)
    assert faint[0] is not first[0]
    assert (first[0].get_alpha(), faint[0].get_alpha()) == (204, 51)


def test_a_hinted_pose_is_the_pose_made_faint():
    """hinted_pose (made positionally) is the character's pose with only its opacity, light,
    colour and ground changed."""
    import dataclasses
    from tabletop.drawing.characters import Pose
    from tabletop.drawing.light import HINT_ALPHA, hinted_pose
    from tabletop.drawing.palette import vivid
    pose = Pose((10.0, 20.0), 0.3, 840.0, 0.9, 1.1, 1.02, 1.2, 0.4, 0.7, 0.2, (1, 2, 3), 0.5)
    want = dataclasses.replace(pose, alpha=0.9 * HINT_ALPHA * 0.8, light=0.0,
                               color=vivid((90, 220, 120), 1.0, 0.8, 0.8), ground=(0, 0, 0))
    assert hinted_pose(pose, [90, 220, 120], 0.8) == want
