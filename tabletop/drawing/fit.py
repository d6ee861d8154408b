"""Points carried onto others by a rigid motion (turn and shift, least squares)."""

from __future__ import annotations

import math

import numpy as np


def rigid_onto(moving: np.ndarray, fixed: np.ndarray, ref: np.ndarray) -> np.ndarray:
    """``moving`` (N x 2) turned and shifted as a whole so that its points ``ref`` (indices;
    every point when empty) lie as near as they can on the same points of ``fixed`` (N x 2,
    same units): the least-squares rigid motion (2-D Procrustes, no scaling)."""
    a = moving[ref] if len(ref) else moving
    b = fixed[ref] if len(ref) else fixed
    ca, cb = a.mean(axis=0), b.mean(axis=0)
    da, db = a - ca, b - cb
    cos = float(np.sum(da * db))
    sin = float(np.sum(da[:, 0] * db[:, 1] - da[:, 1] * db[:, 0]))
    n = math.hypot(cos, sin)
    if not n > 1e-12:                       # one point, or nothing finite: shifted only
        return moving - ca + cb
    c, s = cos / n, sin / n
    return (moving - ca) @ np.array([[c, s], [-s, c]]) + cb
