"""Where a frame must be repainted and presented: the rectangles drawn, marked on a grid of
tiles (compiled, numba), and the marked tiles given back as a few rectangles.

Merging overlapping rectangles into their bounding boxes (the view's earlier way) restores and
presents what lies between them too: on bench/view.py's busy 1280x720 table, this frame's and
the last frame's rectangles merged covered ~443,000 px, their 16 px tiles ~355,000 (the pixels
themselves ~334,000). Every pixel repainted is a pixel copied from the table's image and again
sent to the X server. A glow or a halo lights only the disc inside its square: marking only the
tiles of that disc (:class:`tabletop.drawing.primitives.Disc`) took the busy frame's tiles from
~348,000 to ~325,000 px (same pixels drawn: the corners are dark). Compiled once into the shared
cache (``warm``; :data:`KERNEL`); its kernels call no compiled function of another file.
"""

from __future__ import annotations

import os
from itertools import chain, starmap
from typing import Sequence

import numpy as np

os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
import pygame  # noqa: E402

from behaviors.kernel_cache import compiled  # noqa: E402
from tabletop.drawing.primitives import Disc, Parts, disc_rect  # noqa: E402

TILE = 16        # pixels per tile side
PAD = 2          # pixels added around each rectangle (anti-aliased edges may spill over)
# Presenting a rectangle to X costs a request besides its pixels: on bench/view.py's busy
# 1280x720 table, its ~32 tile rectangles (~326k px) joined where a join adds <= 2,000 px gave
# ~12 (~343k px) and the X server's time per present 0.33-0.39 -> 0.18-0.29 ms (three runs);
# joined further (<= 8,000 px: 4 rectangles, 393k px) no better, the bounding box worse.
SLACK = 2000     # px a join of two presented rectangles may add

# numba's ``njit(cache=True, nogil=True)`` (its own error model, "python"), cached in the shared
# cache under the stamp of this file (behaviors.kernel_cache.compiled): a fresh clone loads what
# another copy of the project built instead of compiling it beside this file (``make kernels``
# on a fresh clone: the view's build 13.7 -> 1.1 CPU s with those of pose, halo and outline)
KERNEL = compiled(None, error_model="python")


@KERNEL
def cover(grid: np.ndarray, rects: np.ndarray, tile: int, pad: int) -> None:
    """Mark in ``grid`` (tile rows x tile columns, uint8) every tile that a rectangle of
    ``rects`` (N x 4: x, y, width, height px) grown by ``pad`` px on every side touches."""
    rows, cols = grid.shape
    for i in range(rects.shape[0]):
        x, y = rects[i, 0] - pad, rects[i, 1] - pad
        w, h = rects[i, 2] + 2 * pad, rects[i, 3] + 2 * pad
        if w <= 2 * pad or h <= 2 * pad:
            continue
        c0, c1 = max(0, x // tile), min(cols - 1, (x + w - 1) // tile)
        r0, r1 = max(0, y // tile), min(rows - 1, (y + h - 1) // tile)
        for r in range(r0, r1 + 1):
            for c in range(c0, c1 + 1):
                grid[r, c] = 1


@KERNEL
def cover_discs(grid: np.ndarray, discs: np.ndarray, tile: int, pad: int) -> None:
    """Mark in ``grid`` every tile holding a pixel nearer than radius + ``pad`` to the centre of
    a disc of ``discs`` (N x 3: centre x, y, radius px): a glow lights only its disc."""
    rows, cols = grid.shape
    for i in range(discs.shape[0]):
        cx, cy, rr = discs[i, 0], discs[i, 1], discs[i, 2] + pad
        if discs[i, 2] <= 0:
            continue
        r0, r1 = max(0, (cy - rr) // tile), min(rows - 1, (cy + rr) // tile)
        c0, c1 = max(0, (cx - rr) // tile), min(cols - 1, (cx + rr) // tile)
        for r in range(r0, r1 + 1):
            ny = min(max(cy, r * tile), r * tile + tile - 1) - cy
            for c in range(c0, c1 + 1):
                nx = min(max(cx, c * tile), c * tile + tile - 1) - cx
                if nx * nx + ny * ny < rr * rr:
                    grid[r, c] = 1


@KERNEL
def boxes(grid: np.ndarray, tile: int, width: int, height: int, out: np.ndarray) -> int:
    """The marked tiles of ``grid`` as rectangles (x, y, width, height px, clipped to
    ``width`` x ``height``) into ``out`` (at least rows x (columns // 2 + 1) rows): each row's runs
    of marked tiles, a run joined to the rectangle above it when that ends on the row above with
    the same run. Returns how many were written; they do not overlap."""
    rows, cols = grid.shape
    n = 0
    for r in range(rows):
        y0, y1 = r * tile, min(height, (r + 1) * tile)
        c = 0
        while c < cols:
            if grid[r, c] == 0:
                c += 1
                continue
            c0 = c
            while c < cols and grid[r, c] != 0:
                c += 1
            x0, x1 = c0 * tile, min(width, c * tile)
            joined = False
            for k in range(n - 1, -1, -1):
                if out[k, 1] + out[k, 3] == y0 and out[k, 0] == x0 and out[k, 2] == x1 - x0:
                    out[k, 3] += y1 - y0
                    joined = True
                    break
            if not joined:
                out[n, 0], out[n, 1], out[n, 2], out[n, 3] = x0, y0, x1 - x0, y1 - y0
                n += 1
    return n


@KERNEL
def merge(out: np.ndarray, n: int, slack: int) -> int:
    """Join rectangles of ``out[:n]`` (x, y, width, height px, not overlapping) two by two
    into their bounding box while it adds at most ``slack`` px to theirs and meets no other;
    returns how many are left (in ``out[:k]``), still not overlapping."""
    joined = True
    while joined:
        joined = False
        for i in range(n):
            for j in range(i + 1, n):
                x0 = min(out[i, 0], out[j, 0])
                y0 = min(out[i, 1], out[j, 1])
                x1 = max(out[i, 0] + out[i, 2], out[j, 0] + out[j, 2])
                y1 = max(out[i, 1] + out[i, 3], out[j, 1] + out[j, 3])
                if (x1 - x0) * (y1 - y0) - out[i, 2] * out[i, 3] - out[j, 2] * out[j, 3] > slack:
                    continue
                free = True
                for k in range(n):
                    if k != i and k != j and out[k, 0] < x1 and x0 < out[k, 0] + out[k, 2] \
                            and out[k, 1] < y1 and y0 < out[k, 1] + out[k, 3]:
                        free = False
                        break
                if free:
                    out[i, 0], out[i, 1], out[i, 2], out[i, 3] = x0, y0, x1 - x0, y1 - y0
                    out[j:n - 1] = out[j + 1:n]
                    n -= 1
                    joined = True
                    break
            if joined:
                break
    return n


def tiles(size: tuple[int, int]) -> np.ndarray:
    """An empty grid of tiles for a ``size`` (px) target."""
    return np.zeros(((size[1] + TILE - 1) // TILE, (size[0] + TILE - 1) // TILE), dtype=np.uint8)


def mark(size: tuple[int, int], rects: Sequence[pygame.Rect | None]) -> np.ndarray:
    """The grid of tiles (see :func:`tiles`) that ``rects`` (px; None ones ignored) touch: of
    a :class:`tabletop.drawing.primitives.Disc` (a glow's square, a halo's; also as a part of a
    :class:`~tabletop.drawing.primitives.Parts`) only the tiles its disc touches."""
    grid = tiles(size)
    rs, discs = [], []
    for r in rects:
        if r is None:
            continue
        for q in (r.parts if type(r) is Parts else (r,)):
            if type(q) is not Disc:
                rs.append(q)
            elif q.w > 0 and q.h > 0:
                discs.append(q.disc)
    if rs:                  # (a Rect iterates as x, y, width, height)
        cover(grid, np.fromiter(chain.from_iterable(rs), np.int64, 4 * len(rs)).reshape(-1, 4),
              TILE, PAD)
    if discs:
        cover_discs(grid, np.array(discs, dtype=np.int64), TILE, PAD)
    return grid


def rectangles(grid: np.ndarray, size: tuple[int, int], slack: int = 0) -> list[pygame.Rect]:
    """The marked tiles of ``grid`` as non-overlapping rectangles, clipped to ``size`` (px), two
    joined into their bounding box where that adds at most ``slack`` px (see :data:`SLACK`);
    the whole target when they would cover more than half of it anyway (one copy is cheaper
    than many then)."""
    w, h = size
    marked = int(np.count_nonzero(grid))
    if marked * TILE * TILE > 0.5 * w * h:
        return [pygame.Rect(0, 0, w, h)]
    out = np.empty((grid.shape[0] * (grid.shape[1] // 2 + 1), 4), dtype=np.int64)
    n = boxes(grid, TILE, w, h, out)
    if slack > 0:
        n = merge(out, n, slack)
    return list(starmap(pygame.Rect, out[:n].tolist()))


def warm() -> None:
    """Compile (or load from the cache) the kernels."""
    rectangles(mark((64, 48), [pygame.Rect(3, 4, 20, 30), None, disc_rect(20, 20, 10)]),
               (64, 48), SLACK)
