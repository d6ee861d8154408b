"""Every puck's trail in one compiled call (numba): its recent path mapped to pixels and stroked in
three age steps, thicker and brighter toward the puck, ending on the puck's halo.
"""

from __future__ import annotations

import math

import numpy as np

from tabletop.drawing.discs import mapped
from tabletop.drawing.kernel_cache import kernel
from tabletop.drawing.limbs import capsule


@kernel
def trails(pix: np.ndarray, fmt: np.ndarray, path: np.ndarray, starts: np.ndarray,
           H: np.ndarray, centers: np.ndarray, holes: np.ndarray, colors: np.ndarray,
           t2: float, t1: float, rects: np.ndarray) -> None:
    """Every puck's trail: trail ``i``'s path points (table x, y metres and time s) are
    ``path[starts[i]:starts[i + 1]]``, mapped to pixels by the homography ``H``; points within
    ``holes[i]`` px of its puck (``centers[i]``, px) are left out and the line ends on that
    circle. Three age steps, oldest (before ``t1``) to newest (from ``t2``), 1, 2 and 3 px
    thick in ``colors[i]``'s three colours, join up. ``rects[i]``: the (x0, y0, x1, y1) pixels
    it touched (x0 > x1: nothing)."""
    for i in range(len(starts) - 1):
        rects[i, 0], rects[i, 1], rects[i, 2], rects[i, 3] = 1, 1, 0, 0
        cx, cy, hole2 = centers[i, 0], centers[i, 1], holes[i] * holes[i]
        if starts[i + 1] - starts[i] < 2:
            continue
        px, py, pk = 0.0, 0.0, -1                    # the last point kept and its age step
        lx, ly, hx, hy = 1e9, 1e9, -1e9, -1e9
        for j in range(starts[i], starts[i + 1]):
            x, y, t = path[j, 0], path[j, 1], path[j, 2]
            qx, qy = mapped(H, x, y)
            dx, dy = qx - cx, qy - cy
            if dx * dx + dy * dy <= hole2:
                continue
            k = 2 if t >= t2 else 1 if t >= t1 else 0
            if pk >= 0 and (k == pk or k == pk + 1):   # a step joins up with the one before
                capsule(pix, fmt, px, py, qx, qy, 0.5 + 0.5 * k, colors[i, k])
            px, py, pk = qx, qy, k
            lx, ly, hx, hy = min(lx, qx), min(ly, qy), max(hx, qx), max(hy, qy)
        if pk < 0:
            continue
        d = math.hypot(px - cx, py - cy)
        ex, ey = cx + (px - cx) * holes[i] / d, cy + (py - cy) * holes[i] / d
        capsule(pix, fmt, px, py, ex, ey, 0.5 + 0.5 * pk, colors[i, pk])
        lx, ly, hx, hy = min(lx, ex), min(ly, ey), max(hx, ex), max(hy, ey)
        rects[i, 0], rects[i, 1] = int(math.floor(lx)) - 4, int(math.floor(ly)) - 4
        rects[i, 2], rects[i, 3] = int(math.ceil(hx)) + 4, int(math.ceil(hy)) + 4

