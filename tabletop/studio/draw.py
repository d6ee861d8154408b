"""Drawing the studio on the table: the countdown, the recording indicator, the status line."""

from __future__ import annotations

import functools
import math
from typing import TYPE_CHECKING, Any, Callable

import pygame

from tabletop import library
from tabletop.drawing import screens
from tabletop.drawing.reading import PLAIN, Reading
from tabletop.frames import CharacterState

if TYPE_CHECKING:
    import numpy as np

# ``renderer`` below is the view's tabletop.renderer.Renderer, typed Any: that module imports
# this one to draw the studio, and the project's imports stay free of cycles

_fonts: dict[int, pygame.font.Font] = {}


def font(size: int) -> pygame.font.Font:
    if size not in _fonts:
        pygame.font.init()
        _fonts[size] = pygame.font.Font(None, size)
    return _fonts[size]


# The studio's words are sized on the table, not in pixels: at 1280x720 over a 1.2 x 0.8 m table
# (840 px/m) the status line's 26 px font has 15 mm capitals, which a designer standing at the
# table reads; fixed pixel sizes would give 10 mm capitals on a 1920x1080 projector and 5 mm on
# a 3840x2160 one. A window smaller than that (a preview on a desk) keeps them readable on its
# monitor.
REF_PPM = 840.0                  # pixels per metre the sizes below are for
STATUS_PX, MARK_PX, DOT_PX = 26, 36, 14
MIN_STATUS_PX, MIN_MARK_PX = 16, 22


def text_scale(renderer: Any) -> float:
    """The studio's words' size factor: the table's pixels per metre at its centre over
    ``REF_PPM``."""
    w, h = renderer.table
    return renderer.map.scale_at(w / 2, h / 2) / REF_PPM


def upright(img: pygame.Surface, renderer: Any) -> pygame.Surface:
    """``img`` (words rendered upright in window pixels) turned to read upright on the table
    from its near edge (:meth:`~tabletop.table_map.TableToScreen.reading`): a rear-projection
    calibration mirrors the window, an upside-down projector turns it half round, one hung
    across the table a quarter round."""
    return renderer.map.reading().turn(img)


def _mark(target: pygame.Surface, renderer: Any, img: pygame.Surface, dot: int,
          x: float, y: float, color: tuple[int, int, int], width: int = 0) -> pygame.Rect:
    """The REC or TRY mark with its dot at (x, y) (pixels, from :func:`_mark_at`): the dot,
    then ``img`` (upright in window pixels) to its right as the table reads them (on a mirrored
    table the words stand left of the dot in the window: it still comes first). Returns the
    mark's rectangle."""
    reading = renderer.map.reading()
    dot_rect = pygame.draw.circle(target, color, (x, y), dot, width=width)
    turned = reading.turn(img)
    return target.blit(turned, _words_at(reading, turned.get_size(), dot, x, y)).union(dot_rect)


def _words_at(reading: Reading, size: tuple[int, int], dot: int, x: float, y: float
              ) -> pygame.Rect:
    """Where a mark's words (``size``: turned, pixels) stand beside its dot at (x, y)."""
    return reading.at(size, reading.offset((x, y), dot + 8), (0.0, 0.5))


def _mark_at(renderer: Any, img: pygame.Surface, dot: int,
             avoid: list[pygame.Rect]) -> tuple[float, float]:
    """Where the REC or TRY mark (a dot of radius ``dot``, then ``img``, upright in window
    pixels) has its dot: at the table's far left corner as its reader sees it, or with its
    words ending at the far right one where that hides less than half as much
    of the characters drawn (``avoid``, pixels) as the corner it is in
    (``renderer.studio_mark_right``, kept so that a character walking by does not make it
    jump to and fro): a character at the far left corner (the bird of ``examples/mop.yaml``)
    is not hidden under the words that say to try it."""
    w, h = renderer.table
    reading = renderer.map.reading()
    size = reading.size(img.get_size())
    left = renderer.map.point(0.04, h - 0.04)
    right = reading.offset(renderer.map.point(w - 0.04, h - 0.04),
                           -(img.get_width() + 8 + dot))

    def hidden(x: float, y: float) -> int:
        box = _words_at(reading, size, dot, x, y).union((x - dot, y - dot, 2 * dot, 2 * dot))
        return sum(box.clip(r).width * box.clip(r).height for r in avoid)

    now, other = (right, left) if renderer.studio_mark_right else (left, right)
    if 2 * hidden(*other) < hidden(*now):
        renderer.studio_mark_right = not renderer.studio_mark_right
        now = other
    return now


def draw_studio(target: pygame.Surface, renderer: Any, c: CharacterState,
                avoid: list[pygame.Rect] | None = None) -> list[pygame.Rect]:
    """Draw the studio's indicator character (see :meth:`Studio.character`): a big countdown
    number in the middle of the table, a red dot and seconds and a red edge round the table
    while recording, a green TRY mark
    (and the path to drag, when the target gives one) while a take is tried, both in the
    table's far corner that hides less of the characters drawn (``avoid``, pixels), and the
    status line along the table's near edge (nothing while it has nothing to say). Returns the
    rectangles of the marks and words (pixels), which the operator overlay keeps clear of."""
    if not c.label or c.action == "quiet":     # (quiet: the operator overlay's line alone)
        return []
    avoid = avoid or []
    marks: list[pygame.Rect] = []
    w, h = renderer.table
    k = text_scale(renderer)
    mark_px, dot = max(MIN_MARK_PX, round(MARK_PX * k)), max(8, round(DOT_PX * k))
    cx, cy = renderer.map.point(w / 2, h / 2)
    if c.action == "countdown" and c.progress is not None:
        n = max(1, math.ceil(c.progress))
        frac = c.progress - math.floor(c.progress) if c.progress % 1 else 1.0
        r = int(min(target.get_size()) * 0.12)
        pygame.draw.circle(target, (255, 255, 255), (cx, cy), r, width=3)
        end = -math.pi / 2 + 2 * math.pi * frac
        rect = pygame.Rect(cx - r, cy - r, 2 * r, 2 * r)
        pygame.draw.arc(target, c.color, rect, math.pi / 2 - (end + math.pi / 2), math.pi / 2, 8)
        img = upright(font(int(r * 1.4)).render(str(n), True, (255, 255, 255)), renderer)
        target.blit(img, img.get_rect(center=(cx, cy)))
        marks.append(rect)
    elif c.action == "recording":
        on = int((c.progress or 0.0) * 2) % 2 == 0   # blinks once a second
        img = font(mark_px).render(f"REC {c.progress or 0.0:4.1f} s", True, c.color)
        x, y = _mark_at(renderer, img, dot, avoid)
        marks.append(_mark(target, renderer, img, dot, x, y, c.color if on else (120, 30, 30)))
        # the table's edge in red (a calibrated projector may throw beyond the table: a
        # frame round the window would be on the floor)
        pygame.draw.polygon(target, c.color, renderer._corners().tolist(), width=6)
    elif c.action in ("trying", "training"):
        green = (90, 220, 120)
        img = font(mark_px).render("TRY: K keep  X discard  R redo" if c.action == "trying"
                                   else "training...", True, green)
        x, y = _mark_at(renderer, img, dot, avoid)
        marks.append(_mark(target, renderer, img, dot, x, y, green,
                           0 if c.action == "trying" else 3))
        if c.points is not None and len(c.points) >= 2:
            _guide(target, renderer, c.points, green)
    # from the near edge's left corner as the table reads, its lines as long as the window
    # leaves towards the reader's right (less as much as the corner has behind it), the last
    # line nearest the edge and the others beyond it, away from the reader, as words read
    reading = renderer.map.reading()
    at = renderer.map.point(0.02, 0.02)
    window = target.get_size()
    back = (-reading.right[0], -reading.right[1])
    room = reading.reach(window, at, reading.right) - max(reading.reach(window, at, back), 12)
    px = max(MIN_STATUS_PX, round(STATUS_PX * k))
    f = font(px)
    off = 4.0                                   # 4 px off the edge
    for line in reversed(fit_lines(c.label, px, int(room))):
        img = reading.turn(f.render(line, True, (235, 235, 235), (0, 0, 0)))
        marks.append(target.blit(img, reading.at(img.get_size(), reading.offset(at, up=off),
                                                 (0.0, 1.0))))
        off += reading.size(img.get_size())[1] + 4
    return marks


@functools.lru_cache(maxsize=16)   # drawn every frame, the same text for seconds
def fit_lines(text: str, size: int, width: int) -> tuple[str, ...]:
    """``text`` cut into lines no wider than ``width`` pixels in the font of ``size``."""
    return tuple(screens.fit_lines(text, font(size), width))


def _guide(target: pygame.Surface, renderer: Any, points: np.ndarray,
           color: tuple[int, int, int]) -> None:
    """A dotted path through ``points`` (N x 2, table metres) from its first point (a ring: put
    your finger here) to an arrowhead."""
    px = [renderer.map.point(float(x), float(y)) for x, y in points]
    pygame.draw.circle(target, color, px[0], 12, width=2)
    for i, p in enumerate(px[1:-1]):
        if i % 2 == 0:
            pygame.draw.circle(target, color, p, 3)
    (x0, y0), (x1, y1) = px[-2], px[-1]
    a = math.atan2(y1 - y0, x1 - x0)
    tip = [(x1, y1)] + [(x1 - 14 * math.cos(a + s), y1 - 14 * math.sin(a + s)) for s in (0.5, -0.5)]
    pygame.draw.polygon(target, color, tip)


class NamePrompt:
    """F2 in the view: type a new name, Enter sends ``designer.rename:ITEM=NAME``, Esc cancels.
    ``ask`` (the studio's :meth:`~tabletop.studio.machine.Studio.may_rename`, in the loop's
    thread) gives the name of the item in play, which the line names ("rename lover as: _",
    so the designer sees what Enter renames, and that Esc cancels, where Esc otherwise quits),
    or "" to refuse F2: the prompt stays closed and the studio says why. The command names
    that ITEM, so a control marker that switched the item while the name was typed makes the
    studio refuse the rename, not rename the item switched to; without ``ask`` it sends
    ``designer.rename:NAME``."""

    def __init__(self) -> None:
        self.text: str | None = None
        self.ask: Callable[[], str] | None = None
        self.item = ""      # the item being renamed ("" when nothing named it)
        self.refused = ""   # why a character typed was not taken, drawn under the line

    @property
    def active(self) -> bool:
        return self.text is not None

    def handle(self, ev: pygame.event.Event) -> str | None:
        """Take a KEYDOWN event; returns a command when one is complete."""
        if self.text is None:
            if ev.key == pygame.K_F2:
                item = "" if self.ask is None else self.ask()
                if item or self.ask is None:
                    self.text, self.refused, self.item = "", "", item
            return None
        typed = ev.unicode   # (a reason said stays while letters follow, so that a fast
        #                      typist still reads it; Backspace, an edit of its own, clears it)
        if ev.key == pygame.K_ESCAPE:
            self.text = None
        elif ev.key in (pygame.K_RETURN, pygame.K_KP_ENTER):
            name, self.text = self.text, None
            if not name:
                return None
            return f"designer.rename:{self.item}={name}" if self.item else \
                f"designer.rename:{name}"
        elif ev.key == pygame.K_BACKSPACE:
            self.text, self.refused = self.text[:-1], ""
        elif typed and library.NAME_RE.match(self.text + typed):
            # only what a library name may hold: 'ü' or a leading '_' was typed, and the
            # rename then refused the name
            self.text += typed
        elif typed and typed.isprintable():     # said, so that the key is not taken for broken
            if len(self.text) >= library.NAME_MAX:
                self.refused = f"a name holds at most {library.NAME_MAX} characters"
            elif not self.text and typed in "_-.":   # allowed, but not first
                self.refused = "a name begins with a letter or digit"
            else:
                self.refused = (f"{'a space' if typed == ' ' else repr(typed)} cannot be in "
                                "a name: ASCII letters, digits, '_', '-' or '.'")
        return None

    @property
    def line(self) -> str:
        """The line drawn while a name is typed."""
        said = f"rename {self.item} as" if self.item else "new name"
        return f"{said}: {self.text}_   (Esc cancels)"

    def draw(self, target: pygame.Surface, renderer: Any = None) -> None:
        """The line being typed, centred along the table's far edge just inside it (the status
        line is along the near one; without ``renderer``, 24 px below the window's top),
        sized on the table as the studio's other words are (:func:`text_scale` of
        ``renderer``; 32 px at 840 px/m) and upright on it (:func:`upright`); the reason a key
        was refused under it. On the edge, not the window's: a projector throwing beyond the
        table (one turned a quarter round over a long table) lights the floor there. Where the
        table's far edge lies outside the window (a projector that does not reach it), at the
        window's edge nearest it, both lines kept whole in the window."""
        if self.text is None:
            return
        k, reading, edge = 1.0, PLAIN, (target.get_width() / 2, 24.0)
        if renderer is not None:
            k, reading = text_scale(renderer), renderer.map.reading()
            far = renderer.map.point(renderer.table[0] / 2, renderer.table[1])
            edge = (min(max(far[0], 0.0), target.get_width()),
                    min(max(far[1], 0.0), target.get_height()))
        window = target.get_rect()
        px = max(MIN_MARK_PX, round(32 * k))
        img = reading.turn(font(px).render(self.line, True, (255, 255, 255), (0, 0, 0)))
        target.blit(img, reading.at(img.get_size(),
                                    reading.offset(edge, up=-(px // 2))).clamp(window))
        if self.refused:
            small = max(MIN_MARK_PX, round(px * 0.6))
            why = reading.turn(font(small).render(self.refused, True, (255, 190, 80),
                                                  (0, 0, 0)))
            target.blit(why, reading.at(why.get_size(), reading.offset(
                edge, up=-(px + 6 + small // 2))).clamp(window))
