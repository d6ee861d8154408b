"""Colours for a projected dark table.

A projector only adds light: dark colours vanish on the table and black is "no light". Character
colours are kept bright and moderately saturated; states of pucks use hues that stay apart.
"""

from __future__ import annotations

import colorsys
import functools
from typing import Any, TypeVar

T = TypeVar("T")

Color = tuple[int, int, int]

BACKGROUND: Color = (0, 0, 0)          # outside the table: no light at all
TABLE: Color = (14, 17, 26)            # the lit table area, a deep navy
TABLE_EDGE: Color = (30, 36, 52)
GRID: Color = (22, 27, 39)
INK: Color = (20, 18, 28)              # eyes' pupils, mouths: dark marks on a light body
EYE_WHITE: Color = (250, 250, 246)
TEXT: Color = (225, 230, 240)
PANEL: tuple[int, int, int, int] = (6, 8, 14, 190)

PUCK_SEEN: Color = (150, 225, 255)     # a calm cold white-cyan
PUCK_COASTING: Color = (255, 186, 70)  # amber: a prediction while the marker is hidden
PUCK_LOST: Color = (255, 86, 96)       # red, fading: the puck has left
PUCK_OFF: Color = (200, 140, 255)      # violet: a seen puck beyond the table's edge
PUCK_STATES: dict[str, Color] = {"seen": PUCK_SEEN, "coasting": PUCK_COASTING, "lost": PUCK_LOST}

# A puck id's colour (its label beside the ring): Okabe and Ito's palette, its black made white
# and its blue lifted 12% to white to read on the dark table (contrast >= 4.5 to TABLE); any two
# of the eight stay >= 16 apart (CIELAB) as a deuteranope or protanope sees them (red and green,
# ids 1 and 2 before, were 13 apart to a deuteranope, blue and violet 0.5).
PUCK_COLORS = [(235, 235, 235), (230, 159, 0), (86, 180, 233), (0, 158, 115), (240, 228, 66),
               (31, 131, 187), (213, 94, 0), (204, 121, 167)]


@functools.lru_cache(maxsize=256)
def vivid(color: Color, min_value: float = 0.86, min_sat: float = 0.35,
          max_sat: float = 0.8) -> Color:
    """``color`` lifted to read when projected on a dark table: value at least ``min_value``,
    saturation within [min_sat, max_sat] (a grey stays grey)."""
    r, g, b = (max(0, min(255, int(v))) / 255.0 for v in color)
    h, s, v = colorsys.rgb_to_hsv(r, g, b)
    if s > 0.05:
        s = min(max(s, min_sat), max_sat)
    v = max(v, min_value)
    return tuple(int(round(255 * c)) for c in colorsys.hsv_to_rgb(h, s, v))  # type: ignore


@functools.lru_cache(maxsize=256)
def resting(color: Color) -> Color:
    """A character with nothing to show: calmer (less saturated, 75 % light), never faded out."""
    r, g, b = (v / 255.0 for v in color)
    h, s, v = colorsys.rgb_to_hsv(r, g, b)
    rgb = colorsys.hsv_to_rgb(h, s * 0.6, v * 0.8)
    return tuple(int(round(255 * c)) for c in rgb)  # type: ignore


def shade(color: Color, k: float) -> Color:
    """``color`` times ``k`` (0 = black; > 1 lightens, clipped; remembered: a figure's few
    shades recur every frame)."""
    return _shade(tuple(color), k)


@functools.lru_cache(maxsize=1024)
def _shade(color: Color, k: float) -> Color:
    return tuple(max(0, min(255, int(round(c * k)))) for c in color)  # type: ignore


def mix(a: Color, b: Color, w: float) -> Color:
    """(1 - w) a + w b (remembered)."""
    return _mix(tuple(a), tuple(b), w)


@functools.lru_cache(maxsize=1024)
def _mix(a: Color, b: Color, w: float) -> Color:
    return tuple(int(round(x + (y - x) * w)) for x, y in zip(a, b))  # type: ignore


def lighten(color: Color, w: float) -> Color:
    """``color`` moved ``w`` of the way to white."""
    return mix(color, (255, 255, 255), w)


def remember(cache: dict[Any, T], key: Any, value: T, limit: int) -> T:
    """Keep ``value`` under ``key`` in ``cache`` and return it; a cache holding ``limit``
    entries forgets its oldest first (not all of them: a cleared cache would make every colour,
    light or shape of the next frames again at once)."""
    while len(cache) >= limit:
        del cache[next(iter(cache))]
    cache[key] = value
    return value


_faded: dict[tuple, Color] = {}


def level(alpha: float) -> int:
    """An opacity (0..1) in the 1/128 steps colours are faded in (:func:`fade`)."""
    return int(round(max(0.0, min(1.0, alpha)) * 128))


def fade(color: Color, alpha: float, ground: Color = TABLE) -> Color:
    """The colour seen when ``color`` is shown at opacity ``alpha`` over ``ground`` (alpha in
    1/128 steps: the same few colours recur frame after frame and are remembered)."""
    key = (color, alpha, ground)
    try:
        return _faded[key]
    except KeyError:
        pass
    except TypeError:         # a colour given as a list
        return _fade(tuple(color), level(alpha), tuple(ground))
    return remember(_faded, key, _fade(tuple(color), level(alpha), tuple(ground)), 4096)


@functools.lru_cache(maxsize=4096)
def _fade(color: Color, alpha128: int, ground: Color) -> Color:
    return mix(ground, color, alpha128 / 128.0)


def rgb(color: Color) -> int:
    """A colour packed as 0xRRGGBB, as the compiled drawing takes it."""
    return (int(color[0]) << 16) | (int(color[1]) << 8) | int(color[2])
