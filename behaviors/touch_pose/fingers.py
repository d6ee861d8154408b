"""Fingers on the table for touch-pose control: each one's part and recent screen path, and the
motion several fingers on empty table make together (the camera turn)."""

from __future__ import annotations

import numpy as np


class Finger:
    """A finger on the table: the part it holds (or None), where it is (table metres) and its
    screen path since it went down, in preallocated buffers (``times`` s, ``path`` (n, 2)
    character metres: views, valid until the next change)."""

    def __init__(self, part: str | None, capacity: int = 128) -> None:
        self.part = part
        #: the part was held while an action ran (set by the engine)
        self.held_through_action = False
        self.table = np.zeros(2)
        self._t = np.empty(capacity)
        self._p = np.empty((capacity, 2))
        self._n = 0

    @property
    def times(self) -> np.ndarray:
        return self._t[: self._n]

    @property
    def path(self) -> np.ndarray:
        return self._p[: self._n]

    def add(self, t: float, screen: np.ndarray) -> None:
        """Append a path point: ``screen`` (character metres) at ``t`` (s); the buffers double
        when full."""
        if self._n == len(self._t):
            self._t = np.concatenate([self._t, np.empty_like(self._t)])
            self._p = np.concatenate([self._p, np.empty_like(self._p)])
        self._t[self._n] = t
        self._p[self._n] = screen
        self._n += 1

    def drop_first(self, k: int) -> None:
        """Forget the ``k`` oldest path points."""
        n = self._n - k
        self._t[:n] = self._t[k: self._n]
        self._p[:n] = self._p[k: self._n]
        self._n = n

    def restart(self, screen: np.ndarray | None = None) -> None:
        """Keep only the newest point (moved to ``screen`` if given): a new drag starts there."""
        if self._n:
            self.drop_first(self._n - 1)
            if screen is not None:
                self._p[0] = screen


def common_motion(moves: np.ndarray) -> np.ndarray:
    """The motion (2,; metres) every finger of ``moves`` (n, 2) makes together: per axis, the
    smallest move when all go the same way, else 0. Two fingers dragged together turn the
    camera as their mean did; a finger resting on empty table (a second visitor's, a leaning
    hand) beside one that moves turns nothing (the mean turned the view by half the move:
    30 degrees for 0.2 m)."""
    lo, hi = moves.min(axis=0), moves.max(axis=0)
    return np.where(lo > 0.0, lo, np.where(hi < 0.0, hi, 0.0))
