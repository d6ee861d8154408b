"""Whole-table looks: the table itself, the calm "one moment" screen shown while the cameras
reconnect, the idle look while nobody plays, and the operator's text on a translucent panel."""

from __future__ import annotations

import math
import re
from typing import Any, Sequence

import numpy as np
import pygame

from tabletop.drawing import primitives as P
from tabletop.drawing.palette import (BACKGROUND, GRID, PANEL, TABLE, TABLE_EDGE, TEXT, Color,
                                      mix)
from tabletop.drawing.reading import PLAIN, Reading

_fonts: dict[int, pygame.font.Font] = {}


def font(px: int) -> pygame.font.Font:
    """pygame's default font at ``px`` pixels (loaded once)."""
    f = _fonts.get(px)
    if f is None:
        if not pygame.font.get_init():
            pygame.font.init()
        f = _fonts[px] = pygame.font.Font(None, px)
    return f


def table_surface(size: tuple[int, int], corners_px: np.ndarray, grid_px: Sequence[tuple]
                  ) -> pygame.Surface:
    """The static table: black around it, the table a deep navy brightening gently to its
    centre, a faint 10 cm grid of dots and a soft edge. ``grid_px``: dot positions (px)."""
    s = pygame.Surface(size)
    s.fill(BACKGROUND)
    P.polygon(s, TABLE, corners_px)
    c = corners_px.mean(axis=0)
    span = float(np.ptp(corners_px, axis=0).max())
    mask = pygame.Surface(size)
    mask.fill((0, 0, 0))
    P.polygon(mask, (255, 255, 255), corners_px)
    light = P.glow_surface(span * 0.55, (10, 12, 18), 1.0)
    tmp = pygame.Surface(size)
    tmp.fill((0, 0, 0))
    tmp.blit(light, light.get_rect(center=(int(c[0]), int(c[1]))))
    tmp.blit(mask, (0, 0), special_flags=pygame.BLEND_MULT)
    s.blit(tmp, (0, 0), special_flags=pygame.BLEND_ADD)
    for q in grid_px:
        P.disc(s, GRID, q, 1.3)
    pygame.draw.aalines(s, TABLE_EDGE, True, corners_px.tolist())
    return s


_panel_lines: dict[tuple[str, int], pygame.Surface] = {}


def panel_line(line: str, px: int = 20, keep: bool = True) -> pygame.Surface:
    """One line of a :func:`panel`, rendered once while it stays the same (the operator
    overlay's figures change a few lines at a time; a whole panel of renders costs ~1 ms).
    ``keep`` False: a line not seen again soon (a snapshot's, once a minute) is not kept."""
    key = (line, px)
    img = _panel_lines.get(key)
    if img is None:
        img = words(line, px, TEXT, PANEL_SUPERSAMPLE)
        if keep:
            if len(_panel_lines) > 256:
                _panel_lines.clear()
            _panel_lines[key] = img
    return img


# The panel's lines are rendered twice as large and scaled down (:func:`words`): at their own
# size (13 to 29 px) the font's hinting rounds each letter's advance to whole pixels, and the
# operator read "zig z ag", "37.7 f ps", "inpu ts" (800x600, 13 px; "f ps" up to 29 px at
# 1920x1080). Twice is enough to space them evenly: 0.12 ms a line at 20 px (0.08 ms plain,
# 0.36 ms four times as large), and only changed lines are rendered, in the overlay's refresh.
PANEL_SUPERSAMPLE = 2


class Sampled:
    """Text measured as :func:`words` draws it at ``px`` pixels, ``k`` times as large and
    scaled down (for :func:`fit_lines`)."""

    def __init__(self, px: int, k: int = PANEL_SUPERSAMPLE) -> None:
        self.f, self.k = font(px * k), k

    def size(self, line: str) -> tuple[int, int]:
        w, h = self.f.size(line)
        return max(1, round(w / self.k)), max(1, round(h / self.k))


def fit_lines(text: str, f: pygame.font.Font | Sampled, width: int) -> list[str]:
    """``text`` cut into lines no wider than ``width`` pixels in font ``f``: between its fields
    (parts set apart by two spaces, an overlay line's "age 12 ms"), at spaces inside a field
    only when the field alone is wider than a line, and inside a word (a file path) only when
    the word alone is wider. Cut at any space, examples/mop.yaml's source line in the overlay
    narrowed to 320 px at 1280x720 read "... scripted visitor  age" over "0 ms"."""
    fields = text.split("  ")
    if len(fields) < 2 or f.size(text)[0] <= width:
        return _fit_words(text, f, width)
    lines: list[str] = []
    line: str | None = None
    for field in fields:
        trial = field if line is None else f"{line}  {field}"
        if f.size(trial)[0] <= width or not trial.strip():
            line = trial
            continue
        if f.size(field)[0] <= width:       # on a line of its own, whole
            if line is not None and line.strip():
                lines.append(line)
            line = field
            continue
        *whole, line = _fit_words(trial, f, width)   # wider than a line: cut at its spaces
        lines.extend(whole)
    lines.append(line or "")
    return lines


def _fit_words(text: str, f: pygame.font.Font | Sampled, width: int) -> list[str]:
    """``text`` cut into lines no wider than ``width`` pixels at spaces, and inside a word only
    when the word alone is wider."""
    lines: list[str] = []
    line = ""
    for word in text.split(" "):
        trial = f"{line} {word}" if line else word
        if f.size(trial)[0] <= width or not trial.strip():
            line = trial
            continue
        if line:
            lines.append(line)
        line = word
        while len(line) > 1 and f.size(line)[0] > width:
            k = len(line) - 1
            while k > 1 and f.size(line[:k])[0] > width:
                k -= 1
            lines.append(line[:k])
            line = line[k:]
    lines.append(line)
    return lines


def cells(line: str) -> list[str]:
    """A panel line's table cells: split at tabs, the first keeping its indent, the others
    trimmed (a line without a tab is one cell)."""
    parts = line.split("\t")
    return [parts[0].rstrip()] + [p.strip() for p in parts[1:]]


def _table_row(parts: Sequence[pygame.Surface], widths: Sequence[int], gap: int) -> pygame.Surface:
    """A row of cells: the first left-aligned, the others right-aligned in columns of
    ``widths`` pixels (the figures' decimal points and units line up)."""
    w = sum(widths[:len(parts)]) + gap * (len(parts) - 1)
    row = pygame.Surface((w, max(p.get_height() for p in parts)), pygame.SRCALPHA)
    x = 0
    for k, img in enumerate(parts):
        row.blit(img, (x if k == 0 else x + widths[k] - img.get_width(), 0))
        x += widths[k] + gap
    return row


def _split_row(line: str, parts: Sequence[pygame.Surface], widths: Sequence[int], gap: int,
               room: int, px: int, keep: bool) -> list[pygame.Surface]:
    """A table row for a panel narrower than the table (``room`` px; a 320 px window's panel
    is 284 px, the stage table ~370 px): its first cell on a line of its own, its figures on
    the next, right-aligned in their columns at the panel's right edge, or wrapped as words
    where even they are wider than ``room``, so no figure runs past the window's edge."""
    f = Sampled(px)
    head = [panel_line(p, px, keep) for p in fit_lines(cells(line)[0], f, room)]
    figures = sum(widths[1:]) + gap * (len(widths) - 2)
    if figures + gap > room:
        words = " ".join(cells(line)[1:])
        return head + [panel_line(p, px, keep) for p in fit_lines(words, f, room)]
    spacer = pygame.Surface((0, 0), pygame.SRCALPHA)
    widths = [room - figures - gap, *widths[1:len(parts)]]
    return head + [_table_row([spacer, *parts[1:]], widths, gap)]


_FIGURE_UNIT = re.compile(r"([-+]?\d[\d.,:]*)\s+(\S.*)")   # "19.74 ms median": figure, words


def _bare_table(lines: Sequence[str], px: int, keep: bool, gap: int, room: int
                ) -> dict[int, pygame.Surface] | None:
    """The table rows of ``lines`` with their figures bare, the words every row's cell of a
    column shares ("ms median", "ms p99") said once on a head row above the first: the
    surfaces by line index (the head's: -1), or None when the cells do not share their words
    or the table is still wider than ``room`` px. The MOP example's panel, narrowed to 320 px
    to end before the dancer (1280x720), split each stage row into its name and its figures:
    24 text rows, 426 px tall, for 7 stages and 6 characters; bare, each row stays on one line:
    18 rows, 324 px (tests/tabletop/test_view_panel_bare.py)."""
    rows = {i: cells(line) for i, line in enumerate(lines) if "\t" in line}
    ncol = max((len(r) for r in rows.values()), default=0)
    if not rows or ncol < 2 or any(len(r) != ncol for r in rows.values()):
        return None
    split = {i: [_FIGURE_UNIT.fullmatch(c) for c in r[1:]] for i, r in rows.items()}
    if any(m is None for ms in split.values() for m in ms):
        return None
    units = [{ms[k].group(2) for ms in split.values()} for k in range(ncol - 1)]
    if any(len(u) != 1 for u in units):
        return None
    head = [pygame.Surface((0, 0), pygame.SRCALPHA)] + [panel_line(u.pop(), px, keep)
                                                         for u in units]
    parts = {i: [panel_line(rows[i][0], px, keep)]
             + [panel_line(m.group(1), px, keep) for m in ms] for i, ms in split.items()}
    widths = [max(r[k].get_width() for r in [head, *parts.values()]) for k in range(ncol)]
    if sum(widths) + gap * (ncol - 1) > room:
        return None
    return {-1: _table_row(head, widths, gap),
            **{i: _table_row(r, widths, gap) for i, r in parts.items()}}


def panel(lines: Sequence[str], px: int = 20, pad: int = 10,
          width: int | None = None, keep: bool = True) -> pygame.Surface:
    """Text lines on a translucent dark panel with rounded corners (an SRCALPHA surface); a
    line that would make the panel wider than ``width`` pixels wraps (``keep``: see
    :func:`panel_line`). Lines with tabs are rows of a table whose columns line up across the
    panel (the overlay's stage figures: spaces in a proportional font leave columns up to
    30 px apart from line to line); a table wider than the panel has its shared words said
    once above it (:func:`_bare_table`), else each row splits in two (:func:`_split_row`)."""
    rows = {i: [panel_line(c, px, keep) for c in cells(line)]
            for i, line in enumerate(lines) if "\t" in line}
    ncol = max((len(r) for r in rows.values()), default=0)
    widths = [max((r[k].get_width() for r in rows.values() if len(r) > k), default=0)
              for k in range(ncol)]
    gap = Sampled(px).size("   ")[0]
    room = None if width is None else width - 2 * pad
    split = room is not None and sum(widths) + gap * (ncol - 1) > room
    bare = _bare_table(lines, px, keep, gap, room) if split and room is not None else None
    imgs = []
    for i, line in enumerate(lines):
        if bare is not None and i in bare:
            if i == min(rows):
                imgs.append(bare[-1])
            imgs.append(bare[i])
            continue
        if i in rows and split:
            imgs.extend(_split_row(line, rows[i], widths, gap, room, px, keep))
            continue
        img = _table_row(rows[i], widths, gap) if i in rows else panel_line(line, px, keep)
        if room is not None and img.get_width() > room and i not in rows:
            imgs.extend(panel_line(part, px, keep) for part in fit_lines(line, Sampled(px), room))
        else:
            imgs.append(img)
    w = max((i.get_width() for i in imgs), default=0) + 2 * pad
    h = sum(i.get_height() + 2 for i in imgs) + 2 * pad - 2
    s = pygame.Surface((max(w, 1), max(h, 1)), pygame.SRCALPHA)
    pygame.draw.rect(s, PANEL, s.get_rect(), border_radius=8)
    y = pad
    for img in imgs:
        s.blit(img, (pad, y))
        y += img.get_height() + 2
    return s.convert_alpha() if pygame.display.get_surface() is not None else s


PANEL_PX = (20, 18, 16, 14, 13)     # the panel's font sizes, tried in turn in a small window
# ... in a window up to this many pixels deep (its height, as the panel reads); in a deeper one
# in proportion (a 1920x1080 projector's panel at 20 px was two thirds of its size at 1280x720)
PANEL_DEEP = 720


def panel_sizes(deep: int) -> tuple[int, ...]:
    """:data:`PANEL_PX` for a window ``deep`` pixels deep (:data:`PANEL_DEEP`)."""
    k = max(1.0, deep / PANEL_DEEP)
    return tuple(int(round(p * k)) for p in PANEL_PX)


def fitted_panel(lines: Sequence[str], width: int, height: int, px: int = PANEL_PX[0],
                 keep: bool = True, px_sizes: Sequence[int] = PANEL_PX
                 ) -> tuple[pygame.Surface, int]:
    """:func:`panel` no taller than ``height`` pixels: in the first font size of
    ``px_sizes`` (:func:`panel_sizes`) from ``px`` (the size that fitted last time) whose panel
    fits, trying the next larger one too when ``px`` fits (lines may have gone); in the
    smallest, the last lines give way to a line saying how many are left out (the shipped
    config's 13 overlay lines make a 256 px panel at 20 px: in a 400x225 window its first
    lines, tick, fps and errors, would stand above the window's top). Its margin is half the
    largest size, at least 10 px. Returns the panel and the font size used."""
    pad = max(10, px_sizes[0] // 2)
    sizes = [p for p in px_sizes if p <= px] or [px_sizes[-1]]
    larger = [p for p in px_sizes if p > sizes[0]]
    if larger:
        up = panel(lines, larger[-1], pad, width=width, keep=keep)
        if up.get_height() <= height:
            return up, larger[-1]
    for size in sizes:
        img = panel(lines, size, pad, width=width, keep=keep)
        if img.get_height() <= height:
            return img, size
    size = px_sizes[-1]
    for n in range(len(lines) - 1, 0, -1):
        cut = [*lines[:n], f"... {len(lines) - n} more lines (a larger window shows them)"]
        img = panel(cut, size, pad, width=width, keep=keep)
        if img.get_height() <= height:
            break
    return img, size


_lines: dict[tuple, pygame.Surface] = {}


# The visitors' words are rendered this many times larger and scaled down: at their own size
# the font's hinting rounds every letter's advance to whole pixels, and "touch the table" read
# "touch the ta ble" (26 px, the idle invitation at 1280x720; "tabl e" at 33 px).
SUPERSAMPLE = 4


def words(line: str, px: int, color: Color, k: int = SUPERSAMPLE) -> pygame.Surface:
    """``line`` at ``px`` pixels, its letters spaced as the font draws them at any size:
    rendered ``k`` times as large (:data:`SUPERSAMPLE`) and scaled down."""
    big = font(px * k).render(line, True, color)
    w, h = big.get_size()
    if w == 0:      # (an empty line: smoothscale would read past a surface 0 px wide)
        return pygame.Surface((0, max(1, round(h / k))), pygame.SRCALPHA)
    return pygame.transform.smoothscale(big, (max(1, round(w / k)), max(1, round(h / k))))


def text(surf: pygame.Surface, line: str, center: tuple[float, float], px: int,
         color: Color, alpha: float = 1.0, reading: Reading = PLAIN) -> None:
    """One line centred on ``center``, at opacity ``alpha``, upright on the table as
    ``reading`` says (rendered and turned once per line, size, colour and reading: a breathing
    line costs a blit per frame, not a render)."""
    img = turned_line(line, px, color, reading)
    img.set_alpha(int(round(255 * min(max(alpha, 0.0), 1.0))))
    surf.blit(img, reading.at(img.get_size(), center))


def turned_line(line: str, px: int, color: Color, reading: Reading) -> pygame.Surface:
    """``line`` in words ``px`` tall of ``color`` (:func:`words`) turned by ``reading`` for its
    reader, kept per line, size, colour and reading (a hint's name: :mod:`light`)."""
    key = (line, px, color, reading)
    img = _lines.get(key)
    if img is None:
        if len(_lines) > 64:
            _lines.clear()
        img = _lines[key] = reading.turn(words(line, px, color))
    return img


def one_moment(surf: pygame.Surface, t: float, alpha: float,
               centre: tuple[float, float] | None = None, reading: Reading = PLAIN) -> None:
    """The calm screen while every camera reconnects: the table dims, a slow ring of lights
    turns and breathes at its centre, "One moment" below it. It is for visitors, so it says
    nothing of why: the source's own words ("cannot open camera 0; reconnecting in 3 s") go to
    the log, the status file and the operator overlay's health lines. ``centre``: the table's
    centre in pixels (default: the window's), where the ring stands (a calibrated projector
    throwing beyond the table puts the table anywhere in its image); "below" and the words'
    way up are the reader's at the table's near edge (``reading``). Its size follows the
    window's smaller side (the calm screen's look at every table size, the same on a
    projector turned a quarter round)."""
    if alpha <= 0.0:
        return
    w, h = surf.get_size()
    k = int(round(255 * (1.0 - 0.75 * alpha)))
    surf.fill((k, k, k), special_flags=pygame.BLEND_MULT)      # dim the table
    side = min(w, h)
    cx, cy = reading.offset((w / 2, h / 2) if centre is None else centre, up=0.04 * side)
    R = 0.06 * side
    col = (150, 200, 255)
    for i in range(8):
        a = math.tau * i / 8 + 0.6 * t
        b = 0.5 + 0.5 * math.sin(1.3 * t - i * 0.55)
        P.glow(surf, (cx + R * math.cos(a), cy + R * math.sin(a)), 0.22 * R, col,
               alpha * (0.25 + 0.55 * b))
    text(surf, "One moment", reading.offset((cx, cy), up=-2.0 * R), int(0.05 * side),
         mix(col, TEXT, 0.6), alpha, reading)


INVITATIONS = {"puck": "put a puck on the table", "touch": "touch the table",
               "stream": "move the controller"}


def invitation(engines: Sequence[dict[str, Any]]) -> str:
    """The idle look's invitation for a configuration's ``engines``: what its visitors play
    with (pucks first, then touch, then streamed sensors); empty when nothing invites play."""
    wanted = set()
    for e in engines:
        kind = e.get("kind")
        if kind == "puppet_master":
            wanted.add("puck")
        elif kind == "touch_pose":
            wanted.add("touch")
        elif kind == "mop":
            wanted.update(i.get("kind", "puck") for p in e.get("performers", ())
                          for i in p.get("inputs", ()))
    for k in ("puck", "touch", "stream"):
        if k in wanted:
            return INVITATIONS[k]
    return ""


def idle(surf: pygame.Surface, t: float, alpha: float, area: np.ndarray,
         invitation: str = INVITATIONS["puck"], words: tuple[float, float] | None = None,
         px: int | None = None, reading: Reading = PLAIN) -> None:
    """The idle look while nobody plays: slow motes of light drift over the table (``area``:
    its corner pixels) and an ``invitation`` (none when empty) breathes between its centre and
    its near edge: at ``words`` (pixels; default 0.3 of ``area``'s height below its centre),
    ``px`` pixels tall (default from that height), upright for the reader at the near edge
    (``reading``)."""
    if alpha <= 0.0:
        return
    lo, hi = area.min(axis=0), area.max(axis=0)
    span = hi - lo
    for i in range(14):
        u = 0.5 + 0.45 * math.sin(0.071 * t * (1 + i % 3) + 1.7 * i)
        v = 0.5 + 0.42 * math.sin(0.053 * t * (1 + i % 4) + 2.9 * i)
        tw = 0.5 + 0.5 * math.sin(0.9 * t + 1.3 * i)
        P.glow(surf, (lo[0] + u * span[0], lo[1] + v * span[1]), 0.025 * span[0] + 4,
               (120, 170, 255) if i % 2 else (255, 170, 200), alpha * (0.2 + 0.35 * tw))
    if not invitation:
        return
    c = (lo + hi) / 2
    b = 0.55 + 0.45 * math.sin(0.8 * t)
    text(surf, invitation, words or (c[0], c[1] + 0.3 * span[1]),
         px or int(0.045 * span[1]) + 8, INVITE_COLOR, alpha * b, reading)


INVITE_COLOR = (200, 215, 240)
# Where the idle invitation may stand (fractions of the table's width and depth, 0 the
# reader's near edge), in order: between the table's centre and its near edge, nearer that edge,
# to either side, at the far edge. A figure drawn 0.6 m tall (touch-pose) stood on the first,
# its feet over "touch the table" (1280x720).
INVITE_AT = ((0.5, 0.2), (0.5, 0.1), (0.25, 0.2), (0.75, 0.2), (0.5, 0.85))


class InvitationPlace:
    """Which of :data:`INVITE_AT` the invitation stands at: where it stood while that stays
    clear of the characters' bodies, else the first place clear of them (the one over the
    least of them when none is): the words do not jump about as a figure breathes."""

    def __init__(self) -> None:
        self.at = 0

    def __call__(self, spots: Sequence[tuple[float, float]], line: str, px: int,
                 reading: Reading, bodies: Sequence[pygame.Rect]) -> tuple[float, float]:
        """The window pixel the invitation ``line`` (``px`` tall, read as ``reading``) is
        centred on, of ``spots`` (pixels, in :data:`INVITE_AT`'s order), kept off
        ``bodies`` (pixels)."""
        if not line:
            return spots[0]
        size = turned_line(line, px, INVITE_COLOR, reading).get_size()

        def over(i: int) -> int:
            r = reading.at(size, spots[i])
            return sum(r.clip(b).w * r.clip(b).h for b in bodies)
        if self.at >= len(spots) or over(self.at):
            self.at = min(range(len(spots)), key=lambda i: (over(i), i))
        return spots[self.at]
