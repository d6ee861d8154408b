"""The reactor's loop (paper section 4.1) compiled: the main's input resampled causally to the
generation rate (resample.CausalResampler) and every generation step now due
(engine.Reactor.advance), each the coherence search's proposal, step_kernel.step and both
searches' pushes, in one call per input sample.

Repeats its Python definitions operation for operation (the same rows to the last bit:
tests/puppet_master/test_pm_step_kernel.py). In the installation a step's own work is small
beside what it costs to reach it from Python with cold caches (the other engines and the view
run between two steps): measured interleaved as bench/puppet_master.py runs, thread CPU, the
Python around the one compiled step call was about half of a step at 3,200 training samples.

The resampler's state ``res`` (RES_SIZE): the previous and the latest input sample (t, x, y,
direction; seconds, metres, radians) and whether there is a previous one.
"""

from __future__ import annotations

import numba
import numpy as np

from behaviors.puppet_master import generation_kernel, search_kernel, step_kernel, step_math
from behaviors.puppet_master.kernels import compiled
from behaviors.puppet_master.step_kernel import LOOK, PERSONAL_SPACE, RX, RY
from behaviors.puppet_master.step_math import _max, _min, wrap_angle

PREV_T, PREV_X, PREV_Y, PREV_D, LAST_T, LAST_X, LAST_Y, LAST_D, HAS_PREV = range(9)
RES_SIZE = 9

_f8, _i8 = numba.float64, numba.int64
_F1, _F2, _I1 = numba.float64[::1], numba.float64[:, ::1], numba.int64[::1]
_F1S, _F2S = numba.float32[::1], numba.float32[:, ::1]


@compiled(numba.types.UniTuple(_f8, 3)(_F1, _f8, _f8), step_math)
def resampled_at(res: np.ndarray, g: float, max_extrapolation: float) -> tuple[float, float,
                                                                               float]:
    """resample.CausalResampler.at: the pose at grid time ``g``."""
    t1, x1, y1, d1 = res[LAST_T], res[LAST_X], res[LAST_Y], res[LAST_D]
    if res[HAS_PREV] == 0.0 or g <= t1:
        return x1, y1, d1
    t0, x0, y0, d0 = res[PREV_T], res[PREV_X], res[PREV_Y], res[PREV_D]
    h = _min(g - t1, max_extrapolation)
    f = _min(h / (t1 - t0), 1.0)
    return (x1 + (x1 - x0) * f, y1 + (y1 - y0) * f,
            wrap_angle(d1 + wrap_angle(d1 - d0) * f))


@compiled(numba.types.Tuple((_i8, _i8, _i8, _i8, _i8, _i8, _f8))(
    _F1, _I1, _F1, _F2, _F2, _F1, _F1, _F2, _F1, _F1,
    _F2, _F2, _I1, _I1, numba.boolean[::1], _F1, _F1, _F1,
    _F2S, _F1, _i8, _F2S, _F1S, _f8, _f8, _i8, _i8, _F1S, _F1S,
    _F2, _F1, _F2, _f8, _f8, _f8, _f8, _i8, _f8, _f8, _f8, _i8, _f8, _i8, _i8, _i8),
    step_math, generation_kernel, search_kernel, step_kernel)
def advance(fs: np.ndarray, ints: np.ndarray, c: np.ndarray, table: np.ndarray,
            bearings: np.ndarray, smooth_x: np.ndarray, smooth_y: np.ndarray,
            recent: np.ndarray, xs: np.ndarray, xc: np.ndarray,
            y: np.ndarray, cbuf: np.ndarray, bases: np.ndarray, ik: np.ndarray,
            valid: np.ndarray, sy: np.ndarray, sx: np.ndarray, sq: np.ndarray,
            aug: np.ndarray, sbuf: np.ndarray, n: int, queries: np.ndarray,
            norms: np.ndarray, lam: float, lam_n: float, lo: int, hi: int,
            e_new: np.ndarray, e_old: np.ndarray, obstacles: np.ndarray, res: np.ndarray,
            rows: np.ndarray, t: float, mx: float, my: float, md: float, i: int, t0: float,
            rate: float, max_extrapolation: float, js: int, cost_s: float, o: int, k: int,
            pushed: int) -> tuple[int, int, int, int, int, int, float]:
    """engine.Reactor.advance's steps for the input sample (t, mx, my, md) (finite, later than
    the latest): the steps due strictly before it (extrapolated from the earlier samples),
    the sample into ``res`` (unless ``pushed``), then the steps due at or before it; each
    step's row (g, x, y, look) into ``rows``, at most its length of them (then called again,
    with ``pushed``). The first arguments up to ``xc`` as step_kernel.step takes them, then
    the coherence search's (similarity.CoherenceSearch.kernel_state) and the situation
    search's (SituationSearch.kernel_state, with the buffer ``sbuf``; its allowed window ends
    one run ``lo`` .. ``hi - 1``, as a Behavior's are); ``i``: the steps made
    since ``t0``; ``js``, ``cost_s``: the situation search's best now; ``o``, ``k``: its
    offset and pushes. With a personal space (a constant), the last row of ``obstacles`` is
    the main's disc, moved to each step's main position. Returns (rows written, i, pushed,
    o, k, best window end, its distance) after the last step."""
    eps = 1e-9
    count = 0
    j, least = js, cost_s
    while count < rows.shape[0]:
        g = t0 + (i + 1) / rate
        if pushed == 0:
            if g >= t - eps:                         # CausalResampler.push
                res[PREV_T], res[PREV_X] = res[LAST_T], res[LAST_X]
                res[PREV_Y], res[PREV_D] = res[LAST_Y], res[LAST_D]
                res[HAS_PREV] = 1.0
                res[LAST_T], res[LAST_X], res[LAST_Y] = t, mx, my
                res[LAST_D] = wrap_angle(md)
                pushed = 1
                continue
        elif g > t + eps:
            break
        gx, gy, gd = resampled_at(res, g, max_extrapolation)
        if c[PERSONAL_SPACE] > 0.0:      # the last obstacle: the main's personal space
            last = obstacles.shape[0] - 1
            obstacles[last, 0], obstacles[last, 1] = gx, gy
        jc, cost_c = search_kernel.coherence_best(y, cbuf, bases, ik, valid, sy, sx)
        target = step_kernel.step(fs, ints, c, table, bearings, smooth_x, smooth_y, recent,
                                  obstacles, xs, xc, gx, gy, gd, js, cost_s, jc, cost_c)
        k += 1
        o, j, least = search_kernel.situation_push(aug, sbuf, o, n, queries, norms, k, xs, lam,
                                                   lam_n, lo, hi, e_new, e_old)
        search_kernel.coherence_push(cbuf, sq, bases, sx, ik, xc, target)
        js, cost_s = j, _max(least, 0.0)
        i += 1
        rows[count, 0], rows[count, 1], rows[count, 2], rows[count, 3] = g, fs[RX], fs[RY], \
            fs[LOOK]
        count += 1
    return count, i, pushed, o, k, j, least
