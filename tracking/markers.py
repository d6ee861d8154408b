"""Fiducial marker detection with OpenCV's objdetect ``ArucoDetector``: grey image -> ids, corners.

ArUco and AprilTag dictionaries are both OpenCV predefined dictionaries (``DICT_4X4_50``,
``DICT_APRILTAG_36h11``, ...). Corners come back as float pixels (x right, y down) in OpenCV's
order: c0 is the marker's printed top-left corner, then clockwise as printed. A marker's pose in
the image is its centre (the intersection of its diagonals, exact under perspective) and its
heading ``atan2(c1.y - c0.y, c1.x - c0.x)`` (image y down).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import cv2
import numpy as np

from tabletop.frames import PuckMeasurement

CORNER_REFINEMENTS = {
    "none": cv2.aruco.CORNER_REFINE_NONE,
    "subpix": cv2.aruco.CORNER_REFINE_SUBPIX,
    "contour": cv2.aruco.CORNER_REFINE_CONTOUR,
    "apriltag": cv2.aruco.CORNER_REFINE_APRILTAG,
}


def dictionary_by_name(name: str) -> cv2.aruco.Dictionary:
    """OpenCV's predefined dictionary ``name``; ValueError naming the choices if unknown."""
    code = getattr(cv2.aruco, name, None) if name.startswith("DICT_") else None
    if not isinstance(code, int):
        raise ValueError(f"unknown marker dictionary {name!r} (OpenCV names such as DICT_4X4_50, "
                         f"DICT_6X6_250, DICT_APRILTAG_36h11)")
    return cv2.aruco.getPredefinedDictionary(code)


@dataclass(frozen=True)
class DetectorSettings:
    """Detector options. ``corner_refinement``: none, subpix, contour or apriltag (slow);
    ``error_correction_rate``: share of the dictionary's correction capacity used (lower admits
    fewer false ids); ``valid_bit_id_threshold``: OpenCV's ``validBitIdThreshold`` (a rate in
    0..1, default 0.49; with the correction rate it guards against false positives);
    ``threshold_window_px``: adaptive threshold window sizes (min, max, step) in pixels;
    ``min_perimeter_rate``: smallest marker perimeter as a fraction of the image's larger side;
    ``aruco3``: OpenCV's ArUco3 fast mode with ``min_length_ratio`` (smallest marker side /
    image's larger side) and ``min_canonical_side_px``."""

    dictionary: str = "DICT_4X4_50"
    corner_refinement: str = "subpix"
    error_correction_rate: float = 0.6
    valid_bit_id_threshold: float = 0.49
    threshold_window_px: tuple[int, int, int] = (3, 23, 10)
    min_perimeter_rate: float = 0.03
    subpix_window_px: int = 5
    aruco3: bool = False
    min_length_ratio: float = 0.0
    min_canonical_side_px: int = 32


def detector_parameters(s: DetectorSettings) -> cv2.aruco.DetectorParameters:
    """OpenCV ``DetectorParameters`` for ``s``."""
    p = cv2.aruco.DetectorParameters()
    if s.corner_refinement not in CORNER_REFINEMENTS:
        raise ValueError(f"DetectorSettings.corner_refinement {s.corner_refinement!r} is unknown "
                         f"(known: {', '.join(CORNER_REFINEMENTS)})")
    p.cornerRefinementMethod = CORNER_REFINEMENTS[s.corner_refinement]
    p.cornerRefinementWinSize = int(s.subpix_window_px)
    p.errorCorrectionRate = float(s.error_correction_rate)
    p.validBitIdThreshold = float(s.valid_bit_id_threshold)
    lo, hi, step = (int(v) for v in s.threshold_window_px)
    p.adaptiveThreshWinSizeMin = max(3, lo)
    p.adaptiveThreshWinSizeMax = max(p.adaptiveThreshWinSizeMin, hi)
    p.adaptiveThreshWinSizeStep = max(1, step)
    p.minMarkerPerimeterRate = float(s.min_perimeter_rate)
    if s.aruco3:
        p.useAruco3Detection = True
        p.minMarkerLengthRatioOriginalImg = float(s.min_length_ratio)
        p.minSideLengthCanonicalImg = int(s.min_canonical_side_px)
    return p


def make_detector(s: DetectorSettings) -> cv2.aruco.ArucoDetector:
    """An ``ArucoDetector`` for the settings (dictionary and parameters)."""
    return cv2.aruco.ArucoDetector(dictionary_by_name(s.dictionary), detector_parameters(s))


def detect_markers(grey: np.ndarray, detector: cv2.aruco.ArucoDetector
                   ) -> tuple[np.ndarray, np.ndarray]:
    """Detect markers in an 8-bit grey image: ids (N,) int and corners (N, 4, 2) float pixels."""
    if grey.ndim == 3:
        grey = cv2.cvtColor(grey, cv2.COLOR_BGR2GRAY)
    corners, ids, _ = detector.detectMarkers(grey)
    if ids is None or len(ids) == 0:
        return np.zeros(0, int), np.zeros((0, 4, 2))
    return (np.asarray(ids, int).reshape(-1),
            np.asarray(corners, float).reshape(-1, 4, 2))


_SUBPIX_CRITERIA = (cv2.TERM_CRITERIA_EPS + cv2.TERM_CRITERIA_COUNT, 30, 0.01)


def refine_corners(grey: np.ndarray, corners: np.ndarray, window_px: int = 5) -> np.ndarray:
    """Sub-pixel refinement (``cv2.cornerSubPix``) of corners (N, 4, 2) in ``grey``; the window
    shrinks for small markers so it never spans more than a quarter of a side."""
    if len(corners) == 0:
        return corners
    out = np.array(corners, np.float32).reshape(-1, 4, 2)
    sides = np.linalg.norm(out - np.roll(out, 1, axis=1), axis=2).min(axis=1)
    windows = np.maximum(2, np.minimum(window_px, sides / 4.0)).astype(int)
    # One cornerSubPix call per window size (usually one for the whole frame), not per marker.
    for w in np.unique(windows):
        sel = windows == w
        pts = np.ascontiguousarray(out[sel].reshape(-1, 1, 2))
        cv2.cornerSubPix(grey, pts, (int(w), int(w)), (-1, -1), _SUBPIX_CRITERIA)
        out[sel] = pts.reshape(-1, 4, 2)
    return out.astype(float)


def marker_centres(corners: np.ndarray) -> np.ndarray:
    """Centres (N, 2) of markers with corners (N, 4, 2): the intersection of the diagonals
    c0-c2 and c1-c3 (the projected centre, exact under perspective); the corner mean where the
    diagonals are degenerate."""
    c = np.asarray(corners, float).reshape(-1, 4, 2)
    p, r = c[:, 0], c[:, 2] - c[:, 0]
    q, s = c[:, 1], c[:, 3] - c[:, 1]
    denom = r[:, 0] * s[:, 1] - r[:, 1] * s[:, 0]
    qp = q - p
    ok = np.abs(denom) > 1e-9
    tpar = np.where(ok, (qp[:, 0] * s[:, 1] - qp[:, 1] * s[:, 0]) / np.where(ok, denom, 1.0), 0.5)
    centre = p + tpar[:, None] * r
    return np.where(ok[:, None], centre, c.mean(axis=1))


def marker_headings(corners: np.ndarray) -> np.ndarray:
    """Headings (N,) radians: ``atan2(c1.y - c0.y, c1.x - c0.x)`` in the corners' own frame."""
    c = np.asarray(corners, float).reshape(-1, 4, 2)
    d = c[:, 1] - c[:, 0]
    return np.arctan2(d[:, 1], d[:, 0])


def marker_poses(corners: np.ndarray) -> np.ndarray:
    """Poses (N, 3): centre x, y and heading (:func:`marker_centres`, :func:`marker_headings`)."""
    c = np.asarray(corners, float).reshape(-1, 4, 2)
    return np.column_stack([marker_centres(c), marker_headings(c)]) if len(c) else np.zeros((0, 3))


def marker_side_lengths(corners: np.ndarray) -> np.ndarray:
    """Mean side length (N,) of each marker, in the corners' units."""
    c = np.asarray(corners, float).reshape(-1, 4, 2)
    return np.linalg.norm(c - np.roll(c, 1, axis=1), axis=2).mean(axis=1)


def marker_measurements(ids: np.ndarray, corners: np.ndarray, t: float,
                        image_to_table: Callable[[np.ndarray], np.ndarray] | None = None,
                        id_map: dict[int, int] | None = None) -> tuple[PuckMeasurement, ...]:
    """Puck measurements from detected markers at time ``t`` (s).

    Without ``image_to_table`` the pose is in pixels (DESIGN.md "track" contract). With it (a
    map of (N, 2) pixels to table metres, e.g. a calibration's), the four corners are mapped
    first, so the centre is the table point under the marker's centre and the heading is the
    direction c0 -> c1 on the table (radians CCW from +x). ``id_map`` renames marker ids to puck
    ids (markers not in it keep their id).
    """
    c = np.asarray(corners, float).reshape(-1, 4, 2)
    if len(c) == 0:
        return ()
    if image_to_table is not None:
        c = np.asarray(image_to_table(c.reshape(-1, 2)), float).reshape(-1, 4, 2)
    poses = marker_poses(c)
    out = []
    for mid, (x, y, a) in zip(np.asarray(ids).reshape(-1), poses):
        pid = int(mid) if id_map is None else int(id_map.get(int(mid), int(mid)))
        out.append(PuckMeasurement(pid, float(x), float(y), float(a), float(t)))
    return tuple(out)


# --- Verification of known markers (tracking without re-detection) ---------------------------

# (id of the dictionary, marker id) -> (the dictionary, its pattern). The dictionary is kept so
# its id is never reused by another one (a freed dictionary's id can come back for a different
# dictionary, whose patterns then had the wrong size).
_PATTERNS: dict[tuple[int, int], tuple[cv2.aruco.Dictionary, np.ndarray]] = {}
_GRIDS: dict[tuple[int, float], np.ndarray] = {}
_NEXT = np.array([1, 2, 3, 0])  # corner k -> corner k + 1


def marker_pattern(dictionary: cv2.aruco.Dictionary, marker_id: int) -> np.ndarray:
    """The printed cells (S, S) bool of ``marker_id`` with its one-cell black border (True =
    white), rows top to bottom as printed; S = the dictionary's marker size + 2."""
    key = (id(dictionary), int(marker_id))
    kept = _PATTERNS.get(key)
    if kept is None:
        s = int(dictionary.markerSize) + 2
        pat = cv2.aruco.generateImageMarker(dictionary, int(marker_id), s, borderBits=1) > 127
        kept = _PATTERNS[key] = (dictionary, pat)
    return kept[1]


def _cell_grid(cells: int, spread: float) -> np.ndarray:
    """Homogeneous sample points (3, M) in the unit square, 3x3 per cell, rows of cells top to
    bottom, the points of one cell's row of samples together (M = (3 cells)^2)."""
    key = (cells, spread)
    grid = _GRIDS.get(key)
    if grid is None:
        g = (np.arange(cells)[:, None] + 0.5 + np.array([-spread, 0.0, spread])[None]).reshape(-1)
        gy, gx = np.meshgrid(g / cells, g / cells, indexing="ij")
        grid = _GRIDS[key] = np.stack([gx.ravel(), gy.ravel(), np.ones(gx.size)])
    return grid


def square_to_quad(corners: np.ndarray) -> np.ndarray:
    """Homographies (N, 3, 3) mapping the unit square (0,0), (1,0), (1,1), (0,1) onto each
    quadrilateral of ``corners`` (N, 4, 2), in closed form (Heckbert 1989)."""
    q = np.asarray(corners, float).reshape(-1, 4, 2)
    x0, x1, x2, x3 = q[:, 0, 0], q[:, 1, 0], q[:, 2, 0], q[:, 3, 0]
    y0, y1, y2, y3 = q[:, 0, 1], q[:, 1, 1], q[:, 2, 1], q[:, 3, 1]
    dx1, dx2, dx3 = x1 - x2, x3 - x2, x0 - x1 + x2 - x3
    dy1, dy2, dy3 = y1 - y2, y3 - y2, y0 - y1 + y2 - y3
    den = dx1 * dy2 - dx2 * dy1
    den = np.where(np.abs(den) > 1e-12, den, 1e-12)
    g = (dx3 * dy2 - dx2 * dy3) / den
    h = (dx1 * dy3 - dx3 * dy1) / den
    out = np.empty((len(q), 3, 3))
    out[:, 0, 0], out[:, 0, 1], out[:, 0, 2] = x1 - x0 + g * x1, x3 - x0 + h * x3, x0
    out[:, 1, 0], out[:, 1, 1], out[:, 1, 2] = y1 - y0 + g * y1, y3 - y0 + h * y3, y0
    out[:, 2, 0], out[:, 2, 1], out[:, 2, 2] = g, h, 1.0
    return out


def sample_cells(grey: np.ndarray, corners: np.ndarray, cells: int, spread: float = 0.2
                 ) -> np.ndarray:
    """Mean grey level (N, cells, cells) of each marker cell: 3x3 points per cell, ``spread``
    cells apart around its centre, mapped through the homography of the marker's corners
    (c0 printed top-left, clockwise), read bilinearly in one ``cv2.remap`` and averaged per
    cell with one area resize."""
    c = np.asarray(corners, float).reshape(-1, 4, 2)
    n = len(c)
    if n == 0:
        return np.zeros((0, cells, cells))
    img = square_to_quad(c) @ _cell_grid(cells, spread)  # (N, 3, M)
    xy = (img[:, :2] / img[:, 2:3]).astype(np.float32)
    side = 3 * cells
    mx = xy[:, 0].reshape(n * side, side)
    my = xy[:, 1].reshape(n * side, side)
    vals = cv2.remap(grey, mx, my, cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT,
                     borderValue=128)
    means = cv2.resize(vals.astype(np.float32), (cells, n * cells), interpolation=cv2.INTER_AREA)
    return means.reshape(n, cells, cells)


def verify_markers(grey: np.ndarray, ids: np.ndarray, corners: np.ndarray,
                   dictionary: cv2.aruco.Dictionary, min_contrast: float = 25.0) -> np.ndarray:
    """Whether each marker (ids (N,), corners (N, 4, 2) pixels in printed order) shows exactly
    its own code: every cell that should be white is brighter than every cell that should be
    black (border included; no bit error allowed, stricter than the detector), by a margin, and
    the white and black means differ by at least ``min_contrast`` grey levels. A covered,
    replaced, blurred-away or misplaced marker fails. Returns (N,) bool."""
    c = np.asarray(corners, float).reshape(-1, 4, 2)
    if len(c) == 0:
        return np.zeros(0, bool)
    if grey.ndim == 3:
        grey = cv2.cvtColor(grey, cv2.COLOR_BGR2GRAY)
    s = int(dictionary.markerSize) + 2
    vals = sample_cells(grey, c, s).reshape(len(c), -1)
    pats = np.stack([marker_pattern(dictionary, int(m)).reshape(-1) for m in ids])
    n_white = pats.sum(axis=1)
    mean_w = (vals * pats).sum(axis=1) / np.maximum(n_white, 1)
    mean_b = (vals * ~pats).sum(axis=1) / np.maximum(s * s - n_white, 1)
    white = np.where(pats, vals, np.inf).min(axis=1)
    black = np.where(pats, -np.inf, vals).max(axis=1)
    contrast = mean_w - mean_b
    # The dimmest white cell and the brightest black one must sit on their own side of the
    # midpoint between the two means, by a quarter of the contrast.
    mid = 0.5 * (mean_w + mean_b)
    return ((contrast >= min_contrast) & (white - mid >= 0.25 * contrast)
            & (mid - black >= 0.25 * contrast))


def track_corners(grey: np.ndarray, predicted: np.ndarray, window_px: int = 5,
                  max_shift_px: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Refine predicted corners (N, 4, 2) on ``grey`` with one batched ``cv2.cornerSubPix``:
    the refined corners and whether each marker stays a plausible quadrilateral (convex, every
    corner moved at most ``max_shift_px``, default the window, sides within 30% of predicted)."""
    p = np.asarray(predicted, float).reshape(-1, 4, 2)
    if len(p) == 0:
        return p, np.zeros(0, bool)
    if grey.ndim == 3:
        grey = cv2.cvtColor(grey, cv2.COLOR_BGR2GRAY)
    h, w = grey.shape[:2]
    ep = p[:, _NEXT] - p
    sp = np.sqrt((ep * ep).sum(axis=2))  # (N, 4) predicted sides
    win = int(max(2, min(window_px, sp.min() / 4.0)))  # one window for all: the smallest
    inside = np.all((p[..., 0] >= win + 1) & (p[..., 0] < w - win - 2)
                    & (p[..., 1] >= win + 1) & (p[..., 1] < h - win - 2), axis=1)
    r = p.copy()
    if inside.any():
        pts = np.ascontiguousarray(p[inside].reshape(-1, 1, 2), np.float32)
        cv2.cornerSubPix(grey, pts, (win, win), (-1, -1), _SUBPIX_CRITERIA)
        r[inside] = pts.reshape(-1, 4, 2)
    limit = float(win if max_shift_px is None else max_shift_px)
    d = r - p
    moved = (d * d).sum(axis=2).max(axis=1) <= limit * limit
    e = r[:, _NEXT] - r
    f = e[:, _NEXT]
    cross = e[:, :, 0] * f[:, :, 1] - e[:, :, 1] * f[:, :, 0]
    convex = np.all(cross > 0, axis=1) | np.all(cross < 0, axis=1)
    sides = np.sqrt((e * e).sum(axis=2))
    similar = np.all((sides > 0.7 * sp) & (sides < 1.3 * sp), axis=1)
    return r, inside & moved & convex & similar
