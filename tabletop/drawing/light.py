"""A hinted pose (MOP early feedback) drawn as the faint light it is: the suspected action's
pose in the character's own lively colour, casting no glow, drawn on black and added onto the
view, so it only brightens what lies under it; drawn as an outline, its inside fainter still,
with the action's name above it, so that it reads as a hint, not as a second character."""

from __future__ import annotations

from typing import Callable

import numpy as np
import pygame

from tabletop.drawing import outline_kernel, raster, screens
from tabletop.drawing.characters import Pose
from tabletop.drawing.palette import Color, lighten, remember, vivid
from tabletop.drawing.reading import Reading

HINT_ALPHA = 0.5         # opacity of a hinted pose (early feedback) at probability 1
HINT_SHOWN = 0.03        # a hinted pose is drawn while its strength (0..1) is above this
# A hinted pose is drawn as its outline, HINT_RIM px wide at 1280x720 (in proportion to the
# window's smaller side), its inside at HINT_FILL of its light. Filled, a hint looked like a
# second, shadow character beside the real one (the MOP example's dancer and mime, 1280x720).
HINT_RIM, HINT_FILL = 2, 0.2
HINT_LABEL_PX = 16       # the action's name above a hinted pose (px at 720 deep) ...
LABEL_GAIN = 2.0         # ... whole from a hint's strength 0.5 (thin words at a hint's
# opacity: "figure eight?" at strength 0.3 was not read in a window run of the MOP example)


def hinted_pose(pose: Pose, color: Color, hint: float) -> Pose:
    """The faint pose of a character's suspected action: ``pose`` at :data:`HINT_ALPHA` times
    the ``hint``'s strength (0..1), in the character's ``color`` at full value and saturation
    0.8, casting no glow, faded toward black (it is added as light, :class:`AddedLight`).
    Lightened toward white instead, a faint pose added onto the navy table read grey for the
    warm and pale characters (the bird's: CIELAB chroma 1.8, its hue 72 degrees off); saturated
    its hue stays within 24 degrees of the character's and it is fainter than the character
    acting (luminance 2.0 to 2.8 times lower at probability 1, 1.6 before)."""
    # (made positionally, its colour remembered: dataclasses.replace and the colour's HSV
    # round trip each frame were most of the hint's own Python)
    p = pose
    return Pose(p.center, p.angle, p.ppm, p.alpha * HINT_ALPHA * hint, p.scale, p.breath,
                p.stretch, p.motion, p.blink, p.gaze, hint_color(color), p.phase, 0.0, (0, 0, 0))


_hint_colors: dict[tuple, Color] = {}


def hint_color(color: Color) -> Color:
    """A hinted pose's colour: the character's ``color`` at full value and saturation 0.8
    (remembered)."""
    key = tuple(color)
    out = _hint_colors.get(key)
    if out is None:
        out = remember(_hint_colors, key, vivid(key, 1.0, 0.8, 0.8), 256)
    return out


def hint_rim(window: tuple[int, int]) -> int:
    """The outline's width (px) of a hinted pose in a ``window`` (W, H): :data:`HINT_RIM` at
    720 px on its smaller side, in proportion, at least 2."""
    return max(2, round(HINT_RIM * min(window) / 720))


def as_points(hint: tuple[Pose, np.ndarray] | None) -> tuple[Pose, np.ndarray] | None:
    """A hinted pose with its points as the compiled drawing takes them (N x 2 floats)."""
    if hint is None:
        return None
    return hint[0], np.ascontiguousarray(hint[1], dtype=np.float64).reshape(-1, 2)


# A hint's outlined light is kept and added again (one additive blit) in the next frame when
# its points are the very same object, instead of being painted and outlined again: the MOP
# engine ticks at 30 Hz and the view at 60 (examples/mop.yaml, 10 s headless: 394 of 833
# hints drawn, 47 %, had the points of the frame before; 205 of 446 at 31 fps under load). It
# shows the pose's fade and breath of the frame before, once: the next frame paints again (a
# hint keeps its points while it fades out: kept longer, its fade stood still). Kept from a
# character's first repeat on (a hint whose points are new every frame, bench/view.py's, pays
# nothing); let go after KEEP_OFF frames in a row of new points. Same-opacity repeats only
# (its inks' 1/128 steps) were 24 of those 205: the strength moves every frame.
KEEP_OFF = 3


class _Kept:
    """One hinted character's light: the points it was drawn from, and while kept, the light
    (its outline, black elsewhere, the view's size) and where it lies."""

    def __init__(self, points: object) -> None:
        self.points = points
        self.again = False            # the kept light was added again once
        self.on = False               # keeping (its points were seen twice)
        self.light: pygame.Surface | None = None
        self.rect: pygame.Rect | None = None
        self.new = 0                  # frames in a row drawn from new points
        self.used = True              # drawn in the view's last frame


class AddedLight:
    """A black scratch surface the size of the view: what is drawn on it is added onto the
    view. Painted over the table with the character's inks faded toward the table's colour, a
    faint pose crossing the character's own glow put out its light: a dark shadow of the pose
    on the glow (a salamander's hinted tail, 1024x768), its pupils darker still."""

    def __init__(self) -> None:
        self._scratch: pygame.Surface | None = None
        self._spans = outline_kernel.empty_spans(0, 0)  # the scratch's rows drawn (first, last)
        self._eroded: pygame.Surface | None = None    # the outline's work (:meth:`_outline`)
        self._kept: dict[str, _Kept] = {}             # by character (:data:`KEEP_OFF`)
        self._spare: list[pygame.Surface] = []        # kept lights let go, to use again

    def begin(self) -> None:
        """A new frame of the view: the lights of characters not drawn in the last are let go."""
        for k in [k for k, v in self._kept.items() if not v.used]:
            self._let_go(self._kept.pop(k))
        for v in self._kept.values():
            v.used = False

    def _let_go(self, kept: _Kept) -> None:
        """``kept``'s light surface kept for another character's (a view-sized surface made
        anew touches 3.7 MB at 1280x720: its first paint cost ~0.5 ms more, mop.yaml's hints
        coming and going)."""
        if kept.light is not None and len(self._spare) < 4:
            self._spare.append(kept.light)
        kept.light, kept.rect = None, None

    def add(self, target: pygame.Surface, paint: Callable[..., pygame.Rect | None],
            rim: int = 0, key: str | None = None, points: object = None,
            marks: bool = False) -> pygame.Rect | None:
        """What ``paint`` draws on black (a pose faded toward black, ``Pose.ground``), added
        onto ``target``; ``rim`` > 0: only its outline, ``rim`` px wide, whole, and its inside
        at :data:`HINT_FILL` (:meth:`_outline`). Given a ``key`` (the character) and the
        ``points`` it is drawn from, the light is added again in the next frame drawn from the
        same points (:data:`KEEP_OFF`). ``marks``: ``paint`` is given the rows' spans too
        (``paint(scratch, spans)``) and marks in them every pixel it draws, as the drawing's
        kernels do given them (:func:`tabletop.drawing.blend.mark`): only those are walked;
        else its whole rectangle is. Returns the rectangle it touched there."""
        kept = None
        if key is not None:
            kept = self._kept.get(key)
            if kept is None:
                kept = self._kept[key] = _Kept(points)
            elif points is kept.points:
                kept.new = 0
                if (kept.rect is not None and not kept.again
                        and kept.light.get_size() == target.get_size()):
                    target.blit(kept.light, kept.rect, kept.rect, pygame.BLEND_RGB_ADD)
                    kept.used = kept.again = True
                    return kept.rect.copy()
                kept.on = True           # the same points again, nothing kept: keep from now
            else:
                kept.points, kept.new = points, kept.new + 1
                if kept.new >= KEEP_OFF:
                    kept.on = False
                    self._let_go(kept)
            kept.used, kept.rect, kept.again = True, None, False
        scratch, spans = self._scratch, self._spans
        if scratch is None or scratch.get_size() != target.get_size():
            scratch = self._scratch = pygame.Surface(target.get_size(), 0, target)
            scratch.fill((0, 0, 0))
            spans = self._spans = outline_kernel.empty_spans(scratch.get_height(),
                                                             scratch.get_width())
        r = paint(scratch, spans) if marks else paint(scratch)
        if r is None:
            return None
        r = r.clip(target.get_rect())
        if rim > 0:
            r = r.inflate(2 * rim + 2, 2 * rim + 2).clip(target.get_rect())
        into, out = raster.pixels(target), raster.pixels(scratch)
        if into is not None and out is not None and into[1].tolist() == out[1].tolist():
            keep = int(round(255 * (1.0 - HINT_FILL)))
            if not marks:                 # (what it drew unknown: every row of the rectangle)
                spans[r.top:r.bottom] = (r.left, r.right - 1)
            if kept is not None and kept.on:
                # what is added also kept (the same pixels added again: the add saturates
                # alike; outlined onto black and blitted, a paint cost 0.15-0.2 ms more)
                light = kept.light
                while light is None and self._spare:
                    light = kept.light = self._spare.pop()
                if light is None or light.get_size() != target.get_size():
                    light = kept.light = pygame.Surface(target.get_size(), 0, target)
                light.fill((0, 0, 0), r)
                lit = raster.pixels(light)
                if lit is not None:
                    outline_kernel.add_outline(_rows(out[0]), _rows(into[0]), _rows(lit[0]),
                                               out[1], r.left, r.top, r.right, r.bottom, rim,
                                               keep, True, spans)
                    kept.rect = r.copy()
                    return r
            # one compiled pass over the drawn spans, the same pixels as :meth:`_outline`'s
            # seven passes and the add: bench/view.py's hinted scene (3 hints, 1280x720)
            # 0.46 ms less draw CPU per frame (paired median, 7.25 -> 6.82 ms)
            view = _rows(into[0])
            outline_kernel.add_outline(_rows(out[0]), view, view, out[1], r.left, r.top,
                                       r.right, r.bottom, rim, keep, False, spans)
            return r
        spans[:, 0], spans[:, 1] = scratch.get_width(), -1    # (the passes below clear it)
        if rim > 0:
            self._outline(scratch, r, rim)
        target.blit(scratch, r, r, pygame.BLEND_RGB_ADD)
        # black again (multiplied by black: a sixth of a plain fill's time here, 0.03 ms for
        # a 300 x 220 px figure)
        scratch.fill((0, 0, 0), r, pygame.BLEND_RGB_MULT)
        return r

    def _outline(self, scratch: pygame.Surface, r: pygame.Rect, rim: int) -> None:
        """What is drawn in ``r`` of ``scratch`` cut to its outline: less :data:`HINT_FILL`'s
        remainder of itself eroded ``rim`` px (the least of itself moved ``rim`` px four
        ways), so its edges keep their light and its inside a fifth of it."""
        eroded = self._eroded
        if eroded is None or eroded.get_size() != scratch.get_size():
            eroded = self._eroded = pygame.Surface(scratch.get_size(), 0, scratch)
        eroded.fill((255, 255, 255), r)    # (then the least: a fifth of a plain copy's time)
        for dx, dy in ((rim, 0), (-rim, 0), (0, rim), (0, -rim)):
            eroded.blit(scratch, r.move(dx, dy), r, pygame.BLEND_RGB_MIN)
        k = int(round(255 * (1.0 - HINT_FILL)))
        eroded.fill((k, k, k), r, pygame.BLEND_RGB_MULT)
        scratch.blit(eroded, r, r, pygame.BLEND_RGB_SUB)


_byte_rows: dict[int, tuple[np.ndarray, np.ndarray]] = {}


def _rows(pix: np.ndarray) -> np.ndarray:
    """:func:`tabletop.drawing.outline_kernel.rows` of ``pix``, made once per pixels' view
    (:func:`tabletop.drawing.raster.pixels` keeps one per surface)."""
    known = _byte_rows.get(id(pix))
    if known is None or known[0] is not pix:
        if len(_byte_rows) >= 16:
            _byte_rows.clear()
        known = _byte_rows[id(pix)] = (pix, outline_kernel.rows(pix))
    return known[1]


def hint_label(window: tuple[int, int], action: str, around: pygame.Rect, color: Color,
               strength: float, reading: Reading, table: pygame.Rect
               ) -> tuple[pygame.Surface, pygame.Rect]:
    """The suspected ``action``'s name with a question mark ("figure eight?") above a hinted
    pose drawn in ``around`` (px), for the reader at the table's near edge (``reading``), in
    the hint's ``color`` lightened, :data:`LABEL_GAIN` times as strong as the hint
    (``strength`` 0..1, at most whole), on the ``table`` (its bounds in the window, px: below
    the pose where above would leave it; the bird's "wave?" in the MOP example stood beyond
    the table's far edge, 1280x720), in a ``window`` (W, H px): its image and where to blit it
    (over every character: drawn with the figure, the next one covered it)."""
    W, H = window
    px = max(13, round(HINT_LABEL_PX * min(W, H) / 720))   # (11 px at 800x600 was not read)
    line = action.replace("_", " ") + "?"
    ink = lighten(hint_color(color), 0.3)
    img = screens.turned_line(line, px, ink, reading)
    up = (around.h if reading.up[1] else around.w) / 2 + 4
    at = reading.at(img.get_size(), reading.offset(around.center, up=up), (0.5, 1.0))
    if not table.contains(at):
        below = reading.at(img.get_size(), reading.offset(around.center, up=-up), (0.5, 0.0))
        at = below if table.contains(below) else at
    at = at.clamp(table if table.w >= at.w and table.h >= at.h else pygame.Rect(0, 0, W, H))
    # a copy per alpha: blitted after every character, two hints of one name and colour
    # sharing the kept render showed both at the alpha set last; kept, as the same few alphas
    # recur (a hint at its strength, frame after frame: copy + set_alpha each frame were
    # a third of hint_label's time)
    alpha = int(round(255 * min(max(LABEL_GAIN * strength, 0.0), 1.0)))
    key = (id(img), alpha)
    kept = _names.get(key)
    if kept is None or kept[0] is not img:
        copy = img.copy()
        copy.set_alpha(alpha)
        kept = remember(_names, key, (img, copy), 256)
    return kept[1], at


_names: dict[tuple[int, int], tuple[pygame.Surface, pygame.Surface]] = {}
