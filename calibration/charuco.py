"""ChArUco boards: the printed board for the lens, the projected pattern, detection and the lens
solve.

OpenCV >= 4.7 API: ``cv2.aruco.CharucoBoard((cols, rows), square, marker, dictionary)`` with the
current (not legacy) pattern, ``CharucoDetector(board).detectBoard(image)``,
``board.matchImagePoints(corners, ids)`` and ``cv2.calibrateCamera``. Board coordinates are
metres on the board; image coordinates are pixels (OpenCV's pixel-centre convention).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import cv2
import numpy as np

from tabletop.frames import InputError

DEFAULT_BOARD = "7x5:40:30:DICT_5X5_100"
MIN_CORNERS = 8          # a view with fewer detected corners is skipped
MIN_VIEWS = 4            # fewer usable views are refused, even with --force
MAX_BOARD_PX = 32767     # a board image's longest side: 2.7 m at 300 dpi; a typo's 10x dpi
                         # would otherwise allocate gigabytes (or fail and be called coarse)
MAX_RMS_PX = 1.0         # a lens solve with a larger RMS error is refused unless --force
PATTERN_DICTIONARY = "DICT_5X5_250"  # the projected pattern: never a puck's 4x4 dictionary


class CalibrationInputError(InputError):
    """A calibration input that cannot be used (bad argument, image or data); one line."""


@dataclass(frozen=True)
class BoardSpec:
    """A ChArUco board: squares across (``cols``) and down (``rows``), square and marker sides
    in metres, and the OpenCV dictionary name of its markers."""

    cols: int
    rows: int
    square_m: float
    marker_m: float
    dictionary: str

    def text(self) -> str:
        """The spec as ``COLSxROWS:SQUARE_MM:MARKER_MM:DICTIONARY``."""
        return (f"{self.cols}x{self.rows}:{self.square_m * 1e3:g}:{self.marker_m * 1e3:g}:"
                f"{self.dictionary}")


def parse_board(text: str) -> BoardSpec:
    """``COLSxROWS:SQUARE_MM:MARKER_MM:DICTIONARY`` -> BoardSpec; CalibrationInputError if bad."""
    usage = "expected COLSxROWS:SQUARE_MM:MARKER_MM:DICTIONARY, e.g. " + DEFAULT_BOARD
    parts = text.split(":")
    if len(parts) != 4:
        raise CalibrationInputError(f"--board {text!r}: {usage}")
    grid, square, marker, dictionary = parts
    try:
        cols, rows = (int(v) for v in grid.lower().split("x"))
        square_mm, marker_mm = float(square), float(marker)
    except ValueError:
        raise CalibrationInputError(f"--board {text!r}: {usage}") from None
    if cols < 3 or rows < 3:
        raise CalibrationInputError(f"--board {text!r}: at least 3x3 squares are needed")
    if not (math.isfinite(square_mm) and math.isfinite(marker_mm) and 0 < marker_mm < square_mm):
        raise CalibrationInputError(f"--board {text!r}: the marker side must be positive and "
                                    "smaller than the square side")
    spec = BoardSpec(cols, rows, square_mm / 1e3, marker_mm / 1e3, dictionary)
    dictionary_of(spec)  # an unknown name is refused now
    needed = cols * rows // 2
    if dictionary_of(spec).bytesList.shape[0] < needed:
        raise CalibrationInputError(f"--board {text!r}: {dictionary} holds fewer than the "
                                    f"{needed} markers this board needs")
    return spec


def dictionary_of(spec: BoardSpec) -> cv2.aruco.Dictionary:
    """The board's OpenCV dictionary; CalibrationInputError naming an unknown one."""
    code = getattr(cv2.aruco, spec.dictionary, None) \
        if spec.dictionary.startswith("DICT_") else None
    if not isinstance(code, int):
        raise CalibrationInputError(f"unknown marker dictionary {spec.dictionary!r} (OpenCV "
                                    "names such as DICT_5X5_100, DICT_6X6_250)")
    return cv2.aruco.getPredefinedDictionary(code)


def make_board(spec: BoardSpec) -> cv2.aruco.CharucoBoard:
    """OpenCV's ChArUco board for ``spec`` (current pattern, not the pre-4.6 legacy one)."""
    board = cv2.aruco.CharucoBoard((spec.cols, spec.rows), spec.square_m, spec.marker_m,
                                   dictionary_of(spec))
    board.setLegacyPattern(False)
    return board


def board_image(spec: BoardSpec, dpi: float, margin_mm: float = 10.0
                ) -> tuple[np.ndarray, tuple[float, float]]:
    """The board drawn for printing at ``dpi`` with a white margin: (grey image, printed size
    (width, height) in millimetres including the margin).

    OpenCV's marker placement rounds outside a square at some sizes (the 7x5 40 mm board at
    64 or 97 dpi, the 9x6 25 mm one at 100 or 150 dpi): there the board is drawn 1-2 pixels
    wider or taller (0.2 mm at 300 dpi), and the printed size returned is the drawn one."""
    px_per_mm = dpi / 25.4
    square_px = spec.square_m * 1e3 * px_per_mm
    margin = int(round(margin_mm * px_per_mm))
    w = int(round(spec.cols * square_px)) + 2 * margin
    h = int(round(spec.rows * square_px)) + 2 * margin
    if max(w, h) > MAX_BOARD_PX:
        raise CalibrationInputError(
            f"{dpi:g} dpi draws the board {w} x {h} pixels, over {MAX_BOARD_PX} pixels a side "
            f"(a {w * h / 2**20:.0f} MB image): use a lower --dpi")
    board = make_board(spec)
    if square_px >= 8:
        for dw, dh in ((0, 0), (1, 0), (0, 1), (1, 1), (-1, 0), (0, -1), (-1, -1), (2, 0),
                       (0, 2), (2, 2), (-2, 0), (0, -2), (-2, -2)):
            try:
                img = board.generateImage((w + dw, h + dh), marginSize=margin, borderBits=1)
            except cv2.error:
                continue
            return img, ((w + dw) / px_per_mm, (h + dh) / px_per_mm)
    raise CalibrationInputError(f"{dpi:g} dpi is too coarse to draw {spec.square_m * 1e3:g} mm "
                                f"squares with their markers: use a higher --dpi")


def detect_board(detector: cv2.aruco.CharucoDetector, image: np.ndarray
                 ) -> tuple[np.ndarray, np.ndarray]:
    """The board's chessboard corners seen in ``image``: (corners (N, 2) pixels, ids (N,))."""
    grey = image if image.ndim == 2 else cv2.cvtColor(image, cv2.COLOR_BGR2GRAY)
    corners, ids, _, _ = detector.detectBoard(grey)
    if ids is None or len(ids) == 0:
        return np.zeros((0, 2)), np.zeros(0, int)
    return np.asarray(corners, float).reshape(-1, 2), np.asarray(ids, int).ravel()


@dataclass
class LensSolve:
    """A lens calibration: camera matrix (3x3), distortion (k1, k2, p1, p2, k3), the overall RMS
    reprojection error (px), each view's RMS error (px) and how many corners were left out as
    outliers (misplaced by the detector, e.g. on small, steeply tilted squares)."""

    camera_matrix: np.ndarray
    distortion: np.ndarray
    rms_px: float
    view_rms_px: list[float]
    outliers: int = 0


def _calibrate(obj: list[np.ndarray], img: list[np.ndarray], image_size: tuple[int, int]
               ) -> tuple[float, np.ndarray, np.ndarray, list[np.ndarray]]:
    """(rms, K, dist, per-view residuals (N,) px) of ``cv2.calibrateCamera``; k3 stays 0 (it
    only overfits a table camera's lens)."""
    criteria = (cv2.TERM_CRITERIA_COUNT + cv2.TERM_CRITERIA_EPS, 100, 1e-9)
    rms, K, dist, rvecs, tvecs = cv2.calibrateCamera(obj, img, image_size, None, None,
                                                     flags=cv2.CALIB_FIX_K3, criteria=criteria)
    res = []
    for o, i, r, t in zip(obj, img, rvecs, tvecs):
        proj, _ = cv2.projectPoints(o, r, t, K, dist)
        res.append(np.linalg.norm(proj.reshape(-1, 2) - i.reshape(-1, 2), axis=1))
    return float(rms), K, np.asarray(dist, float).ravel()[:5], res


def solve_lens(board: cv2.aruco.CharucoBoard, views: list[tuple[np.ndarray, np.ndarray]],
               image_size: tuple[int, int]) -> LensSolve:
    """The lens from views of (corners (N, 2) px, ids (N,)); ``image_size`` is (width,
    height). Solved twice: corners further than max(0.5 px, 3 x RMS) from the first solution
    are left out of the second."""
    obj, img = [], []
    for corners, ids in views:
        o, i = board.matchImagePoints(corners.reshape(-1, 1, 2).astype(np.float32),
                                      ids.reshape(-1, 1).astype(np.int32))
        obj.append(o.reshape(-1, 1, 3).astype(np.float32))
        img.append(i.reshape(-1, 1, 2).astype(np.float32))
    rms, K, dist, res = _calibrate(obj, img, image_size)
    limit = max(0.5, 3.0 * rms)
    keep = [r <= limit for r in res]
    outliers = int(sum(int((~k).sum()) for k in keep))
    if outliers and all(int(k.sum()) >= MIN_CORNERS for k in keep):
        rms, K, dist, res = _calibrate([o[k] for o, k in zip(obj, keep)],
                                       [i[k] for i, k in zip(img, keep)], image_size)
    else:
        outliers = 0
    per_view = [float(np.sqrt(np.mean(r * r))) for r in res]
    return LensSolve(K, dist, rms, per_view, outliers)


def coverage(points: list[np.ndarray], image_size: tuple[int, int],
             cells: tuple[int, int] = (8, 6)) -> np.ndarray:
    """How many views put a corner in each cell of a (rows, cols) grid over the image: the
    coverage map a technician fills, corners and edges included."""
    cols, rows = cells
    counts = np.zeros((rows, cols), int)
    w, h = image_size
    for pts in points:
        if len(pts) == 0:
            continue
        cx = np.clip((np.asarray(pts)[:, 0] / w * cols).astype(int), 0, cols - 1)
        cy = np.clip((np.asarray(pts)[:, 1] / h * rows).astype(int), 0, rows - 1)
        hit = np.zeros((rows, cols), bool)
        hit[cy, cx] = True
        counts += hit
    return counts


REGION_CELLS = 4         # the image as a 4x4 grid: its outer ring is the corners and edges
REGION_VIEWS = 2         # views each corner and edge of the image needs


def coverage_gaps(points: list[np.ndarray], image_size: tuple[int, int],
                  needed: int = REGION_VIEWS) -> list[tuple[str, int]]:
    """The image's corners and edges where fewer than ``needed`` views put board corners:
    (region name, views there). Regions: the corner cells and the middle cells of each side of
    a 4x4 grid over the image (cells a quarter of its width and height): where the lens bends
    most, and where a lens solve without views there only extrapolates."""
    n = REGION_CELLS
    last, middle = n - 1, range(1, n - 1)
    regions = {"top-left corner": [(0, 0)], "top-right corner": [(0, last)],
               "bottom-right corner": [(last, last)], "bottom-left corner": [(last, 0)],
               "top edge": [(0, c) for c in middle], "right edge": [(r, last) for r in middle],
               "bottom edge": [(last, c) for c in middle], "left edge": [(r, 0) for r in middle]}
    views = {name: 0 for name in regions}
    for pts in points:
        hit = coverage([pts], image_size, (n, n)) > 0
        for name, cells in regions.items():
            views[name] += any(hit[r, c] for r, c in cells)
    return [(name, count) for name, count in views.items() if count < needed]


# ------------------------------------------------------------------- the projected pattern
def pattern_spec(size: tuple[int, int]) -> tuple[BoardSpec, int]:
    """The ChArUco board the projector shows at ``size`` (W, H) projector pixels, and its margin
    in pixels; derived from the size alone, so PATTERN.png's size tells how to read it. One
    "metre" of this board is one projector pixel."""
    w, h = size
    square = max(24, int(min(w, h) // 7))
    cols, rows = max(3, (w - square // 2) // square), max(3, (h - square // 2) // square)
    return BoardSpec(int(cols), int(rows), float(square), float(round(square * 0.72)),
                     PATTERN_DICTIONARY), square // 4


def pattern_image(size: tuple[int, int]) -> np.ndarray:
    """The calibration pattern (grey, H x W pixels) a projector of ``size`` (W, H) pixels shows: a
    ChArUco board centred on a white field."""
    w, h = size
    spec, _ = pattern_spec(size)
    bw, bh = int(spec.cols * spec.square_m), int(spec.rows * spec.square_m)
    img = np.full((h, w), 255, np.uint8)
    board = make_board(spec).generateImage((bw, bh), marginSize=0, borderBits=1)
    x0, y0 = (w - bw) // 2, (h - bh) // 2
    img[y0:y0 + bh, x0:x0 + bw] = board
    return img


def pattern_features(pattern: np.ndarray) -> dict[int, np.ndarray]:
    """Projector pixel (2,) of every chessboard corner id, read from the pattern image itself
    (so they follow the same pixel convention as the camera's detections)."""
    h, w = pattern.shape[:2]
    spec, _ = pattern_spec((w, h))
    corners, ids = detect_board(cv2.aruco.CharucoDetector(make_board(spec)), pattern)
    return {int(i): c for i, c in zip(ids, corners)}


def pattern_detector(size: tuple[int, int]) -> cv2.aruco.CharucoDetector:
    """A detector for the pattern of a projector of ``size`` (W, H) pixels."""
    return cv2.aruco.CharucoDetector(make_board(pattern_spec(size)[0]))
