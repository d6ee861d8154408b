"""Fitting the table and the projector, and the morning check's crosses.

- table: marker centres seen by the camera (undistorted pixels) and their known table positions
  (metres) give ``camera_to_table``;
- projector: pattern corners seen by the camera, mapped onto the table, and the projector pixels
  they were drawn at give ``table_to_projector``;
- check: a cross projected under a puck is found in the camera image by fitting a line to each of
  its two bars on the table, so bars cut by the table's edge or hidden by the puck do not bias
  where they cross.

Units: table metres (residuals reported in millimetres where named ``_mm``), pixels.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import cv2
import numpy as np

from calibration.transforms import (apply_homography, fit_homography, inverse, residuals, rms,
                                    table_grid)

MAX_TABLE_MM = 2.0       # camera -> table fits with a larger RMS residual are refused
MAX_PROJECTOR_MM = 2.0   # table -> projector fits with a larger RMS residual are refused
CHECK_MM = 2.0           # a check passes when every cross lands this close to its puck


@dataclass
class Fit:
    """A fitted homography with its residuals: ``H`` (3x3), per-point residuals (N,) in the
    target's units and in millimetres on the table."""

    H: np.ndarray
    residual: np.ndarray
    residual_mm: np.ndarray

    @property
    def rms_mm(self) -> float:
        return rms(self.residual_mm)

    @property
    def worst_mm(self) -> float:
        return float(self.residual_mm.max()) if len(self.residual_mm) else 0.0


def diagonal_centres(corners: np.ndarray) -> np.ndarray:
    """Centres (N, 2) of quadrilaterals (N, 4, 2) as the crossing of their diagonals: the exact
    image of a square's centre under any homography (undistort the corners first)."""
    q = np.asarray(corners, float).reshape(-1, 4, 2)
    p0, p1, p2, p3 = q[:, 0], q[:, 1], q[:, 2], q[:, 3]
    d1, d2 = p2 - p0, p3 - p1
    den = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]
    r = p1 - p0
    t = (r[:, 0] * d2[:, 1] - r[:, 1] * d2[:, 0]) / np.where(den == 0, 1.0, den)
    out = p0 + t[:, None] * d1
    bad = den == 0
    out[bad] = q[bad].mean(axis=1)
    return out


def fit_table(ideal_px: np.ndarray, table_m: np.ndarray) -> Fit:
    """``camera_to_table`` from undistorted marker centres (N, 2) px and their table positions
    (N, 2) m; FitError when fewer than 4 or collinear."""
    H = fit_homography(ideal_px, table_m, "markers")
    r = residuals(H, ideal_px, table_m)
    return Fit(H, r, r * 1e3)


def fit_handedness(H: np.ndarray, quads_px: np.ndarray) -> tuple[bool, bool]:
    """(folded, mirrored) of a ``camera_to_table`` fit, from the markers' corners (N, 4, 2) px
    in OpenCV's order (clockwise in the image: a detected marker is never mirrored there).
    Folded: the table's line at infinity crosses the markers (the projective scale changes
    sign among them), as when two markers' positions are swapped; four markers fit any four
    positions exactly, so the residual said 0.00 mm. Mirrored: most markers turn anticlockwise
    on the table (x right, y up seen from above: every angle would be reversed)."""
    q = np.asarray(quads_px, float).reshape(-1, 4, 2)
    p = np.concatenate([q, np.ones(q.shape[:2] + (1,))], axis=2) @ np.asarray(H, float).T
    w = p[..., 2]
    folded = bool(np.any(w > 0) and np.any(w < 0))
    xy = p[..., :2] / np.where(w == 0, 1.0, w)[..., None]
    e1, e2 = xy[:, 1] - xy[:, 0], xy[:, 3] - xy[:, 0]
    cross = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    return folded, bool(np.sum(cross > 0) > len(cross) / 2)


def on_table(table_m: np.ndarray, table: tuple[float, float], inset: float = 0.01) -> np.ndarray:
    """(N,) True for points at least ``inset`` metres inside the table's edges: light that
    falls beyond the table lands on the floor, off the table's plane."""
    p = np.asarray(table_m, float).reshape(-1, 2)
    return ((p[:, 0] >= inset) & (p[:, 0] <= table[0] - inset)
            & (p[:, 1] >= inset) & (p[:, 1] <= table[1] - inset))


def fit_projector(table_m: np.ndarray, projector_px: np.ndarray,
                  reject_mm: float = 1.5) -> tuple[Fit, np.ndarray]:
    """``table_to_projector`` from pattern corners on the table (N, 2) m and the projector
    pixels they were drawn at (N, 2); residuals in projector pixels and table millimetres.
    Corners further than max(``reject_mm``, 3 x median) from a first fit (a corner cut by the
    table's edge, a puck or a shadow) are left out of the final one. Returns the fit and the
    (N,) mask of corners used."""
    table_m = np.asarray(table_m, float).reshape(-1, 2)
    projector_px = np.asarray(projector_px, float).reshape(-1, 2)
    keep = np.ones(len(table_m), bool)
    for _ in range(3):
        H = fit_homography(table_m[keep], projector_px[keep], "pattern corners")
        back = apply_homography(inverse(H), projector_px)
        err = np.linalg.norm(back - table_m, axis=1) * 1e3
        new = err <= max(reject_mm, 3.0 * float(np.median(err[keep])))
        if np.array_equal(new, keep) or new.sum() < 4:
            break
        keep = new
    H = fit_homography(table_m[keep], projector_px[keep], "pattern corners")
    r = residuals(H, table_m[keep], projector_px[keep])
    back = apply_homography(inverse(H), projector_px[keep])
    return Fit(H, r, np.linalg.norm(back - table_m[keep], axis=1) * 1e3), keep


def stability_mm(H_a: np.ndarray, H_b: np.ndarray, table: tuple[float, float]) -> float:
    """The largest distance (mm) on the table between where two table -> projector fits put
    the same projector pixel, over the whole table, corners included."""
    grid = table_grid(table)
    px = apply_homography(H_a, grid)
    return float(np.linalg.norm(apply_homography(inverse(H_b), px) - grid, axis=1).max() * 1e3)


# --------------------------------------------------------------------------------- the check
@dataclass(frozen=True)
class Cross:
    """The check's cross on the table: bars from ``gap`` to ``arm`` metres from its centre along
    the table's x and y axes (the gap leaves the puck itself dark), ``width`` px thick."""

    gap: float = 0.05
    arm: float = 0.12
    width: int = 3


def cross_image(size: tuple[int, int], table_to_projector: np.ndarray, centres_m: np.ndarray,
                cross: Cross = Cross()) -> np.ndarray:
    """The projector image (grey, H x W) with a white cross at each table point (N, 2) m."""
    w, h = size
    img = np.zeros((h, w), np.uint8)
    for c in np.asarray(centres_m, float).reshape(-1, 2):
        for d in ((1, 0), (-1, 0), (0, 1), (0, -1)):
            ends = c + np.outer([cross.gap, cross.arm], d)
            a, b = (apply_homography(table_to_projector, ends) * 16).round().astype(int)
            cv2.line(img, tuple(map(int, a)), tuple(map(int, b)), 255, cross.width,
                     cv2.LINE_AA, 4)
    return img


def _line_fit(along: np.ndarray, across: np.ndarray, w: np.ndarray) -> tuple[float, float] | None:
    """Weighted least squares across = a + b * along; None when too little was seen."""
    if np.count_nonzero(w) < 8 or w.sum() <= 0:
        return None
    A = np.column_stack([np.ones_like(along), along]) * np.sqrt(w)[:, None]
    sol, *_ = np.linalg.lstsq(A, across * np.sqrt(w), rcond=None)
    return float(sol[0]), float(sol[1])


def locate_cross(lit: np.ndarray, dark: np.ndarray,
                 image_to_table: Callable[[np.ndarray], np.ndarray], centre_m: np.ndarray,
                 table_to_image: Callable[[np.ndarray], np.ndarray], cross: Cross = Cross(),
                 slack: float = 0.03,
                 noise: float = 6.0) -> np.ndarray | None:
    """Where (2,) m a projected cross landed near ``centre_m``: camera images with the crosses
    (``lit``) and without (``dark``), the camera's pixel -> table and table -> pixel maps. The
    brightening is mapped onto the table; each bar's pixels (within ``slack`` metres of the
    expected axis, between 0.6 x gap and arm + slack from the expected centre) fit a line; the
    lines' crossing is the answer. None when a bar is not seen."""
    c = np.asarray(centre_m, float).ravel()
    reach = cross.arm + slack
    ring = c + reach * np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], float)
    box = table_to_image(ring)
    h, w = lit.shape[:2]
    x0, y0 = np.maximum(np.floor(box.min(axis=0)).astype(int), 0)
    x1, y1 = np.minimum(np.ceil(box.max(axis=0)).astype(int) + 1, [w, h])
    if x1 - x0 < 3 or y1 - y0 < 3:
        return None
    diff = lit[y0:y1, x0:x1].astype(np.float32) - dark[y0:y1, x0:x1].astype(np.float32)
    ys, xs = np.nonzero(diff > noise)
    if len(xs) < 16:
        return None
    weight = diff[ys, xs] - noise
    t = image_to_table(np.column_stack([xs + x0, ys + y0]).astype(float)) - c
    r = np.hypot(t[:, 0], t[:, 1])
    ok = (r >= 0.6 * cross.gap) & (r <= reach)
    horizontal = ok & (np.abs(t[:, 1]) <= slack) & (np.abs(t[:, 0]) > np.abs(t[:, 1]))
    vertical = ok & (np.abs(t[:, 0]) <= slack) & (np.abs(t[:, 1]) > np.abs(t[:, 0]))
    hl = _line_fit(t[horizontal, 0], t[horizontal, 1], weight[horizontal])   # y = a + b x
    vl = _line_fit(t[vertical, 1], t[vertical, 0], weight[vertical])         # x = c + d y
    if hl is None or vl is None:
        return None
    a, b = hl
    cc, d = vl
    den = 1.0 - b * d
    if abs(den) < 1e-6:
        return None
    y = (a + b * cc) / den
    return c + np.array([cc + d * y, y])


def check_offsets_mm(pucks_m: np.ndarray, landed_m: list[np.ndarray | None]) -> np.ndarray:
    """Distance (mm) from each puck to where its cross landed (inf when not seen)."""
    out = np.full(len(pucks_m), np.inf)
    for i, (p, q) in enumerate(zip(np.asarray(pucks_m, float).reshape(-1, 2), landed_m)):
        if q is not None:
            out[i] = float(np.linalg.norm(q - p) * 1e3)
    return out
