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

import numpy as np



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
