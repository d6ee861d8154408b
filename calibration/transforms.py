"""Every conversion between camera pixels, table metres and projector pixels.

Three frames (DESIGN.md, "Units and frames of reference"):

- camera pixels: x right, y down, as the lens delivers them (distorted);
- ideal camera pixels: the same camera matrix without lens distortion (``undistort_pixels``);
- table metres: origin at table corner 0, x along the long edge, y along the short edge;
- projector pixels: x right, y down.

Pixel coordinates follow OpenCV's convention throughout: the centre of pixel (i, j) is at (i, j),
so an image's outer edge lies at -0.5 and W - 0.5. Everything here is a pure function of numpy
arrays of points shaped (N, 2); nothing else in the project converts units.
"""

from __future__ import annotations

import numpy as np

MIN_POINTS = 4


class FitError(ValueError):
    """Points that cannot determine a homography (too few, or collinear)."""


def apply_homography(H: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Map points (N, 2) through the 3x3 homography ``H``; returns (N, 2) floats."""
    p = np.asarray(points, dtype=float).reshape(-1, 2)
    out = np.empty_like(p)
    out[:, 0], out[:, 1] = homography_columns(np.asarray(H, float), p[:, 0], p[:, 1])
    return out


def homography_columns(H: np.ndarray, x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, ...]:
    """The points (``x``, ``y``: float64 (N,) each) mapped through the 3x3 homography ``H``: the
    mapped x and y (N,). Component by component: a (N, 2) @ (2, 3) product takes a slow path
    for large N; and on contiguous columns no (N, 2) copy is made (a lens view's 1.2 M samples)."""
    w = H[2, 0] * x
    w += H[2, 1] * y
    w += H[2, 2]
    out = []
    for row in (0, 1):
        m = H[row, 0] * x
        m += H[row, 1] * y
        m += H[row, 2]
        m /= w
        out.append(m)
    return out[0], out[1]


def normalised(H: np.ndarray) -> np.ndarray:
    """``H`` scaled so that H[2, 2] == 1 (when it is not zero)."""
    H = np.asarray(H, dtype=float)
    return H / H[2, 2] if H[2, 2] != 0 else H


def inverse(H: np.ndarray) -> np.ndarray:
    """The inverse homography, normalised."""
    return normalised(np.linalg.inv(np.asarray(H, float)))


def undistort_pixels(points_px: np.ndarray, K: np.ndarray | None,
                     distortion: np.ndarray | None) -> np.ndarray:
    """Camera pixels (N, 2) -> ideal pinhole pixels of the same camera matrix ``K`` (N, 2)."""
    p = np.asarray(points_px, dtype=float).reshape(-1, 2)
    if K is None or distortion is None or not np.any(np.asarray(distortion) != 0) or not len(p):
        return p.copy()
    import cv2
    out = cv2.undistortPoints(p.reshape(-1, 1, 2), np.asarray(K, float),
                              np.asarray(distortion, float), P=np.asarray(K, float))
    return out.reshape(-1, 2).astype(float)


def distort_pixels(ideal_px: np.ndarray, K: np.ndarray | None,
                   distortion: np.ndarray | None) -> np.ndarray:
    """Ideal pinhole pixels (N, 2) -> camera pixels (N, 2), bent as the lens bends them."""
    p = np.asarray(ideal_px, dtype=float).reshape(-1, 2)
    if K is None or distortion is None or not np.any(np.asarray(distortion) != 0) or not len(p):
        return p.copy()
    import cv2
    K = np.asarray(K, float)
    norm = (p - K[:2, 2]) @ np.linalg.inv(K[:2, :2]).T
    obj = np.column_stack([norm, np.ones(len(norm))])
    img, _ = cv2.projectPoints(obj, np.zeros(3), np.zeros(3), K, np.asarray(distortion, float))
    return img.reshape(-1, 2)


def collinearity(points: np.ndarray) -> float:
    """How far points (N, 2) are from lying on one line: the smaller singular value of their
    centred coordinates over the larger (0 = on a line, 1 = spread evenly in both directions)."""
    p = np.asarray(points, float).reshape(-1, 2)
    if len(p) < 3:
        return 0.0
    s = np.linalg.svd(p - p.mean(axis=0), compute_uv=False)
    return float(s[1] / s[0]) if s[0] > 0 else 0.0


def fit_homography(src: np.ndarray, dst: np.ndarray, what: str = "points") -> np.ndarray:
    """Least-squares homography (3x3, normalised) mapping ``src`` (N, 2) onto ``dst`` (N, 2).

    FitError when there are fewer than 4 pairs or either set lies (nearly) on one line."""
    import cv2
    src = np.asarray(src, float).reshape(-1, 2)
    dst = np.asarray(dst, float).reshape(-1, 2)
    if len(src) < MIN_POINTS or len(src) != len(dst):
        raise FitError(f"{len(src)} {what}: at least {MIN_POINTS} are needed")
    if min(collinearity(src), collinearity(dst)) < 0.02:
        raise FitError(f"the {len(src)} {what} lie on one line: they must span the table "
                       "in both directions")
    H, _ = cv2.findHomography(src, dst, 0)
    if H is None or not np.all(np.isfinite(H)):
        raise FitError(f"no homography fits these {len(src)} {what}")
    return normalised(H)


def residuals(H: np.ndarray, src: np.ndarray, dst: np.ndarray) -> np.ndarray:
    """Distances (N,) between ``H`` applied to ``src`` and ``dst``, in ``dst``'s units."""
    return np.linalg.norm(apply_homography(H, src) - np.asarray(dst, float).reshape(-1, 2), axis=1)


def rms(values: np.ndarray) -> float:
    """Root mean square of ``values`` (0 for none)."""
    v = np.asarray(values, float).ravel()
    return float(np.sqrt(np.mean(v * v))) if len(v) else 0.0


def fitted_rectangle(table: tuple[float, float], size: tuple[int, int],
                     margin: int) -> np.ndarray:
    """Table metres -> window pixels when nothing is calibrated: the table fitted into the window
    with ``margin`` pixels around it, x to the right and y up (the table seen from above)."""
    w, h = table
    s = min((size[0] - 2 * margin) / w, (size[1] - 2 * margin) / h)
    ox = (size[0] - s * w) / 2
    oy = (size[1] - s * h) / 2
    return np.array([[s, 0.0, ox], [0.0, -s, oy + s * h], [0.0, 0.0, 1.0]])


def table_grid(table: tuple[float, float], nx: int = 9, ny: int = 7) -> np.ndarray:
    """Points (nx * ny, 2) in table metres covering the whole table, corners included."""
    xs, ys = np.meshgrid(np.linspace(0.0, table[0], nx), np.linspace(0.0, table[1], ny))
    return np.column_stack([xs.ravel(), ys.ravel()])
