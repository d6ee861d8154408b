"""The operator panel shown through where it lies over a character: its dark ground faded
there, its text kept at full light (:class:`SeeThrough`)."""

from __future__ import annotations

from typing import Sequence

import numpy as np
import pygame

from tabletop.drawing import raster
from tabletop.drawing.palette import PANEL


def faded_ground(img: pygame.Surface, fade: int) -> pygame.Surface:
    """A copy of a :func:`panel` whose ground's opacity (:data:`PANEL`'s) is lowered by
    ``fade`` (of 255) and its text's kept: opacities between the ground's and 255 (the
    letters' edges) are spread over the faded ground's to 255, those under the ground's
    (its rounded corners' edges) scaled down with it. Lowered alike, the text went to 105 of
    255 and read half as bright as beside the faded rectangle. Made once per panel (the
    overlay's refresh, four times a second, when it lies over a character): 0.19 ms for
    a 353x315 px panel (17 lines at 20 px), 0.35 ms at 466x417 (29 px) through a table of
    opacities (0.03-0.05 ms lowering them alike; 0.7-1.3 ms computing the map per pixel)."""
    ground, low = PANEL[3], max(PANEL[3] - fade, 0)
    table = _fades.get(low)
    if table is None:
        a = np.arange(256)
        table = _fades[low] = np.where(a >= ground, low + (a - ground) * (255 - low)
                                       // (255 - ground), a * low // ground).astype(np.uint8)
    out = img.copy()
    alpha = pygame.surfarray.pixels_alpha(out)
    np.take(table, alpha, out=alpha)
    del alpha
    return out


_fades: dict[int, np.ndarray] = {}   # faded_ground's tables, by the faded ground's opacity


class SeeThrough:
    """The panel with its opacity lowered by ``fade`` (of 255) inside ``holes`` (rectangles in
    the panel's pixels) but not inside ``solid`` ones: its dark ground
    (:data:`~tabletop.drawing.palette.PANEL`) goes nearly clear while its text keeps its light
    (:func:`faded_ground`). The panel faded whole is made once per panel; each call copies
    pixels, from it inside the holes (so overlapping ones count once) and from the panel
    elsewhere, into a surface kept between calls (made again only when the panel's size
    changes), only within the rectangles that changed; the same panel and rectangles again
    give the last result as it is. At 640x360, the operator's 13 lines over a character moving
    1 px a frame: 47 us a call, against 141 us for both panel-sized surfaces made and blended
    whole every frame, and 225 us for the kept surfaces blended within the changed rectangles
    (SDL's blends of a region cost more than copies; bench/overlay_panel.py)."""

    def __init__(self) -> None:
        self._img: pygame.Surface | None = None
        self._faded: pygame.Surface | None = None
        self._out: pygame.Surface | None = None
        self._key: tuple = ()

    def __call__(self, img: pygame.Surface, holes: Sequence[pygame.Rect],
                 solid: Sequence[pygame.Rect], fade: int) -> pygame.Surface:
        key = (fade, [tuple(r) for r in holes], [tuple(r) for r in solid])
        if img is self._img and key == self._key and self._out is not None:
            return self._out
        if img is not self._img or key[0] != self._key[0] or self._faded is None:
            self._faded = faded_ground(img, fade)
            if self._out is None or self._out.get_size() != img.get_size():
                self._out = img.copy()
            area = self._out.get_rect()
        else:
            changed = [pygame.Rect(r) for r in (*key[1], *key[2], *self._key[1], *self._key[2])]
            area = changed[0].unionall(changed[1:]) if changed else pygame.Rect(0, 0, 0, 0)
        self._img, self._key = img, key
        out, faded = self._out, self._faded
        views = [raster.pixels(s) for s in (out, img, faded)]
        if any(v is None for v in views):            # (not a plain 32-bit surface)
            self._out = out = img.copy()
            for r in holes:
                out.blit(faded, r.topleft, r, pygame.BLEND_RGBA_MIN)
            for r in solid:
                out.blit(img, r.topleft, r, pygame.BLEND_RGBA_MAX)
            return out
        dst, src, low = (v[0] for v in views)        # (indexed [x, y])
        w, h = out.get_size()
        for r, pix in ((area, src), *((r, low) for r in holes), *((r, src) for r in solid)):
            x0, y0, x1, y1 = max(r.left, 0), max(r.top, 0), min(r.right, w), min(r.bottom, h)
            if x1 > x0 and y1 > y0:
                dst[x0:x1, y0:y1] = pix[x0:x1, y0:y1]
        return out
