"""Every puck's halo geometry in one compiled call (numba): where each puck is on screen, its
ring's radius, width and strength, its heading notch and the rectangle it touches.

Per puck this was ~40 Python-level operations (the mapping through the homography, the state's
pulse or widening, the notch's place and colour); one call for all of them leaves the view's
Python only the cached rings to look up. Compiled once into the shared cache (``warm``;
:data:`KERNEL`); it calls no compiled function of another file.
"""

from __future__ import annotations

import math

import numpy as np

from behaviors.kernel_cache import compiled

SEEN, COASTING, LOST = 0, 1, 2     # puck state codes
FIELDS = 13                        # columns of :func:`halos`' output

# numba's ``njit(cache=True, nogil=True)`` in the shared cache (see tabletop.drawing.dirty.KERNEL)
KERNEL = compiled(None, error_model="python")


@KERNEL
def halos(v: np.ndarray, state: np.ndarray, alpha: np.ndarray, H: np.ndarray, radius_m: float,
          pulse: float, table: np.ndarray, out: np.ndarray) -> None:
    """Halo geometry of pucks at ``v`` (N x 3: table x, y metres and heading radians) in
    ``state`` (codes SEEN, COASTING, LOST) shown at opacity ``alpha``; ``H``: table metres ->
    pixels; ``radius_m``: a puck's radius (metres); ``pulse``: a coasting ring's strength factor
    now; ``table``: the table's colour (red, green, blue) a faded notch mixes with.

    ``out`` rows (N x :data:`FIELDS`): centre x, y (px), the trail's hole radius (px: the
    halo's radius), the ring's radius and width (px, in 1/64 px; a lost puck's ring widens as it
    fades), its strength, the centre rounded to whole pixels x, y, the half size of the square
    it touches besides the ring (px), the notch's centre x, y (px), radius (in 1/100 px; -1: no
    notch) and colour (0xRRGGBB).
    A puck that cannot be drawn (not finite, too far) gets half size -1."""
    for i in range(v.shape[0]):
        x, y, a = v[i, 0], v[i, 1], v[i, 2]
        out[i, 8] = -1.0
        if not (abs(x) < 1e4 and abs(y) < 1e4 and abs(a) < 1e4):   # NaN fails too
            continue
        w0 = H[2, 0] * x + H[2, 1] * y + H[2, 2]
        px = (H[0, 0] * x + H[0, 1] * y + H[0, 2]) / w0
        py = (H[1, 0] * x + H[1, 1] * y + H[1, 2]) / w0
        bx, by = x + 0.01, y
        w1 = H[2, 0] * bx + H[2, 1] * by + H[2, 2]
        ex = (H[0, 0] * bx + H[0, 1] * by + H[0, 2]) / w1 - px
        ey = (H[1, 0] * bx + H[1, 1] * by + H[1, 2]) / w1 - py
        qx, qy = x + 0.01 * math.cos(a), y + 0.01 * math.sin(a)
        w2 = H[2, 0] * qx + H[2, 1] * qy + H[2, 2]
        dx = (H[0, 0] * qx + H[0, 1] * qy + H[0, 2]) / w2 - px
        dy = (H[1, 0] * qx + H[1, 1] * qy + H[1, 2]) / w2 - py
        if not (abs(px) < 30000.0 and abs(py) < 30000.0):
            continue
        r = radius_m * math.sqrt(ex * ex + ey * ey) / 0.01
        ang = math.atan2(dy, dx)
        hole = r * 1.35 + 3.0        # the halo's radius: just outside the puck's rim
        R, al = hole, alpha[i]
        if state[i] == COASTING:     # a prediction: the ring breathes quickly
            al *= pulse
        elif state[i] == LOST:
            R *= 1.0 + 0.4 * (1.0 - al)
        out[i, 0], out[i, 1], out[i, 2] = px, py, hole
        out[i, 3] = round(R * 64.0) / 64.0
        out[i, 4] = round(max(2.0, 0.2 * r) * 64.0) / 64.0
        out[i, 5] = al
        out[i, 6], out[i, 7] = round(px), round(py)
        out[i, 8] = float(int(R + max(3.0, 0.14 * r) + 4))
        out[i, 11], out[i, 12] = -1.0, 0.0
        if state[i] != LOST:
            k = round(max(0.0, min(1.0, al)) * 128.0) / 128.0     # palette.fade's steps
            col = 0
            for c in range(3):
                col = col * 256 + int(round(table[c] + (255 - table[c]) * k))
            out[i, 9], out[i, 10] = px + math.cos(ang) * R, py + math.sin(ang) * R
            out[i, 11], out[i, 12] = round(max(2.5, 0.14 * r), 2), col


def warm() -> None:
    """Compile (or load from the cache) the kernel."""
    out = np.empty((1, FIELDS))
    halos(np.zeros((1, 3)), np.zeros(1, dtype=np.int64), np.ones(1), np.eye(3), 0.03, 1.0,
          np.zeros(3), out)
