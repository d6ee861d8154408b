"""Calibration files: one YAML file mapping camera pixels <-> table metres <-> projector pixels.

Format (``format: tabletop-calibration``, ``version: 1``)::

    format: tabletop-calibration
    version: 1
    date: "2026-11-22T10:00:00+00:00"        # when it was measured (ISO 8601)
    image_size: [1280, 720]                  # camera pixels (optional)
    intrinsics:                              # optional; null for an ideal (undistorted) camera
      camera_matrix: [[fx, 0, cx], [0, fy, cy], [0, 0, 1]]
      distortion: [k1, k2, p1, p2, k3]       # OpenCV's order, 4 to 14 numbers
    camera_to_table: [[...], [...], [...]]   # 3x3: undistorted camera pixels -> table metres
    table_to_projector: null                 # 3x3: table metres -> projector pixels, or null
    projector_size: [1280, 720]              # projector pixels it was fitted at (optional)
    reprojection_error:                      # optional figures, null when not measured
      intrinsics_px: 0.21
      camera_to_table_m: 0.0008
      table_to_projector_px: null

When intrinsics are given, ``camera_to_table`` applies to pixels undistorted with
``cv2.undistortPoints(..., P=camera_matrix)``, i.e. to the ideal pinhole image of the same camera
matrix. Loading checks every key and value and names the file and the key of what is wrong.
"""

from __future__ import annotations

import datetime as _dt
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from calibration.plausible import lens_problem, scale_problem
from calibration.transforms import (apply_homography, distort_pixels, inverse, normalised,
                                    undistort_pixels)
from tabletop.files import (MAX_CALIBRATION_BYTES, atomic_write_bytes, atomic_write_text,
                            read_yaml)
from tabletop.frames import InputError

FORMAT = "tabletop-calibration"
VERSION = 1
ERROR_KEYS = ("intrinsics_px", "camera_to_table_m", "table_to_projector_px")


class CalibrationError(InputError):
    """A calibration file is missing or malformed; the message names the file and the key."""


@dataclass
class Calibration:
    """Camera intrinsics (optional), camera -> table and table -> projector homographies.

    ``camera_to_table``: 3x3, undistorted camera pixels -> table metres (None in a file that so
    far holds only the lens). ``table_to_projector``:
    3x3, table metres -> projector pixels, or None. ``camera_matrix`` (3x3) and ``distortion``
    (OpenCV's coefficients) describe the lens, or are None for an ideal camera.
    ``reprojection_error``: named residuals (pixels or metres as their names say).
    ``projector_size``: the projector's (W, H) pixels ``table_to_projector`` was fitted at
    (None when unknown: files written before it was recorded).
    """

    camera_to_table: np.ndarray | None
    table_to_projector: np.ndarray | None = None
    camera_matrix: np.ndarray | None = None
    distortion: np.ndarray | None = None
    image_size: tuple[int, int] | None = None
    reprojection_error: dict[str, float | None] = field(default_factory=dict)
    date: str = ""
    projector_size: tuple[int, int] | None = None
    path: str = field(default="", compare=False)  # the file it was read from, for messages

    def __post_init__(self) -> None:
        if self.camera_to_table is not None:
            self.camera_to_table = normalised(self.camera_to_table)
        if self.table_to_projector is not None:
            self.table_to_projector = normalised(self.table_to_projector)
        if self.camera_matrix is not None:
            self.camera_matrix = np.asarray(self.camera_matrix, dtype=float)
            d = np.zeros(5) if self.distortion is None else np.asarray(self.distortion, float)
            self.distortion = d.ravel()
        self._table_to_camera = (None if self.camera_to_table is None
                                 else inverse(self.camera_to_table))

    def undistort(self, points_px: np.ndarray) -> np.ndarray:
        """Camera pixels (N, 2) -> ideal pinhole pixels of the same camera matrix (N, 2)."""
        return undistort_pixels(points_px, self.camera_matrix, self.distortion)

    def image_to_table(self, points_px: np.ndarray) -> np.ndarray:
        """Camera pixels (N, 2) -> table metres (N, 2), undistorting first when a lens is known."""
        return apply_homography(self.camera_to_table, self.undistort(points_px))

    def table_to_image(self, points_m: np.ndarray) -> np.ndarray:
        """Table metres (N, 2) -> camera pixels (N, 2), distorted as the lens would."""
        ideal = apply_homography(self._table_to_camera, points_m)
        return distort_pixels(ideal, self.camera_matrix, self.distortion)

    def projector_to_table(self, points_px: np.ndarray) -> np.ndarray:
        """Projector pixels (N, 2) -> table metres (N, 2); ValueError without a projector fit."""
        if self.table_to_projector is None:
            raise ValueError("the calibration has no table_to_projector")
        return apply_homography(inverse(self.table_to_projector), points_px)

    def check_projector_size(self, size: Sequence[int], key: str = "view.size") -> None:
        """Refuse a projector of ``size`` (W, H) pixels when ``table_to_projector`` was fitted
        at another resolution (CalibrationError naming the file and both keys)."""
        ps = self.projector_size
        if self.table_to_projector is None or ps is None or tuple(size) == tuple(ps):
            return
        raise CalibrationError(
            f"{self.path or '<calibration>'}: projector_size: the projector was calibrated at "
            f"{ps[0]}x{ps[1]} pixels but {key} is {size[0]}x{size[1]}; set {key}: "
            f"[{ps[0]}, {ps[1]}] or redo `tabletop calibrate projector` at the new size")

    def to_dict(self) -> dict[str, Any]:
        """The file's content as plain YAML-ready values."""
        intrinsics = None
        if self.camera_matrix is not None:
            intrinsics = {"camera_matrix": self.camera_matrix.tolist(),
                          "distortion": [float(v) for v in self.distortion]}
        errors = {k: self.reprojection_error.get(k) for k in ERROR_KEYS}
        errors.update({k: v for k, v in self.reprojection_error.items() if k not in errors})
        return {
            "format": FORMAT,
            "version": VERSION,
            "date": self.date or _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
            "image_size": None if self.image_size is None else list(self.image_size),
            "intrinsics": intrinsics,
            "camera_to_table": (None if self.camera_to_table is None
                                else self.camera_to_table.tolist()),
            "table_to_projector": (None if self.table_to_projector is None
                                   else self.table_to_projector.tolist()),
            "projector_size": (None if self.projector_size is None
                               else [int(v) for v in self.projector_size]),
            "reprojection_error": {k: None if v is None else float(v) for k, v in errors.items()},
        }


# ------------------------------------------------------------------------------------ reading
def _matrix(value: Any, rows: int, cols: int, where: str, key: str) -> np.ndarray:
    shape = f"{rows}x{cols}"
    try:
        a = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise CalibrationError(f"{where}: {key}: expected a {shape} list of numbers, "
                               f"got {value!r}") from None
    if a.shape != (rows, cols) or isinstance(value, (str, bytes)):
        raise CalibrationError(f"{where}: {key}: expected a {shape} list of numbers, "
                               f"got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise CalibrationError(f"{where}: {key}: every number must be finite")
    return a


def _homography(value: Any, where: str, key: str) -> np.ndarray:
    H = _matrix(value, 3, 3, where, key)
    # The test is det(H) < 1e-12 * max(1, |H|max)^3, taken on H scaled by max(1, |H|max) so
    # that entries near 1e300 neither overflow the cube (an OverflowError that would stop
    # `tabletop run` with "internal error") nor the determinant.
    scale = max(1.0, float(np.abs(H).max()))
    if abs(np.linalg.det(H / scale)) < 1e-12:
        raise CalibrationError(f"{where}: {key}: the homography is singular (not invertible)")
    return H


def _size(value: Any, where: str, key: str) -> tuple[int, int] | None:
    """An optional ``[width, height]`` in pixels."""
    if value is None:
        return None
    if (not isinstance(value, list) or len(value) != 2
            or not all(isinstance(v, int) and not isinstance(v, bool) and v > 0 for v in value)):
        raise CalibrationError(f"{where}: {key}: expected [width, height] in pixels, "
                               f"got {value!r}")
    return value[0], value[1]


def calibration_from_dict(data: Any, where: str = "<calibration>",
                          require_table: bool = True) -> Calibration:
    """Validate parsed YAML content; ``where`` names the file in error messages. With
    ``require_table`` False, ``camera_to_table: null`` (a lens-only file) is accepted."""
    if not isinstance(data, dict):
        raise CalibrationError(f"{where}: expected a mapping with keys format, version, "
                               f"camera_to_table, ...; got {type(data).__name__}")
    known = {"format", "version", "date", "image_size", "intrinsics", "camera_to_table",
             "table_to_projector", "projector_size", "reprojection_error"}
    for key in data:
        if key not in known:
            raise CalibrationError(f"{where}: {key}: unknown key (known: "
                                   f"{', '.join(sorted(known))})")
    if data.get("format") != FORMAT:
        raise CalibrationError(f"{where}: format: expected {FORMAT!r}, got {data.get('format')!r}")
    if isinstance(data.get("version"), bool) or data.get("version") != VERSION:
        raise CalibrationError(f"{where}: version: expected {VERSION}, got {data.get('version')!r}")
    if "camera_to_table" not in data:
        raise CalibrationError(f"{where}: camera_to_table: missing; expected a 3x3 homography "
                               "from camera pixels to table metres")
    if data["camera_to_table"] is None and not require_table:
        c2t = None
    elif data["camera_to_table"] is None:
        raise CalibrationError(f"{where}: camera_to_table: null (only the lens is calibrated); "
                               "run `tabletop calibrate table` first")
    else:
        c2t = _homography(data["camera_to_table"], where, "camera_to_table")
    t2p = data.get("table_to_projector")
    t2p = None if t2p is None else _homography(t2p, where, "table_to_projector")
    size = _size(data.get("image_size"), where, "image_size")
    projector_size = _size(data.get("projector_size"), where, "projector_size")
    K = dist = None
    intr = data.get("intrinsics")
    if intr is not None:
        if not isinstance(intr, dict) or "camera_matrix" not in intr:
            raise CalibrationError(f"{where}: intrinsics: expected a mapping with camera_matrix "
                                   "and distortion, or null")
        for key in intr:
            if key not in ("camera_matrix", "distortion"):
                raise CalibrationError(f"{where}: intrinsics.{key}: unknown key "
                                       "(known: camera_matrix, distortion)")
        K = _matrix(intr["camera_matrix"], 3, 3, where, "intrinsics.camera_matrix")
        if K[0, 0] <= 0 or K[1, 1] <= 0 or K[2, 2] != 1.0 or K[1, 0] or K[2, 0] or K[2, 1]:
            raise CalibrationError(f"{where}: intrinsics.camera_matrix: expected "
                                   "[[fx, s, cx], [0, fy, cy], [0, 0, 1]] with fx, fy > 0")
        raw = intr.get("distortion") or [0.0] * 5
        if not isinstance(raw, list) or len(raw) not in (4, 5, 8, 12, 14):
            raise CalibrationError(f"{where}: intrinsics.distortion: expected a list of 4, 5, "
                                   f"8, 12 or 14 numbers, got {raw!r}")
        dist = _matrix([raw], 1, len(raw), where, "intrinsics.distortion").ravel()
    if K is not None:
        key, problem = lens_problem(K, dist, size)
        if problem:
            raise CalibrationError(f"{where}: {key}: {problem}")
    centre = ((size[0] / 2, size[1] / 2) if size is not None
              else (K[0, 2], K[1, 2]) if K is not None else None)
    problem = scale_problem(c2t, centre) if c2t is not None and centre is not None else None
    if problem:
        raise CalibrationError(f"{where}: camera_to_table: {problem}")
    errors = data.get("reprojection_error") or {}
    if not isinstance(errors, dict):
        raise CalibrationError(f"{where}: reprojection_error: expected a mapping of names to "
                               f"numbers, got {errors!r}")
    for key, v in errors.items():
        if key not in ERROR_KEYS:   # (a misspelt one was kept unread, then dropped on save)
            raise CalibrationError(f"{where}: reprojection_error.{key}: unknown key (known: "
                                   f"{', '.join(ERROR_KEYS)})")
        if v is not None and (isinstance(v, bool) or not isinstance(v, (int, float))
                              or not math.isfinite(v) or v < 0):
            raise CalibrationError(f"{where}: reprojection_error.{key}: expected a number "
                                   f">= 0 or null, got {v!r}")
    date = data.get("date", "")
    if isinstance(date, (_dt.date, _dt.datetime)):
        date = date.isoformat()
    if not isinstance(date, str):
        raise CalibrationError(f"{where}: date: expected an ISO 8601 date, got {date!r}")
    return Calibration(c2t, t2p, K, dist, size, dict(errors), date, projector_size)


def load_calibration(path: str | Path, require_table: bool = True) -> Calibration:
    """Read and validate a calibration file; CalibrationError names the file and the key.
    ``require_table`` False also accepts a file that holds only the lens so far."""
    p = Path(path)
    data = read_yaml(p, CalibrationError, missing="calibration file not found",
                     max_bytes=MAX_CALIBRATION_BYTES, kind="calibration")
    if data is None:
        raise CalibrationError(f"{p}: the file is empty")
    cal = calibration_from_dict(data, str(p), require_table)
    cal.path = str(p)
    return cal


def save_calibration(path: str | Path, calibration: Calibration) -> None:
    """Write ``calibration`` to ``path`` atomically (temporary file, fsync, rename). One that
    loading would refuse (CalibrationError naming the file and key) is not written: a forced
    result of numbers no camera has replaced a working file with one no table could start on."""
    import yaml
    data = calibration.to_dict()
    calibration_from_dict(data, str(path), require_table=False)
    text = ("# Tabletop calibration: camera pixels <-> table metres <-> projector pixels.\n"
            + yaml.safe_dump(data, sort_keys=False, default_flow_style=None))
    atomic_write_text(path, text)


def save_with_backup(path: str | Path, calibration: Calibration) -> Path | None:
    """Save ``calibration`` atomically; an existing file is first copied (atomically) to
    ``PATH.bak``. Returns the backup's path, or None when there was no previous file."""
    p = Path(path)
    backup = None
    if p.exists():
        backup = p.with_name(p.name + ".bak")
        atomic_write_bytes(backup, p.read_bytes())
    save_calibration(p, calibration)
    return backup
