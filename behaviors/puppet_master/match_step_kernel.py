"""One generation step of engine.Reactor as one compiled call: BestMatch's two searches, the
step (step_kernel.step) and the new sample pair pushed into both search windows.

What engine.Reactor made four compiled calls with Python between them (coherence_best, step,
situation_push with its live gate, coherence_push: 7-19 arguments each, and the situation
search's state kept in Python), in the same order and with the same arithmetic, so the
outputs are the same to the last bit (tests/puppet_master/test_pm_step_kernel.py). The
arguments that do not change between steps are packed once per reactor start
(Reactor._compiled_state). A step of Reactor.advance (thread CPU, the five shipped
behaviours on two 60 s mains, 60 Hz samples, least of 3 runs, mean over the behaviours, two
alternated rounds on a loaded 2-core machine): 30.3 / 30.3 us with the four calls, 22.8 / 22.6
us with this one; of what is left, 31 array arguments cost 2.2 us to pass, the searches' and
the step's arithmetic about 11 us (2,400 training samples).

The situation search's state (similarity.SituationSearch): ``at`` = (offset of the distances
in ``buf``, steps pushed, best window end, lo, hi, first gated column, window), ``sf`` = (best
distance, recency weight, its n-th power). Its live gate is features.room_gate, computed here
from the pushed vector (``c[ROOM_REACH]``: the room weight's reach in feature units).
"""

from __future__ import annotations

import numba
import numpy as np

from behaviors.kernel_cache import compiled
from behaviors.puppet_master import (apart, character, darts, darts_kernel, generation_kernel,
                                     search_kernel, step_kernel, step_math, step_senses_kernel,
                                     table_boundary)
from behaviors.puppet_master.search_kernel import (coherence_best, coherence_push,
                                                   situation_push)
from behaviors.puppet_master.step_kernel import LOOK, ROOM_REACH, RX, RY, STEP_X, STEP_Y, step
from behaviors.puppet_master.step_math import _max, hypot

# SituationSearch's state (``at``, ``sf``)
AT_O, AT_K, AT_BEST, AT_LO, AT_HI, AT_G0, AT_N = range(7)
SF_BEST, SF_LAM, SF_LAM_N = range(3)

_f8, _i8 = numba.float64, numba.int64
_F1, _F2, _I1 = numba.float64[::1], numba.float64[:, ::1], numba.int64[::1]
_S1, _S2 = numba.float32[::1], numba.float32[:, ::1]


@compiled(numba.types.Tuple((_i8, _f8, _f8, _f8, _f8, _f8))(
    _F1, _I1, _F1, _F2, _F2, _F1, _F1, _F2, _F1, _F1,
    _S2, _F1, _I1, _F1, _S2, _S1, _S1, _S1, _S1,
    _F2, _F2, _F1, _I1, _F1, _I1, numba.boolean[::1], _F1,
    _F2, _f8, _f8, _f8),
    step_kernel, search_kernel, step_math, generation_kernel, table_boundary, apart,
    darts_kernel, darts, character, step_senses_kernel)
def match_step(fs: np.ndarray, ints: np.ndarray, c: np.ndarray, table: np.ndarray,
               bearings: np.ndarray, smooth_x: np.ndarray, smooth_y: np.ndarray,
               recent: np.ndarray, xs: np.ndarray, xc: np.ndarray,
               aug: np.ndarray, buf: np.ndarray, at: np.ndarray, sf: np.ndarray,
               queries: np.ndarray, norms: np.ndarray, gates: np.ndarray, e_new: np.ndarray,
               e_old: np.ndarray,
               y: np.ndarray, cbuf: np.ndarray, sq: np.ndarray, bases: np.ndarray,
               sx: np.ndarray, ik: np.ndarray, valid: np.ndarray, sy: np.ndarray,
               obstacles: np.ndarray, mx: float, my: float,
               md: float) -> tuple[int, float, float, float, float, float]:
    """One step from the main pose (mx, my, md): the situation search's best window (found
    by the last push), the coherence search's, the step (step_kernel.step: the state arrays
    ``fs`` ... ``xc`` and ``obstacles`` as it takes them), then the new situation vector ``xs``
    pushed into the situation search (``aug`` ... ``e_old``, SituationSearch's) and ``xc``
    with the target into the coherence search (``y`` ... ``sy``, CoherenceSearch's). Returns
    the target (training index) and the new pose and step: (target, x, y, look, sx, sy)."""
    jc, cost_c = coherence_best(y, cbuf, bases, ik, valid, sy, sx)
    target = step(fs, ints, c, table, bearings, smooth_x, smooth_y, recent, obstacles, xs,
                  xc, mx, my, md, at[AT_BEST], sf[SF_BEST], jc, cost_c)
    g0 = at[AT_G0]
    gate = 1.0
    if g0 < xs.size:            # features.room_gate of the new situation vector
        gate = _max(0.0, 1.0 - hypot(xs[2], xs[3]) / c[ROOM_REACH])
    k = at[AT_K] + 1
    o, j, least = situation_push(aug, buf, at[AT_O], at[AT_N], queries, norms, k, xs,
                                 sf[SF_LAM], sf[SF_LAM_N], at[AT_LO], at[AT_HI], e_new, e_old,
                                 gates, gate, g0)
    at[AT_O], at[AT_K], at[AT_BEST] = o, k, j
    sf[SF_BEST] = _max(least, 0.0)
    coherence_push(cbuf, sq, bases, sx, ik, xc, target)
    return target, fs[RX], fs[RY], fs[LOOK], fs[STEP_X], fs[STEP_Y]
