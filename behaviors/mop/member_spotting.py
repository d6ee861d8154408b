"""A follower group member's gesture-spotting choices, compiled.

What :func:`behaviors.mop.members.conclude` asks of each member at the end of its sample, as
:class:`~behaviors.mop.spotting.GestureSpotting` answers it for a follower stepped alone:
whether the input moved on from or departed a pending end, whether a template still shares its
start with another, whether the action driving ended short, and how its new attempt starts
(:func:`spot`). Arrays as in :mod:`behaviors.mop.members`; each function states the follower
method it equals.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from behaviors.mop import gesture_end, handover, spotting
from behaviors.mop.gesture_end import MOVE_RADII
from behaviors.mop.handover import FINISH_BACK, FINISH_CRAWLS, FINISH_FROM
from behaviors.mop.spotting import SHARE_BACK
from behaviors.kernel_cache import compiled

# the files whose constants the kernels take in
_CALLS_INTO = (gesture_end, handover, spotting)

_F1, _I1, _B1 = numba.float64[::1], numba.intp[::1], numba.boolean[::1]
# columns of a group's per-template state (group_layout.FLOATS)
_FA1, _BA1 = numba.float64[:], numba.boolean[:]

#: How a member's new attempt starts (:meth:`GestureSpotting._spot`): none; its gesture ended
#: and the input moved on or rests (anchored at the end); it rests at 90% or more while valid;
#: every template was refused too long; the input is still and waiting (anchored at its mean);
#: it moved on from where a template never valid was followed to its end
#: (:data:`~behaviors.mop.gesture_end.UNSEEN_END`).
GOES_ON, AFTER_END, RESTING, ABANDONED, WAITING, UNSEEN = range(6)


@compiled(numba.boolean(_F1, _F1, _F1, _F1), *_CALLS_INTO)
def moved_on(x: np.ndarray, end_x: np.ndarray, last: np.ndarray, still_radius: np.ndarray) -> bool:
    """:meth:`GestureSpotting._moved_on`: farther from the template's last point ``last`` (D,)
    than the end ``end_x`` was, by more than ``MOVE_RADII`` still radii in some column."""
    for c in range(x.size):
        if abs(x[c] - last[c]) > abs(end_x[c] - last[c]) + MOVE_RADII * still_radius[c]:
            return True
    return False


@compiled(numba.boolean(_F1, _F1, _F1, numba.float64, numba.float64), *_CALLS_INTO)
def departed(x: np.ndarray, end_x: np.ndarray, spread: np.ndarray, dims: float,
             limit2: float) -> bool:
    """:meth:`GestureSpotting._departed`: the mean over ``dims`` columns of
    ``((x - end_x) / spread)^2`` at least ``limit2`` (``(distance sigma)^2``)."""
    acc = 0.0
    for c in range(x.size):
        r = (x[c] - end_x[c]) / spread[c]
        acc += r * r
    return acc / dims >= limit2


@compiled(numba.intp(numba.boolean, numba.boolean, numba.float64, numba.float64, numba.boolean,
                   numba.boolean, numba.boolean, numba.float64, numba.intp, numba.intp,
                   numba.boolean, numba.boolean, numba.boolean), *_CALLS_INTO)
def spot(has_end: bool, still_: bool, step_d2: float, null2: float, ok: bool, gone: bool,
         valid: bool, progress: float, lost: int, lost_samples: int, engaged: bool,
         unseen: bool, rests_off: bool) -> int:
    """:meth:`GestureSpotting._spot`'s choice (after ``_end_x`` was set this sample): one of
    :data:`GOES_ON`, :data:`AFTER_END`, :data:`RESTING`, :data:`ABANDONED`, :data:`WAITING`,
    :data:`UNSEEN` (``unseen``: moved on from a pending end never recognised; ``rests_off``: an
    attempt begun at an end, nothing driven since, rests off its anchor, anchored again)."""
    if has_end and (still_ or step_d2 > null2 or not ok or gone):
        return AFTER_END
    if valid and still_ and progress >= 0.9:
        return RESTING
    if unseen and not has_end:
        return UNSEEN
    if lost >= lost_samples:
        return ABANDONED
    if (still_ and not engaged) or rests_off:
        return WAITING
    return GOES_ON


@compiled(numba.boolean(numba.float64, numba.float64, numba.boolean), *_CALLS_INTO)
def finished_short(peak: float, progress: float, crawls: bool) -> bool:
    """:func:`behaviors.mop.handover.finished` (its :data:`FINISH_CRAWLS` as compiled): the
    action driving, at highest progress ``peak``, ended though never reaching its end."""
    return peak >= FINISH_FROM and (peak - progress >= FINISH_BACK or (crawls and FINISH_CRAWLS))


@compiled(numba.float64(_FA1, _FA1, _BA1, numba.intp, numba.intp, numba.intp, numba.float64),
          *_CALLS_INTO)
def lead_gain(shape: np.ndarray, drift: np.ndarray, refused: np.ndarray, a0: int, a1: int, k: int,
              shape_n: float) -> float:
    """How much the last sample widened template ``k``'s shape lead (group index; its member's
    templates ``a0..a1``) over every other not refused (``shape``: the sums, ``drift``: the last
    sample's terms; 0 before the gesture's second sample or with no other). A follower alone
    calls it over its own templates (:meth:`~behaviors.mop.shape_lead.ShapeLead._lead_gain`)."""
    now, before = math.inf, math.inf
    for j in range(a0, a1):
        if j != k and not refused[j]:
            now = min(now, shape[j])
            before = min(before, shape[j] - drift[j])
    if shape_n < 2.0 or now == math.inf:
        return 0.0
    return now - shape[k] - (before - (shape[k] - drift[k]))


@compiled(numba.boolean(numba.intp, numba.intp, numba.intp, numba.intp, _I1, numba.intp, _BA1,
                      _BA1, _F1, _FA1), *_CALLS_INTO)
def shares(a0: int, a1: int, k: int, state: int, shared: np.ndarray, at: int, refused: np.ndarray,
           misshaped: np.ndarray, progress: np.ndarray, gone: np.ndarray) -> bool:
    """:meth:`GestureSpotting._shares`: whether template ``k`` (group index; its member's
    templates ``a0..a1``) at its own state ``state`` is still within its start shared with
    another of them neither refused, misshaped nor going back. ``shared``: every member's
    :func:`~behaviors.mop.sharing.shared_until` matrix flattened, this member's from ``at``."""
    n = a1 - a0
    row = at + (k - a0) * n
    for j in range(a0, a1):
        if (j != k and shared[row + j - a0] >= state and not refused[j] and not misshaped[j]
                and progress[j] >= gone[j] - SHARE_BACK):
            return True
    return False

