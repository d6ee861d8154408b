"""Room for the operator panel beside what it lies over (window pixels): where what is under
the panel leaves its window side clear, its lines wrap narrower so it ends before it."""

from __future__ import annotations

from typing import Callable, Sequence

import pygame

from tabletop.drawing import characters, screens
from tabletop.frames import CharacterState
from tabletop.table_map import TableToScreen

# Narrower in steps of NARROW_STEP px, to at least NARROW_MIN px: a source's line with its
# "(ignored: ...)" counts made the panel 600 px wide at 1280x720, its end seen through over the
# touch-pose character, and the line's last words read as text running past the panel's edge.
NARROW_STEP, NARROW_MIN = 32, 320
MUST_WEIGHT = 100        # a pixel of the studio's words weighs 100 of a character's
OVER_WORDS = 10 ** 9     # ... and a place over any of them loses to every place clear of them


def free_bands(keep: Sequence[pygame.Rect], x0: int, x1: int, top: int, bottom: int,
               gap: int = 4) -> list[tuple[int, int]]:
    """The rows (top, bottom pixel pairs, top to bottom) between ``top`` and ``bottom`` that
    none of ``keep`` lying across the columns ``x0``..``x1`` takes, ``gap`` pixels kept from
    each: where a panel that column-wide may stand without hiding them."""
    cuts = sorted((r.top - gap, r.bottom + gap) for r in keep if r.right > x0 and r.left < x1)
    bands, y = [], top
    for a, b in cuts:
        if a > y:
            bands.append((y, a))
        y = max(y, b)
    if bottom > y:
        bands.append((y, bottom))
    return bands


def clips(place: pygame.Rect, rects: Sequence[pygame.Rect]) -> list[pygame.Rect]:
    """The parts of ``rects`` under a panel at ``place``, in the panel's pixels."""
    return [place.clip(r).move(-place.x, -place.y) for r in rects if place.colliderect(r)]


def bodies(avoid: Sequence[pygame.Rect], drawn: Sequence[tuple[pygame.Rect, CharacterState]],
           table: TableToScreen, place: pygame.Rect, window_h: int) -> list[pygame.Rect]:
    """``avoid`` with each character's drawn rectangle (``drawn``: its glow's bounds, with its
    state) in the column of the panel at ``place`` (window pixels, ``window_h`` high) cut to its
    body (:func:`characters.bodies`): the panel's corner is chosen, its lines wrap to end and a
    narrower panel is taken by the bodies it hides, over the glows' rims. A reactor 0.2 m long
    at 1280x720: glow 309 px wide, body 189 px; judged on the glows, the panel was not narrowed
    (under NARROW_MIN, or taller over a glow below it). The MOP example, 20 s recorded, drawn
    at 1280x720: the panel lay over a body in 1142 -> 226 frames (mean 3,998 -> 1,368 body px),
    over glows 10,164 -> 10,080 px a frame; it changes place or shape 1 -> 10 times (the
    dancer's arms reaching under the narrower panel and back; 3 with :class:`PanelPlace`'s
    dwell)."""
    states = {id(r): c for r, c in drawn}
    column = pygame.Rect(place.x, 0, place.w, window_h)   # where a narrower panel stands
    out = []
    for r in avoid:
        c = states.get(id(r))
        b = characters.bodies([c], table) if c is not None and column.colliderect(r) else []
        out.append((r.clip(b[0]) or r) if b else r)
    return out


def narrow_width(place: pygame.Rect, avoid: Sequence[pygame.Rect], window_w: int) -> int | None:
    """The width (px) a panel at ``place`` wraps to so that it ends before everything of
    ``avoid`` under it, or None when that leaves less than NARROW_MIN or it is no narrower."""
    left = place.x <= window_w - place.right
    ends = [r.left - place.x if left else place.right - r.right
            for r in avoid if place.colliderect(r)]
    if not ends:
        return None
    width = (min(ends) - 8) // NARROW_STEP * NARROW_STEP
    return width if NARROW_MIN <= width < place.w else None


def narrow_at(place: pygame.Rect, size: tuple[int, int], window: tuple[int, int],
              must: Sequence[pygame.Rect]) -> pygame.Rect | None:
    """Where a narrower panel of ``size`` stands in the corner of ``place``, or None when it
    would be taller than the window or lie over the studio's words (``must``)."""
    (W, H), (w, h) = window, size
    at = pygame.Rect(place.x if place.x <= W - place.right else place.right - w,
                     place.y if place.centery < H / 2 else place.bottom - h, w, h)
    return None if h > H - 16 or at.collidelist(list(must)) >= 0 else at


def narrow_place(place: pygame.Rect, size: tuple[int, int], window: tuple[int, int],
                 avoid: Sequence[pygame.Rect], must: Sequence[pygame.Rect]
                 ) -> pygame.Rect | None:
    """Where a narrower panel of ``size`` stands in the corner of ``place``, or None when it
    would be taller than the window, lie over the studio's words (``must``), or hide no less
    of ``avoid``."""
    at = narrow_at(place, size, window, must)
    if at is None:
        return None

    def hidden(r: pygame.Rect) -> int:
        return sum(c.w * c.h for c in clips(r, avoid))
    return at if hidden(at) < hidden(place) else None


class NarrowPanel:
    """The narrowed panels of the last two widths, made again only when their lines, height,
    width or font change (the shape kept and the shape asked for, drawn on alternate frames)."""

    def __init__(self) -> None:
        self._made: dict[tuple, pygame.Surface] = {}

    def __call__(self, lines: Sequence[str], width: int, cap: int, px: int,
                 sizes: Sequence[int], keep: bool) -> pygame.Surface:
        key = (tuple(lines), width, cap, px)
        img = self._made.pop(key, None)
        if img is None:
            img, _ = screens.fitted_panel(lines, width, cap, px, keep=keep,
                                          px_sizes=[p for p in sizes if p <= px])
        self._made = {**dict(list(self._made.items())[-1:]), key: img}
        return img


def hidden(place: pygame.Rect, avoid: Sequence[pygame.Rect], must: Sequence[pygame.Rect],
           drawn: Sequence[tuple[pygame.Rect, CharacterState]], table: TableToScreen,
           window_h: int) -> int:
    """What a panel at ``place`` hides: the pixels of ``avoid`` (of a character its body), a
    pixel of ``must`` weighing MUST_WEIGHT, and OVER_WORDS more when it lies over any of
    them."""
    near = bodies(avoid, drawn, table, place, window_h)
    words = sum(c.w * c.h for c in clips(place, must))
    return (sum(c.w * c.h for c in clips(place, near)) + MUST_WEIGHT * words
            + (OVER_WORDS if words else 0))


# A narrowing or widening asked for by the bodies under the panel waits until the other shape
# has hidden clearly fewer body pixels (MARGIN_PX and a MARGIN share fewer) for DWELL_S of frame
# time, taken at once only when it hides AT_ONCE_PX fewer (a body deep under the text). The MOP
# example, 20 s drawn at 1280x720 (the dancer's arms reaching under the narrowed panel and
# back): the panel changes place or shape 10 -> 3 times, lies over a body in 222 -> 213 frames
# (mean 1,486 -> 1,440 body px); the price, the arms' reach under it kept for up to 0.5 s: body
# px p95 8,465 -> 9,082, max 11,193 -> 11,978 (taken at once from 1,500 to 3,000 px alike; a
# dwell alone: 1 change, 202 frames, mean 1,401, p95 10,560, max 16,344). A first panel, one
# over the studio's words and a move to another corner (its own rule) are taken at once.
DWELL_S, MARGIN_PX, MARGIN, AT_ONCE_PX = 1.0, 400, 0.25, 2000
SHOWN_GAP_S = 0.5    # a panel not placed for longer than this is placed afresh


class PanelPlace:
    """The operator panel's place in the window (pixels): its corner, left for one hiding
    less than half as much, and its lines narrowed to end before a body under it; a new place
    or shape is taken only once it has hidden clearly less for DWELL_S."""

    def __init__(self) -> None:
        self.corner = 0              # 0 top-left, 1 top-right, 2 bottom-left, 3 bottom-right,
        # then the same corners of the rows the studio's words leave free (4-7)
        self.width = 0               # the narrowed lines' width (px); 0: not narrowed
        self._since: float | None = None   # frame time (s) a clearly better layout showed
        self._seen: float | None = None    # frame time (s) the panel was last placed

    def __call__(self, corners: Sequence[tuple[int, int]], img: pygame.Surface,
                 avoid: Sequence[pygame.Rect], must: Sequence[pygame.Rect],
                 drawn: Sequence[tuple[pygame.Rect, CharacterState]], table: TableToScreen,
                 window: tuple[int, int], narrow: Callable[[int], pygame.Surface] | None,
                 t: float | None = None) -> tuple[pygame.Rect, pygame.Surface]:
        """The panel's rectangle and image: ``img`` in one of ``corners`` (its top-left, px),
        or, ``narrow`` given (its lines wrapped to a width), narrower in its corner; ``t`` the
        frame's time (s; None: no frames, every layout taken at once)."""
        W, H = window
        size = img.get_size()
        self.corner %= len(corners)    # (a free rows' place falls back to its window corner)
        over: dict[int, int] = {}

        def hides(i: int) -> int:
            if i not in over:
                over[i] = hidden(pygame.Rect(corners[i], size), avoid, must, drawn, table, H)
            return over[i]
        corner, now = self.corner, hides(self.corner)
        if now > 0:
            best = min(range(4), key=hides)
            if hides(best) >= OVER_WORDS and len(corners) > 4:   # every window corner
                best = min(range(len(corners)), key=hides)
            if hides(best) < 0.5 * now:
                corner = best
        place, out, width = pygame.Rect(corners[corner], size), img, 0
        if narrow is not None and place.collidelist(list(avoid)) >= 0:
            near = bodies(avoid, drawn, table, place, H)
            cut = narrow_width(place, near, W)
            if cut is not None:
                thin = narrow(cut)
                at = narrow_place(place, thin.get_size(), window, near, must)
                if at is not None:
                    place, out, width = at, thin, cut
        held = pygame.Rect(corners[self.corner], size)
        kept: tuple[pygame.Rect, pygame.Surface] | None = (held, img)
        if self.width:
            thin = narrow(self.width) if narrow is not None else None
            at = narrow_at(held, thin.get_size(), window, must) if thin is not None else None
            kept = None if thin is None or at is None or self.width >= size[0] else (at, thin)
        going = (t is not None and self._seen is not None and 0 <= t - self._seen <= SHOWN_GAP_S)
        self._seen = t
        if (corner, width) == (self.corner, self.width):
            self._since = None
            return place, out
        if kept is not None and going and corner == self.corner:
            was = hidden(kept[0], avoid, must, drawn, table, H)
            if was < OVER_WORDS:
                will = hidden(place, avoid, must, drawn, table, H)
                gain = was - will
                if gain < max(MARGIN_PX, MARGIN * was):
                    self._since = None
                    return kept
                self._since = t if self._since is None else self._since
                if t - self._since < DWELL_S and gain < AT_ONCE_PX:
                    return kept
        self.corner, self.width, self._since = corner, width, None
        return place, out
