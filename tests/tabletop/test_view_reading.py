"""Every word the view draws reads upright for a person at the table's near edge, whatever the
projector's calibration does to the window: mirrored (rear projection), upside down, half round,
or turned a quarter round either way (a projector hung across the table, its image's x axis
along the table's y), or turned and mirrored.

Each calibration here is the plain one (1.2 x 0.8 m at 840 px/m in 1280 x 720) followed by a
pixel move of the window (a flip, a quarter turn): the window image taken back by the inverse
move is what a person at the table sees, so the words there must be the very pixels the plain
calibration draws. Each word is found as the pixels it changes (the view drawn with and without
it), real pygame surfaces throughout."""

from typing import Callable

import numpy as np
import pygame
import pytest

from tabletop.drawing.reading import Reading
from tabletop.frames import CharacterState, Frame, Puck
from tabletop.renderer import Renderer

TABLE, SIZE = (1.2, 0.8), (1280, 720)
PLAIN_H = np.array([[840.0, 0.0, 136.0], [0.0, -840.0, 696.0], [0.0, 0.0, 1.0]])
# name: (window pixel move, the moved window's size, the move back on [row, column] arrays)
TURNS: dict[str, tuple[list, tuple[int, int], Callable[[np.ndarray], np.ndarray]]] = {
    "mirrored": ([[-1, 0, 1280], [0, 1, 0]], SIZE, lambda a: a[:, ::-1]),
    "upside down": ([[1, 0, 0], [0, -1, 720]], SIZE, lambda a: a[::-1]),
    "half round": ([[-1, 0, 1280], [0, -1, 720]], SIZE, lambda a: a[::-1, ::-1]),
    "quarter, x up": ([[0, 1, 0], [-1, 0, 1280]], (720, 1280), lambda a: np.rot90(a, -1)),
    "quarter, x down": ([[0, -1, 720], [1, 0, 0]], (720, 1280), lambda a: np.rot90(a, 1)),
    "quarter, mirrored": ([[0, 1, 0], [1, 0, 0]], (720, 1280), lambda a: np.swapaxes(a, 0, 1)),
    "quarter, mirrored across": ([[0, -1, 720], [-1, 0, 1280]], (720, 1280),
                                 lambda a: np.swapaxes(a, 0, 1)[::-1, ::-1]),
}
# the least overlap (intersection over union) of a word's pixels as the table shows it with
# the plain calibration's, each word within 1 px: measured 0.966-1.0 with the words turned;
# drawn upright in the window, 0.0-0.47 (every puck id 0.0, the idle invitation mirrored 0.37,
# the operator panel mirrored 0.40, "One moment" upside down 0.29, the studio's words on a
# quarter turn 0.0-0.04)
SAME = 0.9

Draw = Callable[[Renderer, pygame.Surface, bool], None]


def table_view(turn: str | None, draw: Draw, light: int = 40) -> np.ndarray:
    """The pixels a word changes, as the table shows them (bool, rows x columns of the plain
    window): ``draw(renderer, surface, with_word)`` drawn with and without it; ``light``: the
    least sum of the drawn pixel's channels (words over a dark panel: its bright pixels)."""
    if turn is None:
        H, size, back = PLAIN_H, SIZE, (lambda a: a)
    else:
        move, size, back = TURNS[turn]
        H = np.vstack([np.array(move, dtype=float), [0.0, 0.0, 1.0]]) @ PLAIN_H
    shots = []
    for with_word in (True, False):
        renderer = Renderer(TABLE, size, margin=24, homography=H)
        surface = pygame.Surface(size)
        draw(renderer, surface, with_word)
        # (int16: a channel's difference is within +-255, three channels' sum within 765)
        shots.append(pygame.surfarray.pixels3d(surface).transpose(1, 0, 2).astype(np.int16))
    changed = (channels(np.abs(shots[0] - shots[1])) > 40) & (channels(shots[0]) >= light)
    return back(changed)


def channels(img: np.ndarray) -> np.ndarray:
    """The sum of an image's three channels (rows x columns), as ``img.sum(axis=2)`` in its
    dtype: three whole-image adds, where numpy's reduction over an axis of 3 went pixel by
    pixel (0.15 of a turned view's 0.25 CPU s)."""
    return img[..., 0] + img[..., 1] + img[..., 2]


@pytest.fixture(scope="module")
def plain_view() -> Callable[..., np.ndarray]:
    """``of(None, *args)`` (:func:`table_view`, :func:`one_moment`: the plain calibration's
    view), drawn once per module (every turned view of a word compares with it); read-only,
    so that no test changes what another reads."""
    memo: dict[tuple, np.ndarray] = {}

    def view(of: Callable[..., np.ndarray], *args: object) -> np.ndarray:
        key = (of, *args)
        if key not in memo:
            memo[key] = of(None, *args)
            memo[key].setflags(write=False)
        return memo[key]
    return view


def overlap(a: np.ndarray, b: np.ndarray) -> float:
    """Intersection over union of two masks of one size, each word (a patch of pixels with
    under 6 px between them) taken at its best shift within 1 px: a word centred on the
    window's middle, which falls between two pixels, mirrors to 1 px beside it."""
    from scipy import ndimage   # (not at the top: each test worker imports every module)
    groups, n = ndimage.label(ndimage.binary_dilation(a | b, iterations=6))
    inter = union = 0
    for box in ndimage.find_objects(groups):
        pa, pb = a[box], np.pad(b, 1)[tuple(slice(s.start, s.stop + 2) for s in box)]
        got = max((((pa & pb[1 + dy:1 + dy + pa.shape[0], 1 + dx:1 + dx + pa.shape[1]]).sum(),
                    (pa | pb[1 + dy:1 + dy + pa.shape[0], 1 + dx:1 + dx + pa.shape[1]]).sum())
                   for dy in (-1, 0, 1) for dx in (-1, 0, 1)), key=lambda iu: iu[0] / iu[1])
        inter, union = inter + got[0], union + got[1]
    return inter / max(union, 1)


def invitation(renderer: Renderer, surface: pygame.Surface, with_word: bool) -> None:
    renderer.invitation = "put a puck on the table" if with_word else ""
    renderer.idle = 1.0                      # (nobody has played: the idle look at its full)
    renderer.draw(surface, Frame(seq=0, t=9.817))   # (its breathing at its brightest)


def puck_ids(renderer: Renderer, surface: pygame.Surface, with_word: bool) -> None:
    pucks = (Puck(37, 0.3, 0.3, 0.5), Puck(12, 0.9, 0.55, 2.0))
    renderer.draw(surface, Frame(seq=0, t=0.0, pucks=pucks), [] if with_word else None)


def status_line(renderer: Renderer, surface: pygame.Surface, with_word: bool) -> None:
    studio = CharacterState("studio", 0.0, 0.0, 0.0, kind="studio", size=0.0,
                            label="[lover] behaviour lover: R record, [ ] switch, F2 rename")
    renderer.draw(surface, Frame(seq=0, t=0.0, characters=(studio,) if with_word else ()))


def try_mark(renderer: Renderer, surface: pygame.Surface, with_word: bool) -> None:
    studio = CharacterState("studio", 0.0, 0.0, 0.0, kind="studio", size=0.0, action="trying",
                            label="[pet] trained 317 samples (6.2 s); try it")
    renderer.draw(surface, Frame(seq=0, t=0.0, characters=(studio,) if with_word else ()))
    if with_word:        # and F2's line on the table's far side
        from tabletop.studio.draw import NamePrompt
        prompt = NamePrompt()
        prompt.text, prompt.refused = "shy", "a name holds at most 64 characters"
        prompt.draw(surface, renderer)


def main_ghost(renderer: Renderer, surface: pygame.Surface, with_word: bool) -> None:
    renderer.draw(surface, Frame(seq=0, t=0.0))
    if with_word:        # the studio's played-back main take: a ring, a notch, "main" under it
        renderer.draw_character(surface, CharacterState("main", 0.5, 0.4, 0.7, kind="playback",
                                                        size=0.05))


WORDS = {"idle invitation": invitation, "puck ids": puck_ids, "studio status line": status_line,
         "main take's ghost": main_ghost, "studio's TRY mark, status and F2 lines": try_mark}


@pytest.mark.parametrize("turn", list(TURNS))
@pytest.mark.parametrize("word", list(WORDS))
def test_a_word_reads_upright_on_the_table_on_every_calibration(plain_view, word, turn):
    """The idle invitation and the puck ids read mirrored, upside down or sideways on such a
    table (drawn upright in the window); the studio's status line read sideways on a quarter
    turn. Seen from the table, each is where and as the plain calibration draws it."""
    plain = plain_view(table_view, WORDS[word])
    seen = table_view(turn, WORDS[word])
    if word == "main take's ghost":        # its word only, under the ring (38 px) and notch
        yy, xx = np.mgrid[:720, :1280]
        plain = plain & (np.hypot(xx - 556, yy - 360) > 1.35 * 38)
        seen &= np.hypot(xx - 556, yy - 360) > 1.35 * 38
    assert plain.sum() > 100, word                  # (the word is drawn at all)
    assert overlap(plain, seen) >= SAME, (word, turn, overlap(plain, seen))


def bright(img: np.ndarray) -> np.ndarray:
    return channels(img) > 300


def one_moment(turn: str | None) -> np.ndarray:
    """The window drawing "One moment" (rgb, rows x columns of the plain window) as the table
    shows it."""
    if turn is None:
        H, size, back = PLAIN_H, SIZE, (lambda a: a)
    else:
        move, size, back = TURNS[turn]
        H = np.vstack([np.array(move, dtype=float), [0.0, 0.0, 1.0]]) @ PLAIN_H
    renderer = Renderer(TABLE, size, margin=24, homography=H)
    renderer.moment = 1.0                # (the calm screen at its full)
    surface = pygame.Surface(size)
    renderer.draw(surface, Frame(seq=0, t=0.0, status="one_moment"))
    return back(pygame.surfarray.pixels3d(surface).transpose(1, 0, 2).astype(int))


@pytest.mark.parametrize("turn", list(TURNS))
def test_one_moment_reads_upright_below_its_ring_on_every_calibration(plain_view, turn):
    """"One moment", the words under the ring of lights while the cameras reconnect, read
    mirrored or sideways on such a table. Seen from the table, the words (the bright pixels
    below the ring: it turns with the window's axes) are the plain calibration's."""
    views = [plain_view(one_moment), one_moment(turn)]
    # the ring: 0.06 of the window's smaller side (720 px) around the table's centre moved 0.04 of
    # it away from the reader; its lights' glows reach 0.5 of that beyond it
    ring_y, r = 360 - 0.04 * 720, 0.06 * 720
    below = slice(int(ring_y + 1.5 * r), None)
    plain, seen = (bright(v[below]) for v in views)
    assert plain.sum() > 200
    assert overlap(plain, seen) >= SAME, (turn, overlap(plain, seen))


PANEL = ["calibration check at 07:02:11:", "puck 3: 0.8 mm", "PASS (worst 0.8 mm)"]


def panel(renderer: Renderer, surface: pygame.Surface, with_word: bool) -> None:
    """The operator overlay's panel with the calibration check's lines."""
    renderer.draw(surface, Frame(seq=0, t=0.0), PANEL if with_word else None)


@pytest.mark.parametrize("turn", list(TURNS))
def test_the_operator_panel_reads_upright_on_every_calibration(plain_view, turn):
    """The operator overlay's panel (the calibration check's lines, the sources' health) read
    mirrored or sideways on such a table. It stands in a window corner: seen from the table,
    cut to its own extent, it is the plain calibration's panel."""
    def cut(m: np.ndarray) -> np.ndarray:
        rows, cols = np.flatnonzero(m.any(axis=1)), np.flatnonzero(m.any(axis=0))
        return m[rows[0]:rows[-1] + 1, cols[0]:cols[-1] + 1]
    # (its text: its translucent ground changes the table under it, which differs by corner,
    # and with it which of its letters' soft edges pass the threshold: extents within 1 px)
    plain, seen = cut(plain_view(table_view, panel, 300)), cut(table_view(turn, panel, 300))
    assert all(abs(a - b) <= 1 for a, b in zip(plain.shape, seen.shape)), (plain.shape, seen.shape)
    rows, cols = (max(a, b) for a, b in zip(plain.shape, seen.shape))
    plain, seen = (np.pad(m, ((0, rows - m.shape[0]), (0, cols - m.shape[1])))
                   for m in (plain, seen))
    assert overlap(plain, seen) >= SAME, (turn, overlap(plain, seen))


@pytest.mark.parametrize("turn", list(TURNS))
def test_the_reading_of_a_calibration_is_its_turn(turn):
    """The orientation read from each calibration: the reader's right (table +x) and up
    (table +y) as window directions, a quarter turn read as one (not as its nearest flip),
    and a calibration turned 30 degrees reads as the plain one."""
    move, size, _ = TURNS[turn]
    H = np.vstack([np.array(move, dtype=float), [0.0, 0.0, 1.0]]) @ PLAIN_H
    got = Renderer(TABLE, size, margin=24, homography=H).map.reading()
    m = np.array(move)[:, :2]
    want = Reading(tuple(int(v) for v in m @ (1, 0)), tuple(int(v) for v in m @ (0, -1)))
    assert got == want and got.quarter == turn.startswith("quarter")
    c, s = np.cos(np.radians(30)), np.sin(np.radians(30))
    tilted = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]) @ PLAIN_H
    assert Renderer(TABLE, SIZE, homography=tilted).map.reading().plain


def renamed(H: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The window ([x, y, rgb]) with the empty view drawn under calibration ``H``, then with
    F2's line "shy" and a refusal drawn over it."""
    from tabletop.studio.draw import NamePrompt
    renderer = Renderer(TABLE, SIZE, margin=24, homography=H)
    surface = pygame.Surface(SIZE)
    renderer.draw(surface, Frame(seq=0, t=0.0))
    before = pygame.surfarray.array3d(surface).copy()
    prompt = NamePrompt()
    prompt.text, prompt.refused = "shy", "a name begins with a letter or digit"
    prompt.draw(surface, renderer)
    return before, pygame.surfarray.array3d(surface)


def test_the_rename_line_stands_on_the_table_where_the_projector_throws_beyond_it():
    """A projector turned a quarter round over the long table throws its 1280 px along the
    table's 0.8 m (448 px); the window beyond x 416 lights the floor. F2's line stands along
    the table's far edge (window x 416), just inside it, not at the window's far edge."""
    before, now = renamed(np.array([[0.0, -560.0, 864.0], [-560.0, 0.0, 696.0], [0, 0, 1.0]]))
    changed = (now != before).any(axis=2)    # [x, y]
    cols, rows = np.flatnonzero(changed.any(axis=1)), np.flatnonzero(changed.any(axis=0))
    assert cols.size and 416 <= cols.min() and cols.max() < 416 + 80, (cols.min(), cols.max())
    assert 24 <= rows.min() and rows.max() <= 696, (rows.min(), rows.max())


def test_the_rename_line_stays_in_the_window_where_the_projector_does_not_reach_the_far_edge():
    """A calibration whose table's far edge lies 72 px above the window (y = -72): the line
    and the refusal under it stand at the window's top edge, both whole in the window, the
    reason below the line."""
    H = np.array([[840.0, 0.0, 136.0], [0.0, -840.0, 600.0], [0.0, 0.0, 1.0]])
    assert Renderer(TABLE, SIZE, homography=H).map.point(TABLE[0] / 2, TABLE[1])[1] < -60
    before, now = renamed(H)
    white = ((now != before).any(axis=2) & (now.min(axis=2) > 200)).any(axis=0)   # rows
    amber = ((now != before).any(axis=2) & (now[..., 2] < 120)
             & (now[..., 0] > 200)).any(axis=0)
    w, a = np.flatnonzero(white), np.flatnonzero(amber)
    assert w.size and a.size, (w.size, a.size)
    assert 0 <= w.min() and w.max() < a.min() and a.max() < 120, (w.min(), w.max(), a.min())


def test_words_are_placed_by_their_anchor_on_every_reading():
    """Reading.at (worked out inline) against the rule it states, on all eight readings: the
    words' ``anchor`` fraction along the reader's right and down lies on ``pos``, a flipped axis
    mirrored about that pixel."""
    import math
    import random
    from tabletop.drawing.reading import _ORIENTATIONS
    rnd = random.Random(0)
    for right, up in _ORIENTATIONS:
        reading = Reading(right, up)
        down = (-up[0], -up[1])
        for _ in range(500):
            size = (rnd.randint(1, 200), rnd.randint(1, 200))
            pos = (rnd.uniform(-300, 1500), rnd.uniform(-300, 1500))
            anchor = (rnd.choice((0.0, 0.4, 0.5, 0.6, 1.0, rnd.random())), rnd.random())
            topleft = []
            for k in (0, 1):
                d, f = (right, anchor[0]) if right[k] else (down, anchor[1])
                n = math.floor(f * size[k])
                topleft.append(math.floor(pos[k]) - (n if d[k] > 0 else size[k] - 1 - n))
            assert reading.at(size, pos, anchor) == pygame.Rect(topleft, size), (right, up)
