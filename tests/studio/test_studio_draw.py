"""The studio's status line on the table: it fits the window, whatever it has to say."""

import numpy as np
import pygame
import pytest

from tabletop.frames import CharacterState
from tabletop.renderer import Renderer
from tabletop.studio.draw import draw_studio

SIZE = (480, 270)
GREY = (60, 60, 60)


def drawn(label: str) -> np.ndarray:
    renderer = Renderer((1.2, 0.8), SIZE, margin=24)
    surface = pygame.Surface(SIZE)
    surface.fill(GREY)
    draw_studio(surface, renderer, CharacterState("studio", 0.0, 0.0, 0.0, kind="studio",
                                                  size=0.0, label=label))
    return pygame.surfarray.array3d(surface).transpose(1, 0, 2).astype(int)


def rows_with_text(img: np.ndarray) -> np.ndarray:
    return np.flatnonzero((img != GREY).any(axis=2).any(axis=1))


def test_a_long_status_line_wraps_within_the_window():
    """A bad library file's path made the line run off the window's right edge (the path,
    what the designer needs, unseen): it wraps onto lines above within the window."""
    short = drawn("[lover] behaviour lover: R record")
    long = drawn("[lover] behaviour lover: R record, [ ] switch, F2 rename, Del delete, U undo"
                 "   | 2 bad library file(s): /tmp/studio/library/bully/behavior.yaml: "
                 "corrupt YAML at line 3, column 1")
    right = long[:, -12:]
    assert not (right != GREY).any(), "text runs to the window's right edge"
    # three lines or more at this width, the last (lowest) where the short line stands
    assert rows_with_text(long).max() == rows_with_text(short).max()
    assert len(rows_with_text(long)) >= 2.5 * len(rows_with_text(short))


def test_the_rename_prompt_takes_only_what_a_library_name_may_hold():
    """F2 took 'ü' and a leading '_' as typed (a space was left out), and the rename refused
    the name ("use 1-64 letters, ..."): the designer typed it all again."""
    from tabletop import library
    from tabletop.studio.draw import NamePrompt

    def key(k: int, text: str = "") -> pygame.event.Event:
        return pygame.event.Event(pygame.KEYDOWN, key=k, unicode=text, mod=0)

    prompt = NamePrompt()
    prompt.handle(key(pygame.K_F2))
    for c in "_wü tend.2-":
        prompt.handle(key(pygame.K_a, c))
    cmd = prompt.handle(key(pygame.K_RETURN))
    assert cmd == "designer.rename:wtend.2-"
    assert library.check_name(cmd.partition(":")[2])
    with pytest.raises(library.LibraryError, match="use 1-64 ASCII letters"):   # ü is a letter
        library.check_name("wütend")


def test_a_character_the_rename_prompt_does_not_take_is_said_under_it():
    """F2's prompt says under its line why a typed character was not taken (a space, 'ü', a
    leading '_', the 65th), until Backspace or a new prompt (without it, "shy lover" became
    "shylover" without a word)."""
    from tabletop.studio.draw import NamePrompt

    def key(k: int, text: str = "") -> pygame.event.Event:
        return pygame.event.Event(pygame.KEYDOWN, key=k, unicode=text, mod=0)

    def rows(prompt: NamePrompt) -> np.ndarray:
        surface = pygame.Surface((1280, 720))
        surface.fill(GREY)
        prompt.draw(surface, Renderer((1.2, 0.8), (1280, 720), margin=24))
        img = pygame.surfarray.array3d(surface).transpose(1, 0, 2).astype(int)
        return rows_with_text(img)

    prompt = NamePrompt()
    prompt.handle(key(pygame.K_F2))
    for c in "shy":
        prompt.handle(key(pygame.K_a, c))
    plain = rows(prompt)
    prompt.handle(key(pygame.K_SPACE, " "))
    assert prompt.text == "shy" and "a space cannot" in prompt.refused
    assert "letters" in prompt.refused
    said = rows(prompt)
    assert said.max() > plain.max() + 15         # a line of its own below the name
    prompt.handle(key(pygame.K_a, "_"))          # typed on: the reason stays in sight
    assert "a space" in prompt.refused and prompt.text == "shy_"
    assert rows(prompt).max() == said.max()
    prompt.handle(key(pygame.K_RETURN))
    prompt.handle(key(pygame.K_F2))              # a new prompt: nothing said yet
    assert prompt.refused == "" and rows(prompt).max() == plain.max()
    prompt.handle(key(pygame.K_TAB, "\t"))       # no character: nothing to say
    assert prompt.refused == ""
    prompt.text = "a" * 64                       # full: the 65th says so
    prompt.handle(key(pygame.K_a, "b"))
    assert "64" in prompt.refused and prompt.text == "a" * 64
    prompt.handle(key(pygame.K_BACKSPACE))       # an edit: the reason is gone with it
    assert prompt.refused == "" and prompt.text == "a" * 63
    prompt.text = "shy"
    prompt.handle(key(pygame.K_a, "ü"))
    assert "'ü' cannot be in a name" in prompt.refused
    prompt.text = ""
    for c in "_-.":                              # allowed in a name, but not first
        prompt.handle(key(pygame.K_a, c))
        assert prompt.refused == "a name begins with a letter or digit" and prompt.text == ""


def test_the_recording_edge_is_drawn_round_the_table():
    """The red recording frame ran round the window: a calibrated projector throwing beyond
    the table put it on the floor. It runs along the table's edge."""
    h = np.array([[150.0, 0.0, 40.0], [0.0, -150.0, 200.0], [0.0, 0.0, 1.0]])  # x 40-220 px
    renderer = Renderer((1.2, 0.8), SIZE, homography=h)
    surface = pygame.Surface(SIZE)
    surface.fill(GREY)
    red = (255, 60, 60)
    draw_studio(surface, renderer, CharacterState("studio", 0.0, 0.0, 0.0, kind="studio",
                                                  size=0.0, action="recording", progress=1.2,
                                                  label="[lover] recording", color=red))
    img = pygame.surfarray.array3d(surface).transpose(1, 0, 2).astype(int)

    def is_red(y: int, x: int) -> bool:
        return bool((np.abs(img[y, x] - red) < 40).all())
    assert is_red(150, 40) and is_red(150, 220) and is_red(80, 130)  # the table's edges
    assert not is_red(135, SIZE[0] - 2) and not is_red(SIZE[1] - 2, 400)  # not the window's


def text_mm(size: tuple[int, int], action: str, progress: float | None = None) -> float:
    """Height (mm on the table) of what the studio draws in ``size``: the status line (its
    box) while idle, the REC mark while recording (rows of red pixels)."""
    renderer = Renderer((1.2, 0.8), size, margin=24)
    surface = pygame.Surface(size)
    surface.fill(GREY)
    draw_studio(surface, renderer, CharacterState(
        "studio", 0.0, 0.0, 0.0, kind="studio", size=0.0, action=action, progress=progress,
        color=(255, 60, 60), label="[lover] behaviour lover: R record"))
    img = pygame.surfarray.array3d(surface).transpose(1, 0, 2).astype(int)
    if action == "recording":     # below the red table edge, right of the dot: the words
        edge = int(renderer.map.point(0.6, 0.8)[1]) + 8
        left, mid = int(renderer.map.point(0.1, 0.8)[0]), int(renderer.map.point(0.6, 0.8)[0])
        box = img[edge: size[1] // 3, left:mid]
        rows = np.flatnonzero(((box[..., 0] > 200) & (box[..., 1] < 120)).any(axis=1))
    else:
        rows = rows_with_text(img[size[1] // 2:])
    return 1000 * len(rows) / renderer.map.scale_at(0.6, 0.4)


@pytest.mark.parametrize("action", ["idle", "recording"])
def test_the_studio_words_keep_their_size_on_the_table_at_any_projector_resolution(action):
    """A 1920x1080 projector drew the status line and the REC mark in the pixels of 1280x720:
    two thirds as tall on the table (measured, the status line's box: 23 mm at 1280x720, 15 mm
    at 1920x1080; a 4K projector: a third)."""
    at_720 = text_mm((1280, 720), action, 2.0)
    at_1080 = text_mm((1920, 1080), action, 2.0)
    assert at_720 > 8.0
    assert abs(at_1080 / at_720 - 1.0) < 0.1, (at_720, at_1080)
    if action == "idle":     # a preview window on a desk: still a 16 px font (a 12 px box)
        ppm = Renderer((1.2, 0.8), (480, 270), margin=24).map.scale_at(0.6, 0.4)
        assert text_mm((480, 270), action) * ppm / 1000 >= 12


def test_the_rename_prompt_keeps_its_size_on_the_table_too():
    """F2's line was 32 px at every resolution: 2/3 as tall on the table at 1920x1080."""
    from tabletop.studio.draw import NamePrompt
    heights = []
    for size in ((1280, 720), (1920, 1080)):
        renderer = Renderer((1.2, 0.8), size, margin=24)
        surface = pygame.Surface(size)
        surface.fill(GREY)
        prompt = NamePrompt()
        prompt.text = "shy"
        prompt.draw(surface, renderer)
        img = pygame.surfarray.array3d(surface).transpose(1, 0, 2).astype(int)
        heights.append(len(rows_with_text(img)) / renderer.map.scale_at(0.6, 0.4))
    assert abs(heights[1] / heights[0] - 1.0) < 0.1, heights


@pytest.mark.parametrize("action", ["trying", "recording"])
def test_the_try_and_rec_marks_keep_off_a_character_in_their_corner(action):
    """The TRY (or REC) words at the table's far left corner were drawn over a character
    standing there (the bird of examples/mop.yaml, the very character being tried): they go to
    the far right corner while it is there, and stay there until the left one hides less than
    half as much."""
    from tabletop.frames import Frame

    renderer = Renderer((1.2, 0.8), (1280, 720), margin=24)
    surface = pygame.Surface((1280, 720))
    studio = CharacterState("studio", 0.0, 0.0, 0.0, kind="studio", size=0.0, action=action,
                            progress=1.0, label="[mop/bird] try it")

    def mark(t: float, *characters: CharacterState) -> pygame.Rect:
        renderer.draw(surface, Frame(seq=int(t * 60), t=t, characters=(*characters, studio)))
        return renderer._studio_marks[0]

    assert mark(0.0).centerx < 640                     # no one there: the far left corner
    bird = CharacterState("bird", 0.12, 0.72, 0.0, kind="reactor", size=0.1)
    shown = [mark(0.1 + i / 60, bird) for i in range(60)]   # (it fades in)
    body = renderer._keep_clear[0]
    assert shown[-1].centerx > 640 and not shown[-1].colliderect(body)
    middle = CharacterState("bird", 0.6, 0.4, 0.0, kind="reactor", size=0.1)
    assert mark(2.0, middle).centerx > 640             # nothing in either corner: it stays


@pytest.mark.parametrize("turn", ["mirrored", "half round"])
def test_the_studio_words_read_on_a_mirrored_or_turned_table(turn):
    """A projector calibration that mirrors the table (its corner 0 at the window's right), or
    turns it half round (a projector hung upside down): the status line, from the table's
    corner 0, was cut a letter a line down the window's right edge, and the TRY words ran off
    it. Both stand inside the window: the TRY mark in the table's far left corner as its
    reader sees it (the window's right), the status line from the near left one."""
    import numpy as np
    from tabletop.frames import Frame

    flip_y = -840.0 if turn == "mirrored" else 840.0
    H = np.array([[-840.0, 0.0, 1144.0], [0.0, flip_y, 696.0 if turn == "mirrored" else 24.0],
                  [0.0, 0.0, 1.0]])
    renderer = Renderer((1.2, 0.8), (1280, 720), margin=24, homography=H)
    surface = pygame.Surface((1280, 720))
    label = "[pet] trained 317 samples (6.2 s); try it: K keep, X discard, R redo"
    studio = CharacterState("studio", 0.0, 0.0, 0.0, kind="studio", size=0.0, action="trying",
                            label=label)
    renderer.draw(surface, Frame(seq=0, t=0.0, characters=(studio,)))
    mark, *status = renderer._studio_marks
    assert surface.get_rect().contains(mark) and mark.centerx > 640, mark
    assert len(status) == 1 and surface.get_rect().contains(status[0]), status
    assert status[0].width > 500 and status[0].left < 640, status


@pytest.mark.parametrize("turn", ["mirrored", "half round", "upside down"])
def test_the_studio_words_read_the_right_way_round_on_a_mirrored_or_turned_table(turn):
    """The studio's words were rendered upright in window pixels: on a mirrored (rear
    projection) or half-turned calibration they read mirrored or upside down on the table.
    Seen from the table (the window image taken back through the calibration, here a flip),
    the status line and the TRY mark are the very pixels a plain calibration draws, and the
    F2 line is not over the status line."""
    from tabletop.frames import Frame
    from tabletop.studio.draw import NamePrompt

    flips = {"mirrored": (True, False), "half round": (True, True),
             "upside down": (False, True)}[turn]
    sx, sy = (-1 if f else 1 for f in flips)
    H = np.array([[840.0 * sx, 0.0, 1144.0 if flips[0] else 136.0],
                  [0.0, -840.0 * sy, 24.0 if flips[1] else 696.0], [0.0, 0.0, 1.0]])
    label = "[pet] trained 317 samples (6.2 s); try it: K keep, X discard, R redo"
    studio = CharacterState("studio", 0.0, 0.0, 0.0, kind="studio", size=0.0, action="trying",
                            label=label)
    seen = []
    for h in (None, H):
        renderer = Renderer((1.2, 0.8), (1280, 720), margin=24, homography=h)
        surface = pygame.Surface((1280, 720))
        renderer.draw(surface, Frame(seq=0, t=0.0, characters=(studio,)))
        img = pygame.surfarray.array3d(surface).transpose(1, 0, 2).astype(int)
        if h is not None:      # the table's view: the window flipped back (to within 1 px)
            img = img[::sy, ::sx]
        seen.append((img, renderer._studio_marks))
    (plain, (mark, status)), (table, (tmark, _)) = seen

    def best(a: np.ndarray, rect: pygame.Rect) -> float:
        """Mean difference of ``rect`` of ``plain`` and of ``a`` shifted by at most 1 px."""
        want = plain[rect.top:rect.bottom, rect.left:rect.right]
        return min(float(np.abs(a[rect.top + dy:rect.bottom + dy,
                                  rect.left + dx:rect.right + dx] - want).mean())
                   for dx in (-1, 0, 1) for dy in (-1, 0, 1))
    assert best(table, status) < 2.0, turn          # the status line, where it reads
    # the TRY mark, in the corner its calibration put it: its words and its dot alike
    x = 1279 - tmark.right + 1 if flips[0] else tmark.left
    y = 719 - tmark.bottom + 1 if flips[1] else tmark.top
    moved = np.roll(table, (mark.top - y, mark.left - x), axis=(0, 1))
    assert best(moved, mark) < 2.0, turn

    renderer = Renderer((1.2, 0.8), (1280, 720), margin=24, homography=H)
    surface = pygame.Surface((1280, 720))
    renderer.draw(surface, Frame(seq=0, t=0.0, characters=(studio,)))
    prompt = NamePrompt()
    prompt.text = "shy"
    before = pygame.surfarray.array3d(surface).copy()
    prompt.draw(surface, renderer)
    changed = np.flatnonzero((pygame.surfarray.array3d(surface) != before).any(axis=2).any(0))
    status_rows = set(range(renderer._studio_marks[-1].top, renderer._studio_marks[-1].bottom))
    assert changed.size and not status_rows & set(changed.tolist()), turn
