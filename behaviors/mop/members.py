"""A follower group's per-member rules over arrays of members (one row per member).

:class:`~behaviors.mop.group.FollowerGroup` steps many followers at once; the rules a single
:class:`~behaviors.mop.follower.ActionFollower` applies to itself (best template, validity,
stillness, early feedback, gesture spotting) are written here once more as pure functions over
arrays: per-template arrays ``(K,)`` of the whole group cut into members by ``bounds`` (each
member's first template), per-member arrays ``(M,)`` or ``(M, D)`` (``D`` the widest member's
features, narrower members padded with values that change nothing). Each function states the
follower method it equals; ``tests/mop/test_follower.py`` checks the group against followers
stepped alone.
"""

from __future__ import annotations

import numba
import numpy as np

from behaviors.mop.validity import PATH_REACH


def segment_argmax(values: np.ndarray, top: np.ndarray, bounds: np.ndarray, counts: np.ndarray,
                   index: np.ndarray) -> np.ndarray:
    """Per member, the index (within the group) of its first template holding its maximum
    ``top`` of ``values``, as ``np.argmax`` of the member's slice; ``index``: ``arange(K)``."""
    at = np.where(values == np.repeat(top, counts), index, index.size)
    return np.minimum.reduceat(at, bounds)


def top_three(p: np.ndarray, bounds: np.ndarray, counts: np.ndarray, index: np.ndarray
              ) -> np.ndarray:
    """Per member, its three most probable templates (group indices, likeliest first, ties in
    template order: ``np.argsort(-p, kind="stable")[:3]``) (M, 3); -1 where a member has fewer."""
    q = p.copy()
    out = np.full((bounds.size, 3), -1, dtype=np.intp)
    for j in range(3):
        top = np.maximum.reduceat(q, bounds)
        i = segment_argmax(q, top, bounds, counts, index)
        has = counts > j
        out[has, j] = i[has]
        q[i[has]] = -np.inf
    return out


def push(buf: np.ndarray, count: np.ndarray, x: np.ndarray, rows: np.ndarray, keep: np.ndarray) -> None:
    """Append ``x`` (M, D) to the recent-sample buffers ``buf`` (M, S, D) of the members ``rows``
    (bool), oldest row first, the newest last; ``count`` (M,): valid rows, at most ``keep`` (M,)."""
    buf[rows, :-1] = buf[rows, 1:]
    buf[rows, -1] = x[rows]
    count[rows] = np.minimum(count[rows] + 1, keep[rows])


def still(buf: np.ndarray, count: np.ndarray, samples: np.ndarray, radius: np.ndarray) -> np.ndarray:
    """:meth:`GestureSpotting._still` after the push: the last ``samples`` (M,) rows of each
    buffer all within ``2 radius`` (M, D) per column (False while fewer were seen)."""
    s = buf.shape[1]
    mask = (np.arange(s)[None, :] >= (s - samples)[:, None])[:, :, None]
    hi = np.where(mask, buf, -np.inf).max(axis=1)
    lo = np.where(mask, buf, np.inf).min(axis=1)
    return (count >= samples) & ((hi - lo) <= 2.0 * radius).all(axis=1)


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


def moved_on(x: np.ndarray, end_x: np.ndarray, last: np.ndarray, still_radius: np.ndarray) -> np.ndarray:
    """:meth:`GestureSpotting._moved_on`: farther from the template's last point ``last`` (M, D)
    than the end ``end_x`` was, by more than 3 still radii in some column."""
    return (np.abs(x - last) > np.abs(end_x - last) + 3.0 * still_radius).any(axis=1)


def departed(x: np.ndarray, end_x: np.ndarray, spread: np.ndarray, dims: np.ndarray,
             limit2: np.ndarray) -> np.ndarray:
    """:meth:`GestureSpotting._departed`: the mean over each member's ``dims`` columns of
    ``((x - end_x) / spread)^2`` at least ``limit2`` (``(distance sigma)^2``)."""
    r = (x - end_x) / spread
    return (r * r).sum(axis=1) / dims >= limit2


def spot(has_end: np.ndarray, still_: np.ndarray, step_d2: np.ndarray, null2: np.ndarray,
         ok: np.ndarray, gone: np.ndarray, valid: np.ndarray, progress: np.ndarray,
         lost: np.ndarray, lost_samples: np.ndarray, engaged: np.ndarray
         ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """:meth:`GestureSpotting._spot`'s choice per member (after ``_end_x`` was set this
    sample): (ended and moved on: restart anchored at the end, ended at 90% resting: restart,
    every template refused too long: restart, still and waiting: re-anchor), exclusive."""
    after_end = has_end & (still_ | (step_d2 > null2) | ~ok | gone)
    rest = ~after_end
    resting = rest & valid & still_ & (progress >= 0.9)
    rest &= ~resting
    abandon = rest & (lost >= lost_samples)
    rest &= ~abandon
    waiting = rest & still_ & ~engaged
    return after_end, resting, abandon, waiting


@numba.njit(numba.float64[:, ::1](numba.float64[:, ::1], numba.float64[:, ::1], numba.intp[::1],
                                  numba.intp[::1], numba.intp[::1], numba.intp[::1]), cache=True, nogil=True)
def nearest_on_path(z: np.ndarray, path: np.ndarray, gi: np.ndarray, starts: np.ndarray,
                    ends: np.ndarray, offset: np.ndarray) -> np.ndarray:
    """:meth:`Validity._nearest_on_path` for every template of a group: the point (K, D) of each
    template's path nearest to its sample ``z`` (K, D) among the segments starting at its states
    within :data:`~behaviors.mop.validity.PATH_REACH` of ``gi`` (its bank's index; ``starts``,
    ``ends``: its first and last state there, ``offset``: where its bank begins in ``path``).
    ``path`` (states, 2D + 1): per state its mean, its segment to the next and 1 / that
    segment's length^2, side by side (one row read per state). Compiled: as array operations
    over (K, 7, D) it cost as much as the forward step."""
    before, after = PATH_REACH
    k, d = z.shape
    out = np.empty((k, d))
    for j in range(k):
        best = np.inf
        for o in range(-before, after + 1):
            s = min(max(gi[j] + o, starts[j]), ends[j]) + offset[j]
            row = path[s]
            za = 0.0
            for i in range(d):
                za += (z[j, i] - row[i]) * row[d + i]
            t = min(max(za * row[2 * d], 0.0), 1.0)
            dd = 0.0
            for i in range(d):
                e = (z[j, i] - row[i]) - t * row[d + i]
                dd += e * e
            if dd < best:
                best = dd
                for i in range(d):
                    out[j, i] = row[i] + t * row[d + i]
    return out


def leads(shape: np.ndarray, rivals: np.ndarray, gb: np.ndarray, bounds: np.ndarray,
          margin: float) -> np.ndarray:
    """:meth:`GestureSpotting._leads`' verdict per member: its template ``gb`` (group index)
    has a ``shape`` sum below every rival's (``rivals``, not itself) by ``margin``, or has none."""
    others = np.where(rivals, shape, np.inf)
    others[gb] = np.inf
    best_rival = np.minimum.reduceat(others, bounds)
    return np.isinf(best_rival) | (best_rival - shape[gb] >= margin)
