"""Pucks: a halo ring of light around each physical puck (its centre left dark, so the marker
and the hand on it are not painted), coloured by state, with a short fading trail."""

from __future__ import annotations

import math
from dataclasses import replace
from itertools import chain
from typing import Callable, Collection, Sequence

import numpy as np
import pygame

from tabletop.drawing import halo_kernel, raster
from tabletop.drawing.discs import discs, uncover_drawn
from tabletop.drawing.reading import Reading
from tabletop.drawing.screens import font
from tabletop.drawing.trail_kernel import trails
from tabletop.drawing import primitives as P
from tabletop.drawing.life import PuckTrace
from tabletop.drawing.palette import (INK, PUCK_COLORS, PUCK_OFF, PUCK_STATES, TABLE, Color,
                                      fade, remember, rgb)
from tabletop.frames import Puck
from tabletop.table_map import TableToScreen


#: How far beyond the table's edge a puck is drawn in :data:`PUCK_OFF`, in puck radii: a puck
#: on the edge, its marker half over it, jitters across it by millimetres and keeps its colour
BEYOND_RADII = 1.0


def inside_edge(pucks: Sequence[Puck], table: tuple[float, float], radius_m: float
                ) -> tuple[Sequence[Puck], frozenset[int]]:
    """The pucks where the view draws them, and the ids of those drawn as beyond the table.
    ``table``: width, height in metres from the origin; ``radius_m``: a puck's radius (m).

    A puck past the edge (a serial or TUIO sender's coordinates) is drawn at the nearest
    point of the edge, its notch pointing to where it is; once it is more than
    :data:`BEYOND_RADII` radii past, its id is returned so its ring turns violet (a seen
    puck; a predicted one keeps its breathing amber, a lost one its fading red: the state
    is the puck's own). The mapping is continuous (a puck on the table is drawn where it is,
    one past the edge on the edge), so jitter across the edge moves the halo by no more than
    the jitter and its trail draws no backward stroke. Why not where it is: the margin
    around the table is not the table (the projector's light there falls on the floor or on
    the visitors, or off the window); why not hidden: the operator would see a tracked puck
    vanish with no word of it, and the characters still react to it. A ring on the edge
    lights the margin as far as it reaches, as a puck on the table at its edge does (about
    1.7 radii: 43 px at 840 px/m with 3 cm pucks); drawing it further inside would keep the
    margin dark but, to be continuous, move pucks on the table off their markers (lighting
    the marker the ring's dark centre keeps from the camera) or draw an outgoing puck
    moving inward.
    Not finite positions are left as they are (the halos' kernel skips them)."""
    w, h = table
    if all(0.0 <= p.x <= w and 0.0 <= p.y <= h for p in pucks):
        return pucks, frozenset()                    # (every puck on the table: the usual)
    far = BEYOND_RADII * radius_m
    out, beyond = [], set()
    for p in pucks:
        if (0.0 <= p.x <= w and 0.0 <= p.y <= h) or not (math.isfinite(p.x)
                                                          and math.isfinite(p.y)):
            out.append(p)
            continue
        x, y = min(max(p.x, 0.0), w), min(max(p.y, 0.0), h)
        if math.hypot(p.x - x, p.y - y) > far:
            beyond.add(p.id)
            out.append(replace(p, x=x, y=y, angle=math.atan2(p.y - y, p.x - x)))
        else:
            out.append(replace(p, x=x, y=y))
    return out, frozenset(beyond)


def under_pucks(surf: pygame.Surface, bare: pygame.Surface, pucks: Sequence[Puck],
                beyond: Collection[int], to_screen: TableToScreen, radius_m: float,
                drawn: Sequence[pygame.Rect]) -> None:
    """Leave every puck's top dark: inside the rim of each puck of ``pucks`` (as
    :func:`inside_edge` places them; ``radius_m``: a puck's radius, metres) the bare table
    ``bare`` (the view's static table, the size of ``surf``) is put back over whatever
    ``drawn`` (the rectangles the characters touched) painted there, so a character passing
    under a puck goes under it, as the physical puck hides it, and does not light the marker
    the camera reads and the hand on it, as the halo does not (its centre is left dark). Pucks
    in ``beyond`` (past the table's edge, drawn on it) are not there: nothing is hidden. One
    compiled call for all of them (:func:`tabletop.drawing.discs.uncover_drawn`)."""
    if not drawn:
        return
    xy = [(p.x, p.y) for p in pucks if p.id not in beyond]
    if not xy:
        return
    at = np.array(xy, dtype=np.float64)
    parts = [q for r in drawn for q in getattr(r, "parts", (r,))]   # (a union's own parts)
    view = raster.pixels(bare)
    if view is None or bare.get_size() != surf.get_size():   # (not the view's own table)
        px = to_screen.points(at)
        radii = radius_m * np.hypot(*(to_screen.points(at + (0.01, 0.0)) - px).T) / 0.01
        Rect = pygame.Rect
        for (x, y), r in zip(px.tolist(), radii.tolist()):
            if 0.0 < r and abs(x) < 30000.0 and abs(y) < 30000.0 and Rect(  # (NaN fails too)
                    int(x - r) - 1, int(y - r) - 1, int(2 * r) + 3, int(2 * r) + 3
                    ).collidelist(parts) >= 0:
                raster.draw(surf, discs, np.array([(x, y)]), r, rgb(bare.get_at(
                    (min(max(int(x), 0), bare.get_width() - 1),
                     min(max(int(y), 0), bare.get_height() - 1)))[:3]))
        return
    # (a Rect iterates as x, y, width, height)
    rects = np.fromiter(chain.from_iterable(parts), np.int64, 4 * len(parts)).reshape(-1, 4)
    raster.draw(surf, uncover_drawn, view[0], view[1], at, to_screen.H, float(radius_m), rects)


def state_color(state: str, beyond: bool = False) -> Color:
    """The halo colour of a puck state (``seen``, ``coasting`` or ``lost``); ``beyond``: a
    seen puck past the table's edge (:func:`inside_edge`) is :data:`PUCK_OFF`."""
    if beyond and state == "seen":
        return PUCK_OFF
    return PUCK_STATES.get(state, PUCK_STATES["seen"])


def trail_inks(color: Color, alpha: float) -> tuple[int, int, int]:
    """A trail's three age steps' colours (oldest to newest, packed 0xRRGGBB) for a puck of
    ``color`` shown at opacity ``alpha`` (remembered with the puck's look: :func:`_look`)."""
    return tuple(rgb(fade(color, alpha * k, TABLE)) for k in (0.18, 0.32, 0.5))  # type: ignore


def draw_trails(surf: pygame.Surface, paths: Sequence[np.ndarray], centers: np.ndarray,
                inks: Sequence[tuple[int, int, int]], holes: np.ndarray, H: np.ndarray, t: float,
                span_s: float) -> list[pygame.Rect]:
    """Every puck's recent path (``paths``: N x 3 arrays of table x, y metres and time s) as a
    line that fades with age (three steps, newest brightest: ``inks``, see
    :func:`trail_inks`), ending at its halo, in one compiled call. ``centers``: each puck's
    centre px (N x 2); ``holes``: radius px around it that stays dark; ``H``: table metres ->
    pixels. Returns the rectangles touched."""
    starts = np.zeros(len(paths) + 1, dtype=np.int64)
    starts[1:] = np.cumsum([len(path) for path in paths])
    if not starts[-1]:
        return []
    pts = np.concatenate(paths)
    rects = np.zeros((len(paths), 4), dtype=np.int64)
    # age steps: 2 newest (v >= 2, with v = 3 (1 - age / span)), 1, 0 oldest and anything older
    raster.draw(surf, trails, pts, starts, H,
                np.ascontiguousarray(centers, dtype=np.float64),
                np.ascontiguousarray(holes, dtype=np.float64), np.array(inks, dtype=np.int64),
                float(t - span_s / 3.0), float(t - 2.0 * span_s / 3.0), rects)
    return [pygame.Rect(x0, y0, x1 - x0 + 1, y1 - y0 + 1) for x0, y0, x1, y1 in rects.tolist()
            if x1 >= x0]


_STATE_CODES = {"seen": halo_kernel.SEEN, "coasting": halo_kernel.COASTING,
                "lost": halo_kernel.LOST}
_looks: dict[tuple, tuple] = {}


def _look(state: str, alpha: float, beyond: bool = False
          ) -> tuple[int, Color, tuple[int, int, int]]:
    """(state code for the halos' kernel, halo colour, trail inks) of a puck in ``state``
    shown at opacity ``alpha``, ``beyond`` the table's edge or not (remembered)."""
    key = (state, alpha, beyond)
    look = _looks.get(key)
    if look is None:
        color = state_color(state, beyond)
        look = remember(_looks, key, (_STATE_CODES.get(state, 0), color,
                                      trail_inks(color, alpha)), 1024)
    return look


_TABLE_RGB = np.array(TABLE, dtype=np.float64)


def draw_pucks(surf: pygame.Surface, items: Sequence[tuple[PuckTrace, str, float]],
               to_screen: TableToScreen, puck_radius_m: float, t: float, trail_s: float,
               label: Callable[[int], pygame.Surface] | None = None,
               beyond: Collection[int] = ()) -> list[pygame.Rect]:
    """Every puck of ``items`` ((trace, state, opacity) each, see
    :meth:`tabletop.drawing.life.Traces.update`), in layers: the trails, then each halo's ring
    of light (coloured by state, the puck's centre left dark; every ring in one additive blit
    call), then the bright notches along the pucks' headings (one compiled call per colour),
    then, given ``label`` (puck id -> its text, turned upright on the table), each id beside
    its halo's upper right as the reader at the table's near edge sees it.
    ``beyond``: ids of pucks past the table's edge (:func:`inside_edge`).
    ``puck_radius_m``: a puck's radius in metres. A coasting puck's ring breathes quickly; a
    lost one's widens as it fades. The geometry of every halo is one compiled call
    (:func:`tabletop.drawing.halo_kernel.halos`). Returns the rectangles touched."""
    n = len(items)
    if not n:
        return []
    v = np.array([(tr.puck.x, tr.puck.y, tr.puck.angle) for tr, _, _ in items], dtype=np.float64)
    looks = [_look(s, a, tr.puck.id in beyond) for tr, s, a in items]
    geo = np.empty((n, halo_kernel.FIELDS))
    halo_kernel.halos(v, np.array([lk[0] for lk in looks], dtype=np.int64),
                      np.array([a for *_, a in items], dtype=np.float64), to_screen.H,
                      float(puck_radius_m), 0.7 + 0.3 * math.sin(t * 9.0), _TABLE_RGB, geo)
    paths = [tr.path.points() for tr, _, _ in items]
    inks = [lk[2] for lk in looks]
    keep = geo[:, 8] >= 0                        # (not finite or too far: not drawn)
    if keep.all():
        out = draw_trails(surf, paths, geo[:, 0:2], inks, geo[:, 2], to_screen.H, t, trail_s)
    else:
        k = keep.tolist()
        out = draw_trails(surf, [p for p, ok in zip(paths, k) if ok], geo[keep, 0:2],
                          [i for i, ok in zip(inks, k) if ok], geo[keep, 2], to_screen.H, t,
                          trail_s)
    rings, notches, labels = [], {}, []
    reading, window = to_screen.reading(), surf.get_rect()
    ring, append = P.ring_surface, out.append
    for (tr, _, _), (_, color, _), (_, _, _, R, w, a, xi, yi, e, nx, ny, nr, ncol) in zip(
            items, looks, geo.tolist()):
        if e < 0:
            continue
        xi, yi = int(xi), int(yi)
        half = int(e)
        if a > 0.02 and R >= 1:
            g = ring(R, w, color, a)
            gw = g.get_width()
            rings.append((g, (xi - gw // 2, yi - gw // 2)))
            if gw // 2 > half:
                half = gw // 2
        append(P.disc_rect(xi, yi, half + 1))   # (ring and notch lie in this disc)
        if nr > 0:
            notches.setdefault((int(ncol), nr), []).append((nx, ny))
        if label is not None:
            img = label(tr.puck.id)
            labels.append((img, label_place(reading, img.get_size(), (xi, yi), round(R),
                                            window)))
    surf.fblits(rings, pygame.BLEND_ADD)
    for (col, rad), q in notches.items():
        # (filled to the whole pixels of its radius + 0.5 px, as gfxdraw's discs are)
        raster.draw(surf, discs, np.array(q, dtype=np.float64),
                    float(int(rad + 0.5) + 0.5), col)
    if labels:
        out.extend(surf.blits(labels))
    return out


def puck_color(puck_id: int) -> Color:
    """The identity colour of a puck id (its label in designer mode)."""
    return PUCK_COLORS[puck_id % len(PUCK_COLORS)]


# A puck's id is ringed with dark (:data:`INK`, no light) this many of its pixels wide (at
# least 1 px): over a character its colour alone did not read (the orange "1" on the pink
# lover of examples/split, the contrast ratio of their light 1.2).
LABEL_RIM = 0.06


# (right, up) sides of a halo its id is tried on, as the reader sees them
_SIDES = ((1, 1), (-1, 1), (1, -1), (-1, -1))


def label_place(reading: Reading, size: tuple[int, int], centre: tuple[int, int], r: int,
                window: pygame.Rect) -> pygame.Rect:
    """Where a puck's id (``size`` px) stands beside its halo (``centre``, radius ``r`` px):
    at the halo's upper right as the reader sees it, else the first of its upper left, lower
    right and lower left that lies whole in ``window``, else moved into it. A table filling
    the projector's image put the id of a puck within a halo of its far or right edge out of
    the window: the designer saw a ring without its id."""
    x, y = centre
    if type(x) is not int or type(y) is not int:
        return _place(_sides(reading, size, r, centre), 0, 0, window)
    key = (reading.right, reading.up, size, r)
    sides = _label_sides.get(key)
    if sides is None:
        sides = remember(_label_sides, key, _sides(reading, size, r, (0, 0)), 1024)
    return _place(sides, x, y, window)


# Where an id stands on each side of a halo about pixel (0, 0), by reading, size and radius:
# about a whole pixel (x, y) it is the same moved by (x, y) (the sides' offsets are multiples
# of 1/4 px: the sums are exact, and floor(x + d) = x + floor(d)); every puck's id is placed
# every frame (the overlay shown), and placed anew each time its four sides were 0.08-0.10 ms
# of a busy frame under load
_label_sides: dict[tuple, list[pygame.Rect]] = {}


def _sides(reading: Reading, size: tuple[int, int], r: int,
           centre: tuple[float, float]) -> list[pygame.Rect]:
    """The id's rectangle on each side of :data:`_SIDES` of the halo about ``centre``."""
    return [reading.at(size, reading.offset(centre, right * 0.75 * r, up * r),
                       (0.0 if right > 0 else 1.0, 0.6 if up > 0 else 0.4))
            for right, up in _SIDES]


def _place(sides: list[pygame.Rect], x: int, y: int, window: pygame.Rect) -> pygame.Rect:
    """The first of ``sides`` moved by (``x``, ``y``) px whole in ``window``, else the first
    moved into it."""
    first = None
    for q in sides:
        rect = q.move(x, y)
        if window.contains(rect):
            return rect
        first = first or rect
    return first.clamp(window)


def id_label(puck_id: int, px: int, reading: Reading) -> pygame.Surface:
    """``puck_id`` in its colour (:func:`puck_color`), ``px`` pixels tall, ringed with dark
    (:data:`LABEL_RIM`), upright on the table as ``reading`` says."""
    f, text = font(px), str(puck_id)
    ink = f.render(text, True, puck_color(puck_id))
    rim = max(1, round(LABEL_RIM * px))
    dark = f.render(text, True, INK)
    out = pygame.Surface((ink.get_width() + 2 * rim, ink.get_height() + 2 * rim),
                         pygame.SRCALPHA)
    out.blits([(dark, (rim + dx, rim + dy)) for dx in range(-rim, rim + 1)
               for dy in range(-rim, rim + 1) if dx * dx + dy * dy <= rim * rim + rim])
    out.blit(ink, (rim, rim))
    return reading.turn(out)


def warm() -> None:
    """Compile (or load from the cache) the halos' kernel."""
    halo_kernel.warm()
