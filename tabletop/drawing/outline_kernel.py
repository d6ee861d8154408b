"""A hinted pose's outline added onto the view in one compiled pass (numba).

The pose is painted on a black scratch surface (:class:`tabletop.drawing.light.AddedLight`);
what is added onto the view is the pose less a share of itself eroded ``rim`` px (the least of
itself moved ``rim`` px four ways): its edges keep their light, its inside a fraction of it.
Seven pygame passes over the pose's whole rectangle did this (a white fill, four least-of
blits, a multiplying fill, a subtracting blit) and two more added it and cleared the scratch;
here one pass walks only each row's span the paint drew (its first to its last pixel, marked
by the drawing's kernels: :func:`tabletop.drawing.blend.mark`) and clears the scratch behind
it. Compiled once into the shared cache (``warm``; :data:`KERNEL`); it calls no compiled
function of another file.
"""

from __future__ import annotations

import numba
import numpy as np

from behaviors.kernel_cache import compiled

# numba's ``njit(cache=True, nogil=True)`` in the shared cache (see tabletop.drawing.dirty.KERNEL)
KERNEL = compiled(None, error_model="python")


# Each row's span is worked a byte at a time, in single floats (exact: every value is an integer
# below 2 ** 17), which the compiler vectorises: the per-pixel form (a lit pixel's three
# channels each shifted out of its word) spent ~28 ns per lit pixel. The spans hold 23 % of a
# hint's rectangle, 1.4 times its lit pixels (bench/view.py's hinted scene, 384 hints at
# 1280x720 and at 1920x1080); over the whole rectangle this form was 1.24 times slower than the
# per-pixel one, over the spans twice as fast (in place, per hint: 196 -> 98 us median).
@KERNEL
def add_outline(scratch: np.ndarray, target: np.ndarray, kept: np.ndarray, fmt: np.ndarray,
                x0: int, y0: int, x1: int, y1: int, rim: int, keep: int, keeping: bool,
                spans: np.ndarray) -> None:
    """Add ``scratch``'s light in x0..x1-1, y0..y1-1 (px) onto ``target`` (both 32-bit pixels
    as rows of bytes, rows x 4 width, of format ``fmt``: red, green, blue shifts) cut to its
    outline: each channel less ``keep``/256 of its least over its four neighbours ``rim`` px
    away (``rim`` 0: added whole), rounded as pygame's multiplying fill and saturating blits
    round. Only each row's span in ``spans`` (rows x (first, last) px, the scratch black
    beyond it) is walked; after, the scratch's red, green and blue in the rectangle are black
    and its rows' spans empty (first = width, last = -1). ``keeping``: what is added is also
    written into ``kept`` (pixels as ``target``'s, black in the rectangle before), so that
    adding it again adds the same (:class:`tabletop.drawing.light.AddedLight` keeps a hint's
    light)."""
    H, W = scratch.shape[0], scratch.shape[1] // 4
    n = x1 - x0
    if n <= 0 or y1 <= y0:
        return
    kf = np.float32(keep if rim > 0 else 0)
    gain = np.zeros(4 * n, dtype=np.float32)     # 1 for a pixel's colour bytes, 0 for its 4th
    black = np.full(4 * n, 255, dtype=np.uint8)  # what clearing keeps of each byte
    for i in range(n):
        for j in range(3):
            gain[4 * i + fmt[j] // 8] = 1.0
            black[4 * i + fmt[j] // 8] = 0
    beyond = np.full(4 * W, 255, dtype=np.uint8)  # (a neighbour beyond the surface: none)
    r4 = 4 * rim
    for y in range(y0, y1):
        a, b = max(x0, spans[y, 0]), min(x1, spans[y, 1] + 1)
        if a < b:
            row, into, out = scratch[y], target[y], kept[y]
            up = scratch[y - rim] if y - rim >= 0 else beyond
            down = scratch[y + rim] if y + rim < H else beyond
            ia, ib = max(a, rim), min(b, W - rim)     # both neighbours along the row on it
            if ia >= ib:
                ia = ib = b
            for x in range(a, ia):
                _edge(row, into, out, up, down, x, rim, W, kf, gain, x0, keeping)
            for x in range(ib, b):
                _edge(row, into, out, up, down, x, rim, W, kf, gain, x0, keeping)
            lo, hi, g = 4 * ia, 4 * ib, 4 * (ia - x0)
            _span(row[lo:hi], row[lo - r4:hi - r4], row[lo + r4:hi + r4], up[lo:hi],
                  down[lo:hi], into[lo:hi], out[lo:hi], gain[g:g + hi - lo], hi - lo, kf,
                  keeping)
        if y - rim >= y0:          # no row below needs this one's light any more
            _black(scratch[y - rim], spans, y - rim, black, x0, x1, W)
    for y in range(max(y0, y1 - rim), y1):
        _black(scratch[y], spans, y, black, x0, x1, W)


@numba.njit(inline="always")
def _span(s: np.ndarray, left: np.ndarray, right: np.ndarray, up: np.ndarray,
          down: np.ndarray, into: np.ndarray, out: np.ndarray, gain: np.ndarray, n: int,
          kf: np.float32, keeping: bool) -> None:
    """``n`` bytes of a row added (:func:`add_outline`), their neighbours all on the surface."""
    f255, inv, zero = np.float32(255.0), np.float32(1.0 / 256.0), np.float32(0.0)
    if keeping:
        for i in range(n):
            m = min(min(up[i], down[i]), min(left[i], right[i]))
            d = max(np.float32(s[i]) - np.floor((np.float32(m) * kf + f255) * inv), zero) \
                * gain[i]
            into[i] = np.uint8(min(np.float32(into[i]) + d, f255))
            out[i] |= np.uint8(d)
    else:
        for i in range(n):
            m = min(min(up[i], down[i]), min(left[i], right[i]))
            d = max(np.float32(s[i]) - np.floor((np.float32(m) * kf + f255) * inv), zero) \
                * gain[i]
            into[i] = np.uint8(min(np.float32(into[i]) + d, f255))


@numba.njit(inline="always")
def _edge(row: np.ndarray, into: np.ndarray, out: np.ndarray, up: np.ndarray,
          down: np.ndarray, x: int, rim: int, W: int, kf: np.float32, gain: np.ndarray,
          x0: int, keeping: bool) -> None:
    """Pixel ``x`` of a row added (:func:`add_outline`), a neighbour along the row beyond the
    surface (none: no less than itself)."""
    f255, inv, zero = np.float32(255.0), np.float32(1.0 / 256.0), np.float32(0.0)
    for j in range(4):
        i = 4 * x + j
        m = min(up[i], down[i])
        if x >= rim:
            m = min(m, row[i - 4 * rim])
        if x + rim < W:
            m = min(m, row[i + 4 * rim])
        d = max(np.float32(row[i]) - np.floor((np.float32(m) * kf + f255) * inv), zero) \
            * gain[4 * (x - x0) + j]
        into[i] = np.uint8(min(np.float32(into[i]) + d, f255))
        if keeping:
            out[i] |= np.uint8(d)


@numba.njit(inline="always")
def _black(row: np.ndarray, spans: np.ndarray, y: int, black: np.ndarray, x0: int, x1: int,
           W: int) -> None:
    """Row ``y``'s span (within x0..x1-1) of the scratch black again, and the span empty."""
    a, b = max(x0, spans[y, 0]), min(x1, spans[y, 1] + 1)
    if a < b:
        span, keeps = row[4 * a:4 * b], black[4 * (a - x0):4 * (b - x0)]
        for i in range(span.shape[0]):     # (from 0: no negative index to wrap, vectorised)
            span[i] &= keeps[i]
    spans[y, 0], spans[y, 1] = W, -1


def rows(pix: np.ndarray) -> np.ndarray:
    """A surface's pixels seen ``[x, y]`` (:func:`tabletop.drawing.raster.pixels`) as the
    kernel takes them: rows of bytes (rows x 4 width, the same memory)."""
    return pix.T.view(np.uint8)


def empty_spans(height: int, width: int) -> np.ndarray:
    """Spans (rows x (first, last) px) of ``height`` rows, all empty, for a surface ``width``
    px wide."""
    spans = np.empty((height, 2), dtype=np.int64)
    spans[:, 0], spans[:, 1] = width, -1
    return spans


def warm() -> None:
    """Compile (or load from the cache) the kernel for the pixels it is given: a surface's rows
    of bytes (:func:`rows` of its pixels). Warmed for other arrays than those (row-major pixels
    for column-major ones), the first hint of a run loaded a second version from the cache:
    33-58 ms in that frame (examples/mop.yaml, headless)."""
    px = np.zeros((8, 8), dtype=np.uint32).T
    px[3:5, 3:5] = 0x808080
    into = np.zeros((8, 8), dtype=np.uint32).T
    spans = empty_spans(8, 8)
    spans[3:5] = (3, 4)
    add_outline(rows(px), rows(into), rows(into), np.array([16, 8, 0, -1]), 0, 0, 8, 8, 1, 204,
                False, spans)
