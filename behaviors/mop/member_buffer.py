"""A follower group member's recent samples, compiled: the buffer each member keeps of its last
samples (oldest row first, the newest last) and the tests :class:`~behaviors.mop.spotting.
GestureSpotting` makes on its own list of them (still, arrived at an end, the nearest to a
point), over one member ``i`` of the group's ``(M, S, D)`` buffer at a time; called from
:func:`behaviors.mop.members.conclude` (``tests/mop/test_group.py`` checks each against the
follower's own).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from behaviors.mop import gesture_end
from behaviors.mop.gesture_end import END_GRACE
from behaviors.kernel_cache import compiled

_CALLS_INTO = (gesture_end,)   # the files whose constants the kernels take in

_F1, _F2, _F3 = numba.float64[::1], numba.float64[:, ::1], numba.float64[:, :, ::1]
_I1 = numba.intp[::1]


@compiled(numba.void(_F3, _I1, _F2, numba.intp, numba.intp), *_CALLS_INTO)
def push(buf: np.ndarray, count: np.ndarray, x: np.ndarray, i: int, keep: int) -> None:
    """Append member ``i``'s sample ``x[i]`` to its recent-sample buffer ``buf[i]`` (S, D),
    oldest row first, the newest last; ``count[i]``: valid rows, at most ``keep``."""
    s = buf.shape[1]
    for r in range(s - 1):
        buf[i, r] = buf[i, r + 1]
    buf[i, s - 1] = x[i]
    count[i] = min(count[i] + 1, keep)


@compiled(numba.boolean(_F3, _I1, numba.intp, numba.intp, _F1), *_CALLS_INTO)
def still(buf: np.ndarray, count: np.ndarray, i: int, samples: int, radius: np.ndarray) -> bool:
    """:meth:`GestureSpotting._still` after the push: member ``i``'s last ``samples`` buffered
    samples all within ``2 radius`` (D,) per column (False while fewer were seen)."""
    if count[i] < samples:
        return False
    s = buf.shape[1]
    for c in range(buf.shape[2]):
        hi = -np.inf
        lo = np.inf
        for r in range(s - samples, s):
            hi = max(hi, buf[i, r, c])
            lo = min(lo, buf[i, r, c])
        if not hi - lo <= 2.0 * radius[c]:
            return False
    return True


@compiled(numba.intp(_F3, _I1, numba.intp, _F1, numba.float64), *_CALLS_INTO)
def arrived(buf: np.ndarray, count: np.ndarray, i: int, radius: np.ndarray, reach: float) -> int:
    """:func:`behaviors.mop.gesture_end.arrived` over member ``i``'s buffered samples (the last the
    newest): how many before the last lie, with it, within ``reach radius`` (D,) per column
    (range; ``reach``: :data:`~behaviors.mop.gesture_end.ARRIVE_RADIUS`, read where the group is
    built), at most ``END_GRACE``."""
    s = buf.shape[1]
    n = 0
    while n < min(END_GRACE, count[i] - 1):
        for c in range(buf.shape[2]):
            hi = -np.inf
            lo = np.inf
            for r in range(s - n - 2, s):
                hi = max(hi, buf[i, r, c])
                lo = min(lo, buf[i, r, c])
            if not hi - lo <= reach * radius[c]:
                return n
        n += 1
    return n


@compiled(numba.void(_F3, _I1, numba.intp, _F1, _F1), *_CALLS_INTO)
def nearest(buf: np.ndarray, count: np.ndarray, i: int, point: np.ndarray,
            out: np.ndarray) -> None:
    """:func:`behaviors.mop.spotting.nearest` over member ``i``'s buffered samples (the last the
    newest) into ``out``: the one nearest ``point`` (D,), the latest among equals."""
    s = buf.shape[1]
    best, at = np.inf, s - 1
    for r in range(s - 1, s - 1 - count[i], -1):
        acc = 0.0
        for c in range(buf.shape[2]):
            acc += (buf[i, r, c] - point[c]) ** 2
        if acc < best:
            best, at = acc, r
    out[:] = buf[i, at]


def recent_mean(buf: np.ndarray, count: np.ndarray, last: np.ndarray | int,
                x: np.ndarray | None = None) -> np.ndarray:
    """The mean of each member's last ``last`` buffered samples, and of ``x`` when given (M, D),
    summed oldest first as ``np.mean`` of the list sums them."""
    s = buf.shape[1]
    n = np.minimum(count, last)
    keep = (np.arange(s)[None, :] >= (s - n)[:, None])[:, :, None]
    total = np.where(keep, buf, 0.0).sum(axis=1)
    if x is not None:
        total += x
        n = n + 1
    return total / n[:, None]


@compiled(numba.boolean(_F3, _I1, numba.intp, numba.intp, _F1, _F1, numba.float64),
          *_CALLS_INTO)
def rests_off(buf: np.ndarray, count: np.ndarray, i: int, last: int, point: np.ndarray,
              radius: np.ndarray, radii: float) -> bool:
    """Whether the mean of member ``i``'s last ``last`` buffered samples lies farther than
    ``radii`` times ``radius`` (D,) from ``point`` (D,) in some column (spotting: re-anchored at
    rest, :data:`~behaviors.mop.gesture_end.REANCHOR_RADII`)."""
    s = buf.shape[1]
    n = min(count[i], last)
    for c in range(buf.shape[2]):
        total = 0.0
        for r in range(s - n, s):
            total += buf[i, r, c]
        if abs(total / n - point[c]) > radii * radius[c]:
            return True
    return False


@compiled(numba.float64(_F3, _I1, numba.intp, _F1, numba.intp), *_CALLS_INTO)
def step_length(buf: np.ndarray, count: np.ndarray, i: int, radius: np.ndarray,
                dims: int) -> float:
    """:func:`behaviors.mop.validity.step_length` over member ``i``'s buffered samples (its
    first ``dims`` columns, ``radius`` (D,) per column): 0 before two samples."""
    if count[i] < 2:
        return 0.0
    s = buf.shape[1]
    acc = 0.0
    for c in range(dims):
        v = (buf[i, s - 1, c] - buf[i, s - 2, c]) / radius[c]
        acc += v * v
    return math.sqrt(acc)
