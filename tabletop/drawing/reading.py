"""Words that read upright on the table for a person at its front edge (table y = 0, +x to
their right, +y away from them), whatever the projector's calibration does to the window: a
rear-projection calibration mirrors it, a projector hung upside down turns it half round, one
hung across the table turns it a quarter round either way (the table's x axis going up or down
the window). Every word the view draws is rendered upright in window pixels, turned by
:meth:`Reading.turn` and placed by :meth:`Reading.at`, so its reading directions follow the
table's, not the window's."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import pygame

Axis = tuple[int, int]       # a window direction along one of its axes: (1, 0), (0, -1), ...

# the eight ways a window can hold the table: the reader's right, then the reader's up
# (away from them), the plain window first (chosen on an exact tie, a 45-degree table)
_ORIENTATIONS: list[tuple[Axis, Axis]] = [
    (r, (s * r[1], -s * r[0])) for r in ((1, 0), (0, -1), (-1, 0), (0, 1)) for s in (1, -1)]


@dataclass(frozen=True)
class Reading:
    """How the table's reading directions lie in the window: ``right`` is the window
    direction of the reader's right (table +x), ``up`` that of the reader's up, away from them
    (table +y); each a unit step along a window axis (pixels, y down)."""

    right: Axis = (1, 0)
    up: Axis = (0, -1)

    @classmethod
    def of(cls, point: Callable[[float, float], tuple[float, float]], x: float, y: float,
           step: float = 0.01) -> "Reading":
        """The reading at table point (``x``, ``y``) (metres) of the map ``point`` (table
        metres -> window pixels): of the eight orientations, the one whose right and up lie
        nearest the window directions of table +x and +y there (a keystoned or slightly turned
        projector reads as its nearest; a quarter turn as a quarter turn)."""
        x0, y0 = point(x, y)
        x1, y1 = point(x + step, y)
        x2, y2 = point(x, y + step)
        ex, ey = (x1 - x0, y1 - y0), (x2 - x0, y2 - y0)
        nx, ny = math.hypot(*ex) or 1.0, math.hypot(*ey) or 1.0

        def score(o: tuple[Axis, Axis]) -> float:
            (rx, ry), (ux, uy) = o
            return (rx * ex[0] + ry * ex[1]) / nx + (ux * ey[0] + uy * ey[1]) / ny
        best = max(_ORIENTATIONS, key=score)   # (max keeps the first of equals)
        return cls(*best)

    @property
    def plain(self) -> bool:
        """True when words drawn upright in the window already read upright on the table."""
        return self.right == (1, 0) and self.up == (0, -1)

    @property
    def mirrored(self) -> bool:
        """True when the table sees the window mirrored (a rear projection, or a turn and a
        mirror): a picture drawn as it is reads the wrong way round there."""
        (rx, ry), (ux, uy) = self.right, self.up
        return rx * uy - ry * ux > 0

    @property
    def quarter(self) -> bool:
        """True when a line of words runs along the window's y axis (a quarter turn)."""
        return self.right[0] == 0

    def turn(self, img: pygame.Surface) -> pygame.Surface:
        """``img`` (words rendered upright in window pixels) turned and flipped to read upright
        on the table: exact pixel moves (flips and quarter turns), no resampling; ``img``
        itself when the window is plain."""
        if self.plain:
            return img
        (rx, ry), (ux, uy) = self.right, self.up
        if not self.quarter:
            return pygame.transform.flip(img, rx < 0, uy > 0)
        # turned a quarter counter-clockwise (text right -> window up, text down -> window
        # right), then flipped where the reading's axes point the other way
        return pygame.transform.flip(pygame.transform.rotate(img, 90), ux > 0, ry > 0)

    def size(self, size: tuple[int, int]) -> tuple[int, int]:
        """The window size (pixels) of words ``size`` pixels large upright, once turned."""
        return (size[1], size[0]) if self.quarter else (size[0], size[1])

    def at(self, size: tuple[int, int], pos: tuple[float, float],
           anchor: tuple[float, float] = (0.5, 0.5)) -> pygame.Rect:
        """Where words turned by :meth:`turn` (``size``: their window size, pixels) stand so
        that their point ``anchor`` (fractions of the upright words: from the reader's left,
        from the reader's top) lies on window pixel ``pos``. A flipped axis mirrors about that
        pixel, so words placed at mirrored anchors on a mirrored window cover the mirrored
        pixels exactly."""
        ax, ay = anchor
        (rx, ry), (ux, uy) = self.right, self.up
        # each window axis takes the upright fraction of the words' right or down (-up), the
        # one along it, with its sign (worked out inline: this places every puck's id each
        # frame, and a general search over the two was 2 % of a busy frame's time)
        if rx:
            sx, fx, sy, fy = rx, ax, -uy, ay
        else:
            sx, fx, sy, fy = -ux, ay, ry, ax
        w, h = size
        n = math.floor(fx * w)
        left = math.floor(pos[0]) - (n if sx > 0 else w - 1 - n)
        n = math.floor(fy * h)
        top = math.floor(pos[1]) - (n if sy > 0 else h - 1 - n)
        return pygame.Rect(left, top, w, h)

    def offset(self, pos: tuple[float, float], right: float = 0.0,
               up: float = 0.0) -> tuple[float, float]:
        """``pos`` (window pixels) moved ``right`` pixels to the reader's right and ``up``
        pixels away from the reader."""
        return (pos[0] + right * self.right[0] + up * self.up[0],
                pos[1] + right * self.right[1] + up * self.up[1])

    def reach(self, window: tuple[int, int], pos: tuple[float, float], d: Axis) -> float:
        """Pixels from ``pos`` to the edge of a ``window`` (W, H) going along ``d``."""
        k = 0 if d[0] else 1
        return window[k] - pos[k] if d[k] > 0 else pos[k]


PLAIN = Reading()
