"""Characters' placement on screen, compiled (numba): every character's centre, scale, heading,
gaze and motion direction in one call per frame, and a figure's points mapped to pixels, grown
about its centre and bounded in one call per figure.

Each was a handful of small numpy operations or a Python loop over the pucks per character
(~1-3 us apiece); one compiled call replaces them. Compiled once into the shared cache
(``warm``; :data:`KERNEL`); its kernels call no compiled function of another file.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from behaviors.kernel_cache import compiled

FIELDS = 8     # columns of :func:`places`' output

# numba's ``njit(cache=True, nogil=True)`` in the shared cache (see tabletop.drawing.dirty.KERNEL)
KERNEL = compiled(None, error_model="python")


@numba.njit(inline="always")
def _map(H: np.ndarray, x: float, y: float) -> tuple:
    w = H[2, 0] * x + H[2, 1] * y + H[2, 2]
    return (H[0, 0] * x + H[0, 1] * y + H[0, 2]) / w, (H[1, 0] * x + H[1, 1] * y + H[1, 2]) / w


@KERNEL
def places(v: np.ndarray, H: np.ndarray, pucks: np.ndarray, look_range: float,
           out: np.ndarray) -> None:
    """Where characters stand on screen. ``v`` rows (N x 6, table metres and radians): x, y,
    heading, the x, y of what it looks at (NaN: nothing stated) and the direction of its motion
    (NaN: still); ``H``: table metres -> pixels; ``pucks``: every puck's x, y (M x 2 metres);
    a character without a stated target looks at the nearest puck nearer than ``look_range``
    metres (and farther than 1 mm).

    ``out`` rows (N x :data:`FIELDS`): centre x, y (px), pixels per metre there, the heading's
    screen angle (radians, y down), 1 when it looks at something else 0, the screen angle
    toward it, the motion's screen angle (the heading's when still), 1 when its x, y and
    heading are finite and within 10,000 (a state that can be drawn) else 0."""
    for i in range(v.shape[0]):
        x, y, a = v[i, 0], v[i, 1], v[i, 2]
        out[i, 7] = 1.0 if abs(x) < 1e4 and abs(y) < 1e4 and abs(a) < 1e4 else 0.0
        px, py = _map(H, x, y)
        bx, by = _map(H, x + 0.01, y)
        qx, qy = _map(H, x + 0.01 * math.cos(a), y + 0.01 * math.sin(a))
        angle = math.atan2(qy - py, qx - px)
        out[i, 0], out[i, 1] = px, py
        out[i, 2] = math.sqrt((bx - px) ** 2 + (by - py) ** 2) / 0.01
        out[i, 3] = angle
        tx, ty = v[i, 3], v[i, 4]
        if not (math.isfinite(tx) and math.isfinite(ty)):
            tx, ty, best = math.nan, math.nan, look_range
            for j in range(pucks.shape[0]):
                d = math.sqrt((pucks[j, 0] - x) ** 2 + (pucks[j, 1] - y) ** 2)
                if 1e-3 < d < best:
                    tx, ty, best = pucks[j, 0], pucks[j, 1], d
        out[i, 4], out[i, 5] = 0.0, 0.0
        if math.isfinite(tx):
            gx, gy = _map(H, tx, ty)
            out[i, 4], out[i, 5] = 1.0, math.atan2(gy - py, gx - px)
        m = v[i, 5]
        out[i, 6] = angle
        if math.isfinite(m):
            mx, my = _map(H, x + 0.01 * math.cos(m), y + 0.01 * math.sin(m))
            out[i, 6] = math.atan2(my - py, mx - px)


@KERNEL
def posed(H: np.ndarray, xy: np.ndarray, cx: float, cy: float, k: float) -> tuple:
    """A figure's points on screen: table points (N x 2 metres) mapped to pixels by ``H`` and
    grown by ``k`` about (cx, cy) px, with their bounds: (points N x 2 px, smallest x, y,
    largest x, y); no points (0 x 2) when one is not finite or there are none."""
    n = xy.shape[0]
    out = np.empty((n, 2))
    x0, y0, x1, y1 = math.inf, math.inf, -math.inf, -math.inf
    for i in range(n):
        x, y = _map(H, xy[i, 0], xy[i, 1])
        if not (math.isfinite(x) and math.isfinite(y)):
            return np.empty((0, 2)), math.nan, math.nan, math.nan, math.nan
        x, y = (x - cx) * k + cx, (y - cy) * k + cy
        out[i, 0], out[i, 1] = x, y
        x0, y0, x1, y1 = min(x0, x), min(y0, y), max(x1, x), max(y1, y)
    return out, x0, y0, x1, y1


def facing_px(H: np.ndarray, x: float, y: float,
              facing: tuple[float, float, float] | None) -> tuple[float, float, float]:
    """A figure's ``facing`` (CharacterState) at (x, y) table metres in pixels: its direction
    on screen (``H`` maps table metres to px), scaled to its length on the table, and its part
    toward the viewer; NaN for a figure without one (seen from above)."""
    if facing is None:
        return math.nan, math.nan, math.nan
    fx, fy, fz = facing
    h = np.asarray(H, dtype=float) @ np.array([[x, x + 1e-3 * fx], [y, y + 1e-3 * fy], [1, 1]])
    (ax, bx), (ay, by) = (h[:2] / h[2]).tolist()
    n = math.hypot(bx - ax, by - ay)
    k = math.hypot(fx, fy) / n if n > 0 else 0.0
    return (bx - ax) * k, (by - ay) * k, float(fz)


def warm() -> None:
    """Compile (or load from the cache) the kernels."""
    out = np.empty((1, FIELDS))
    places(np.zeros((1, 6)), np.eye(3), np.zeros((1, 2)), 0.5, out)
    posed(np.eye(3), np.zeros((1, 2)), 0.0, 0.0, 1.0)
    frozen = np.zeros((1, 2))
    frozen.setflags(write=False)          # characters' points are read-only: another signature
    posed(np.eye(3), frozen, 0.0, 0.0, 1.0)
