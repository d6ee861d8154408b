"""General trajectory generation (paper section 4.4.1: generation.py) compiled for the step:
the target fitted onto the table, the step toward or around it, kept on the table and apart
from the other characters, and the look's limited turn; each function repeats its Python
definition in generation.py operation for operation (the same bits).

The table (x0, y0, x1, y1, metres) is the first four of the step's constants (``c``, see
step_kernel); ``others``: (m, 3) rows x, y, least distance (metres).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from behaviors.puppet_master import apart, step_math, table_boundary
from behaviors.puppet_master.apart import APART_PASSES, EDGE_EPS, LEAD, SLIDE_DEPTH
from behaviors.puppet_master.step_math import _max, _min, hypot, remainder, wrap_angle
from behaviors.puppet_master.table_boundary import EDGE_TURN
from behaviors.kernel_cache import compiled

# the table among the step's constants (Reactor._cs)
X0, Y0, X1, Y1 = range(4)

_f8 = numba.float64
_F1, _F2 = numba.float64[::1], numba.float64[:, ::1]
_P2 = numba.types.UniTuple(_f8, 2)


@compiled(_P2(_f8, _f8, _F1), step_math)
def clamp_to_table(x: float, y: float, c: np.ndarray) -> tuple[float, float]:
    """table_boundary.clamp_to_table (table from the constants)."""
    return _min(_max(x, c[X0]), c[X1]), _min(_max(y, c[Y0]), c[Y1])


@compiled(_P2(_f8, _f8, _f8, _f8, _f8, _f8, _F1, _F2), step_math)
def fit_target(mx: float, my: float, tx: float, ty: float, rx: float, ry: float,
               c: np.ndarray, bearings: np.ndarray) -> tuple[float, float]:
    """table_boundary.fit_target (``bearings``: table_boundary._bearings as an (m, 2) array)."""
    x0, y0, x1, y1 = c[X0], c[Y0], c[X1], c[Y1]
    if x0 <= tx <= x1 and y0 <= ty <= y1:
        return tx, ty
    rho = hypot(tx - mx, ty - my)
    found = False
    bd, bx, by = 0.0, 0.0, 0.0
    if rho > 1e-9:
        for k in range(bearings.shape[0]):
            px, py = mx + rho * bearings[k, 0], my + rho * bearings[k, 1]
            if x0 <= px <= x1 and y0 <= py <= y1:
                d = (px - rx) ** 2 + (py - ry) ** 2
                if not found or d < bd:
                    found = True
                    bd, bx, by = d, px, py
    if found:
        return bx, by
    return clamp_to_table(tx, ty, c)


@compiled(_P2(_f8, _f8, _f8), step_math)
def capped(sx: float, sy: float, cap: float) -> tuple[float, float]:
    """generation.capped."""
    length = hypot(sx, sy)
    if length > cap:
        return sx * cap / length, sy * cap / length
    return sx, sy


@compiled(numba.types.UniTuple(_f8, 3)(_f8, _f8, _F1, _F1, _f8, _f8, _f8, _f8), step_math)
def kept_straightness(sx: float, sy: float, xs: np.ndarray, ys: np.ndarray, share: float,
                      kept: float, decay: float, most: float) -> tuple[float, float, float]:
    """generation.kept_straightness."""
    n = xs.size
    total = 0.0
    for q in range(n):
        total += hypot(xs[q], ys[q])
    mean = total / n
    length = hypot(sx, sy)
    if mean <= 1e-12:
        return sx, sy, kept
    kept += decay * (length / mean - kept)
    if kept >= share or length <= 1e-12:
        return sx, sy, kept
    f = _min(share / kept, most / length)
    if f <= 1.0:
        return sx, sy, kept
    return sx * f, sy * f, kept


@compiled(_P2(_f8, _f8, _f8, _f8, _f8, numba.int64), step_math)
def mean_capped(px: float, py: float, sx: float, sy: float, cap: float,
                size: int) -> tuple[float, float]:
    """generation.mean_capped."""
    length = hypot(sx, sy)
    if length <= cap:
        return sx, sy
    f = cap / length
    most = size * cap
    cc = px * px + py * py - most * most
    if cc < 0.0 and size > 1:
        a = sx * sx + sy * sy
        b = px * sx + py * sy
        f = _max(f, _min((-b + math.sqrt(b * b - a * cc)) / a, 1.0))
    return sx * f, sy * f


@compiled(_P2(_f8, _f8, _f8, _f8), step_math)
def turn_between(ax: float, ay: float, bx: float, by: float) -> tuple[float, float]:
    """generation.turn_between."""
    la, lb = hypot(ax, ay), hypot(bx, by)
    if la < 1e-9 or lb < 1e-9:
        return 1.0, 0.0
    n = la * lb
    return (ax * bx + ay * by) / n, (ax * by - ay * bx) / n


@compiled(_P2(_f8, _f8, _f8, _f8, _f8), step_math)
def step_toward(rx: float, ry: float, tx: float, ty: float,
                length: float) -> tuple[float, float]:
    """generation.step_toward."""
    dx, dy = tx - rx, ty - ry
    dist = hypot(dx, dy)
    if dist < 1e-12:
        return 0.0, 0.0
    return dx * length / dist, dy * length / dist


@compiled(_P2(_f8, _f8, _f8, _f8, _f8, _f8, _f8), step_math)
def step_around(mx: float, my: float, rx: float, ry: float, tx: float, ty: float,
                length: float) -> tuple[float, float]:
    """generation.step_around."""
    ax, ay = rx - mx, ry - my
    bx, by = tx - mx, ty - my
    ra, rb = hypot(ax, ay), hypot(bx, by)
    if ra < 1e-6 or rb < 1e-6:
        return step_toward(rx, ry, tx, ty, _min(length, hypot(tx - rx, ty - ry)))
    a0 = math.atan2(ay, ax)
    da = remainder(math.atan2(by, bx) - a0, math.tau)
    path = hypot(rb - ra, 0.5 * (ra + rb) * da)
    if path <= length or path < 1e-12:
        return tx - rx, ty - ry
    f = length / path
    rho, ang = ra + f * (rb - ra), a0 + f * da
    return step_toward(rx, ry, mx + rho * math.cos(ang), my + rho * math.sin(ang), length)


@compiled(_P2(_f8, _f8, _f8, _f8, _f8, _f8, _f8), step_math)
def less_approach(msx: float, msy: float, bx: float, by: float, shown: float, cx: float,
                  cy: float) -> tuple[float, float]:
    """generation.less_approach."""
    r = hypot(bx, by)
    if r <= 1e-9:
        return cx, cy
    ex, ey = bx / r, by / r
    beyond = msx * ex + msy * ey - _max(shown, 0.0)
    inward = -(cx * ex + cy * ey)
    if beyond > 0.0 and inward > 0.0:
        cut = _min(inward, beyond)
        cx, cy = cx + cut * ex, cy + cut * ey
    return cx, cy


@compiled(_P2(_f8, _f8, _f8, _f8, _f8, _f8, _f8), step_math)
def share_around(mx: float, my: float, rx: float, ry: float, tx: float, ty: float,
                 share: float) -> tuple[float, float]:
    """generation.share_around."""
    cx, cy = share * (tx - rx), share * (ty - ry)
    ax, ay = rx - mx, ry - my
    bx, by = tx - mx, ty - my
    ra, rb = hypot(ax, ay), hypot(bx, by)
    if ra > 1e-6 and rb > 1e-6 and rb > ra:
        a0 = math.atan2(ay, ax)
        da = remainder(math.atan2(by, bx) - a0, math.tau)
        rho, ang = ra + share * (rb - ra), a0 + share * da
        cx, cy = mx + rho * math.cos(ang) - rx, my + rho * math.sin(ang) - ry
    return cx, cy


@compiled(_P2(_f8, _f8, _f8, _f8, _F1), step_math)
def keep_on_table(rx: float, ry: float, sx: float, sy: float,
                  c: np.ndarray) -> tuple[float, float]:
    """table_boundary.keep_on_table."""
    x0, y0, x1, y1 = c[X0], c[Y0], c[X1], c[Y1]
    length = hypot(sx, sy)
    nx, ny = rx + sx, ry + sy
    changed = False
    if nx < x0 or nx > x1:
        sx = 0.0
        changed = True
    if ny < y0 or ny > y1:
        sy = 0.0
        changed = True
    if changed:
        rest = hypot(sx, sy)
        if rest > 1e-12:
            sx, sy = sx * length / rest, sy * length / rest
    nx, ny = clamp_to_table(rx + sx, ry + sy, c)
    return nx - rx, ny - ry


@compiled(_P2(_f8, _f8, _f8, _f8, _F1, _f8), step_math, table_boundary)
def turn_off_edges(rx: float, ry: float, sx: float, sy: float, c: np.ndarray,
                   band: float) -> tuple[float, float]:
    """table_boundary.turn_off_edges (EDGE_TURN frozen when compiled)."""
    if band <= 0.0:
        return sx, sy
    length = hypot(sx, sy)
    wx = _max(0.0, 1.0 - (rx - c[X0]) / band) - _max(0.0, 1.0 - (c[X1] - rx) / band)
    wy = _max(0.0, 1.0 - (ry - c[Y0]) / band) - _max(0.0, 1.0 - (c[Y1] - ry) / band)
    if length <= 1e-12 or (wx == 0.0 and wy == 0.0):
        return sx, sy
    ux, uy = sx / length + EDGE_TURN * wx, sy / length + EDGE_TURN * wy
    n = hypot(ux, uy)
    if n <= 1e-12:
        return sx, sy
    return length * ux / n, length * uy / n


@compiled(_f8(_f8, _f8, _f8, _f8, _F1), step_math)
def table_reach(x: float, y: float, ux: float, uy: float, c: np.ndarray) -> float:
    """table_boundary.table_reach (table from the constants)."""
    reach = math.inf
    if ux > 0.0:
        reach = _min(reach, (c[X1] - x) / ux)
    elif ux < 0.0:
        reach = _min(reach, (c[X0] - x) / ux)
    if uy > 0.0:
        reach = _min(reach, (c[Y1] - y) / uy)
    elif uy < 0.0:
        reach = _min(reach, (c[Y0] - y) / uy)
    return reach


@compiled(_f8(_f8, _f8, _f8, _f8, _f8, _f8), step_math)
def _along(off: float, centre: float, at: float, lo: float, hi: float, least: float) -> float:
    """apart._along."""
    h = least * least - off * off
    if h > 0.0:
        n = centre + math.copysign(math.sqrt(h), at - centre)
        if lo <= n <= hi:
            return n
    return math.nan


@compiled(_P2(_f8, _f8, _f8, _f8, _f8, _F1), step_math, apart)
def along_edge(x: float, y: float, ox: float, oy: float, least: float,
               c: np.ndarray) -> tuple[float, float]:
    """apart.along_edge (table from the constants)."""
    if x <= c[X0] + EDGE_EPS or x >= c[X1] - EDGE_EPS:
        ny = _along(x - ox, oy, y, c[Y0], c[Y1], least)
        if ny == ny:
            return x, ny
    if y <= c[Y0] + EDGE_EPS or y >= c[Y1] - EDGE_EPS:
        nx = _along(y - oy, ox, x, c[X0], c[X1], least)
        if nx == nx:
            return nx, y
    return x, y


@compiled(_P2(_f8, _f8, _f8, _F1, _F2), step_math)
def _free_axis(x: float, y: float, least: float, c: np.ndarray,
               others: np.ndarray) -> tuple[float, float]:
    """apart._free_axis (table from the constants)."""
    bx, by, most = 1.0, 0.0, -math.inf
    rx, ry = math.nan, 0.0
    for k in range(4):
        ux = 1.0 if k == 0 else (-1.0 if k == 1 else 0.0)
        uy = 1.0 if k == 2 else (-1.0 if k == 3 else 0.0)
        reach = table_reach(x, y, ux, uy, c)
        if reach >= least:
            px, py = x + ux * least, y + uy * least
            clear = True
            for m in range(others.shape[0]):
                if hypot(px - others[m, 0], py - others[m, 1]) < others[m, 2] - 1e-9:
                    clear = False
            if clear:
                return ux, uy
            if rx != rx:
                rx, ry = ux, uy
        if reach > most:
            bx, by, most = ux, uy, reach
    if rx == rx:
        return rx, ry
    return bx, by


@compiled(_P2(_f8, _f8, _F2, _F1), step_math, apart)
def keep_apart(x: float, y: float, others: np.ndarray, c: np.ndarray) -> tuple[float, float]:
    """apart.keep_apart (``others``: (m, 3) rows x, y, least distance)."""
    for visit in range(APART_PASSES):
        moved = False
        for k in range(others.shape[0]):
            ox, oy, least = others[k, 0], others[k, 1], others[k, 2]
            dx, dy = x - ox, y - oy
            d = hypot(dx, dy)
            if d < least:
                if d < 1e-9:
                    dx, dy = _free_axis(ox, oy, least, c, others)
                    push, d = _min(least, table_reach(ox, oy, dx, dy, c)), 1.0
                else:
                    push = _max(d, _min(least, table_reach(ox, oy, dx / d, dy / d, c)))
                x, y = ox + dx * push / d, oy + dy * push / d
                if visit > 0 and push < (1.0 - SLIDE_DEPTH) * least:
                    x, y = along_edge(x, y, ox, oy, least, c)
                moved = True
        if not moved or others.shape[0] < 2:
            break
    return clamp_to_table(x, y, c)


@compiled(_P2(_f8, _f8, _f8, _f8, _F2, _F1), step_math, apart)
def no_deeper(rx: float, ry: float, x: float, y: float, others: np.ndarray,
              c: np.ndarray) -> tuple[float, float]:
    """apart.no_deeper (``others``: (m, 3) rows x, y, least distance)."""
    for visit in range(APART_PASSES):
        moved = False
        for k in range(others.shape[0]):
            ox, oy, least = others[k, 0], others[k, 1], others[k, 2]
            dx, dy = x - ox, y - oy
            d = hypot(dx, dy)
            keep = _min(least, hypot(rx - ox, ry - oy))
            if d >= keep:
                continue
            if d < 1e-9:
                x, y = rx, ry
            else:
                x, y = ox + dx * keep / d, oy + dy * keep / d
                cx, cy = clamp_to_table(x, y, c)
                if cx != x or cy != y:
                    x, y = along_edge(cx, cy, ox, oy, keep, c)
            moved = True
        if not moved or others.shape[0] < 2:
            break
    return clamp_to_table(x, y, c)


@compiled(_P2(_f8, _f8, _f8, _f8, _f8, _f8, _f8, _F1), step_math, apart)
def pressed_along_edge(x: float, y: float, mx: float, my: float, vx: float, vy: float,
                       least: float, c: np.ndarray) -> tuple[float, float]:
    """apart.pressed_along_edge (table from the constants)."""
    dx, dy = x - mx, y - my
    d = hypot(dx, dy)
    if d >= least or d < 1e-9 or dx * vx + dy * vy < 0.0:
        return x, y
    push = _max(d, _min(least, table_reach(mx, my, dx / d, dy / d, c)))
    if push >= (1.0 - SLIDE_DEPTH) * least:
        return x, y
    px, py = clamp_to_table(mx + dx * push / d, my + dy * push / d, c)
    into = 0.0
    if px <= c[X0] + EDGE_EPS:
        into = -vx
    elif px >= c[X1] - EDGE_EPS:
        into = vx
    if py <= c[Y0] + EDGE_EPS:
        into = _max(into, -vy)
    elif py >= c[Y1] - EDGE_EPS:
        into = _max(into, vy)
    if into <= 0.0:
        return x, y
    return along_edge(px, py, mx, my, least, c)


@compiled(_P2(_f8, _f8, _f8, _f8, _f8, _f8, _f8, _f8, _F1), step_math, apart)
def out_of_way(x: float, y: float, mx: float, my: float, vx: float, vy: float, least: float,
               largest: float, c: np.ndarray) -> tuple[float, float]:
    """apart.out_of_way (table from the constants)."""
    v2 = vx * vx + vy * vy
    ahead = LEAD * least / largest
    if v2 <= largest * largest or ahead <= 0.0:
        return pressed_along_edge(x, y, mx, my, vx, vy, least, c)
    ex, ey = vx * ahead, vy * ahead
    u = ((x - mx) * ex + (y - my) * ey) / (v2 * ahead * ahead)
    if u <= 0.0:
        return x, y
    u = _min(u, 1.0)
    cx, cy = mx + u * ex, my + u * ey
    dx, dy = x - cx, y - cy
    d = hypot(dx, dy)
    if d >= least:
        return x, y
    if d < 1e-9:
        dx, dy, d = -vy, vx, math.sqrt(v2)
    push = _max(d, _min(least, table_reach(cx, cy, dx / d, dy / d, c)))
    return clamp_to_table(cx + dx * push / d, cy + dy * push / d, c)


@compiled(_P2(_f8, _f8, _f8, _f8, _f8, _F2, _F1), step_math, apart)
def moved_on(x: float, y: float, sx: float, sy: float, f: float, others: np.ndarray,
             c: np.ndarray) -> tuple[float, float]:
    """engine.Reactor.update's position between two steps (and _slid's): (x, y) moved on by
    the share ``f`` of the step (sx, sy), kept on the table and apart from ``others`` (m, 3)."""
    x, y = clamp_to_table(x + sx * f, y + sy * f, c)
    if others.shape[0] > 0:
        x, y = keep_apart(x, y, others, c)
    return x, y


@compiled(_f8(_f8, _f8, _f8), step_math)
def limit_turn(previous: float, desired: float, max_delta: float) -> float:
    """generation.limit_turn."""
    d = wrap_angle(desired - previous)
    d = _min(_max(d, -max_delta), max_delta)
    return wrap_angle(previous + d)


@compiled(numba.void(_F1, _F1, _f8, _f8), step_math)
def lose_inward(xs: np.ndarray, ys: np.ndarray, bx: float, by: float) -> None:
    """generation.StepSmoother.lose_inward on the smooth's remembered steps ``xs``, ``ys``."""
    length = hypot(bx, by)
    if length <= 1e-9:
        return
    ux, uy = bx / length, by / length
    for q in range(xs.size):
        inward = xs[q] * ux + ys[q] * uy
        if inward < 0.0:
            xs[q] -= inward * ux
            ys[q] -= inward * uy
