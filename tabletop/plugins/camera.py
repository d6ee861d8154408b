"""Source ``camera``: an overhead camera whose frames are searched for puck markers.

Frames come from :class:`tracking.camera.CameraSource` (a device index or path, a video file or a
folder of images; grabbing, detection and reconnection run in the source's own thread). Markers
are found by the tracking section's detector and mapped to table metres with the calibration
(this entry's ``calibration``, else the config's top-level one). Without any calibration the
image is stretched over the table (image top = far edge of the table), which is only good enough
to check that a camera works. The observation carries puck measurements in table metres.
"""

from __future__ import annotations

import dataclasses
import logging
import math
import os
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, Mapping

import numpy as np

from tabletop import registry
from tabletop.frames import Observation, PuckMeasurement
from tabletop.registry import BuildContext
from tabletop.schema import (Bool, ConfigError, Context, FilePath, ListOf, Number, Optional_,
                             Record, Spec, shown)

if TYPE_CHECKING:
    from calibration.files import Calibration
    from tracking.camera import CameraSource

log = logging.getLogger("tabletop")

DEFAULT_DICTIONARY = "DICT_4X4_50"


class Device(Spec):
    """A camera index (0, 1, ...), a device path (/dev/video2), or a video file or image folder
    (relative to the config file; these must exist at start-up)."""

    def __init__(self, default: Any = 0, doc: str = "") -> None:
        self.default, self.doc = default, doc or self.__doc__

    def describe(self) -> str:
        return "a camera index, a /dev path, a video file or a folder of images"

    def validate(self, value: Any, path: str, ctx: Context) -> Any:
        if isinstance(value, int) and not isinstance(value, bool):
            if value < 0:
                raise self.wrong_type(value, path, ctx)
            return value
        if not isinstance(value, str) or not value:
            raise self.wrong_type(value, path, ctx)
        if value.isdigit():
            return int(value)
        if value.startswith("/dev/"):
            if not is_video_device(value):
                raise ctx.error(path, f"{value} is not a video device (a camera is "
                                      "/dev/videoN)")
            return value  # a camera may be plugged in later: checked (and retried) at run time
        p = FilePath(kind="any").validate(value, path, ctx)
        problem = unreadable_input(p)
        if problem:   # it was retried for ever as "cannot open ..."
            raise ctx.error(path, f"{shown(value)}: {problem}")
        return str(p)


V4L_MAJOR = 81   # Linux's device number of every video4linux device (/dev/video*)


def is_video_device(path: str) -> bool:
    """False for a path that exists on Linux and is no video4linux device (/dev/null,
    /dev/ttyACM0); True otherwise (a camera not plugged in yet, another system)."""
    import stat
    import sys
    try:
        st = os.stat(path)
    except OSError:
        return True
    return (not sys.platform.startswith("linux")
            or (stat.S_ISCHR(st.st_mode) and os.major(st.st_rdev) == V4L_MAJOR))


def unreadable_input(path: Path) -> str:
    """Why a video file or image folder cannot be played as a camera, or '' when it can."""
    import cv2
    from tabletop.quiet import quiet_stderr
    from tracking.camera import IMAGE_SUFFIXES
    if path.is_dir():
        if any(p.suffix.lower() in IMAGE_SUFFIXES for p in path.iterdir()):
            return ""
        return f"the folder holds no images ({', '.join(IMAGE_SUFFIXES)})"
    with quiet_stderr():   # FFmpeg's own complaint ("moov atom not found")
        capture = cv2.VideoCapture(str(path))
        ok = capture.isOpened()
        capture.release()
    return "" if ok else "not a video file OpenCV can read"


class Exposure(Number):
    """A manual exposure in V4L2 units of 100 us: 1 (0.1 ms) to 10000 (1 s).

    OpenCV's V4L2 backend passes the number on as ``exposure_time_absolute``, which counts
    100 us from 1; 10000 (1 s) is longer than any frame a tracking camera delivers. A negative
    number is DirectShow's convention (log2 seconds: -5 is 1/32 s), which V4L2 drivers refuse
    or clamp to their least exposure: the message gives the value in these units."""

    def __init__(self) -> None:
        super().__init__(lo=1, hi=10_000)

    def describe(self) -> str:
        return f"{super().describe()} (V4L2 units of 100 us)"

    def validate(self, value: Any, path: str, ctx: Context) -> Any:
        try:
            return super().validate(value, path, ctx)
        except ConfigError as exc:
            if isinstance(value, (int, float)) and not isinstance(value, bool) and -16 <= value < 0:
                raise ctx.error(path, f"{value:g} is out of range: expected V4L2 units of 100 us "
                                      f"from 1 to 10000 ({value:g} as DirectShow's log2 seconds "
                                      f"is {2.0 ** value * 1e4:.0f} here)") from None
            raise exc


SCHEMA = Record({
    "device": Device(0),
    "resolution": Optional_(ListOf(Number(integer=True, unit="pixels",
                                          lo=16, hi=16384), min_len=2, max_len=2),
                            doc="requested [width, height] in pixels (devices)"),
    "fps": Optional_(Number(unit="Hz", lo=1.0, hi=1000.0),
                     doc="requested frame rate (devices); playback rate (files, folders)"),
    "exposure": Optional_(Exposure(), doc="manual exposure in V4L2 units of 100 us"),
    "calibration": Optional_(FilePath(kind="file"),
                             doc="calibration YAML for this camera (default: the top-level one)"),
    "retry_max_s": Number(8.0, lo=0.1, hi=600.0, doc="longest wait between reconnections"),
    "keep_image": Bool(False, doc="attach each grey frame to the observation (view, snapshots)"),
})


def tracking_dictionary(config: Mapping[str, Any]) -> str:
    """The marker dictionary named by the config's tracking section (``dictionary`` at its top
    or in a nested mapping such as ``markers``), else DICT_4X4_50."""
    section = config.get("tracking") or {}
    if isinstance(section.get("dictionary"), str):
        return section["dictionary"]
    for value in section.values():
        if isinstance(value, dict) and isinstance(value.get("dictionary"), str):
            return value["dictionary"]
    return DEFAULT_DICTIONARY


class PlainDetector:
    """Full-frame ``ArucoDetector`` with sub-pixel corners: the detector used when no tracking
    plugin provides one. ``detect(grey, predictions_px)`` ignores the predictions."""

    def __init__(self, dictionary: str = DEFAULT_DICTIONARY) -> None:
        import cv2
        params = cv2.aruco.DetectorParameters()
        params.cornerRefinementMethod = cv2.aruco.CORNER_REFINE_SUBPIX
        code = getattr(cv2.aruco, dictionary, None)
        if not isinstance(code, int):
            raise ValueError(f"unknown marker dictionary {dictionary!r}")
        self.detector = cv2.aruco.ArucoDetector(cv2.aruco.getPredefinedDictionary(code), params)

    def detect(self, grey: np.ndarray, predictions_px: Mapping[int, tuple[float, float]] | None
               = None) -> tuple[np.ndarray, np.ndarray]:
        corners, ids, _ = self.detector.detectMarkers(grey)
        if ids is None or len(ids) == 0:
            return np.zeros(0, int), np.zeros((0, 4, 2))
        return np.asarray(ids, int).ravel(), np.asarray(corners, float).reshape(-1, 4, 2)


def make_detector(ctx: BuildContext) -> Any:
    """A fresh detector for one camera: the tracking plugin's ``build_detector`` when installed."""
    tracking = registry.optional_module("tabletop.plugins.tracking")
    if tracking is not None and hasattr(tracking, "build_detector"):
        return tracking.build_detector(ctx.config.get("tracking") or {})
    return PlainDetector(tracking_dictionary(ctx.config))


def stretch_calibration(width: int, height: int, table: tuple[float, float]) -> Calibration:
    """A stand-in calibration that stretches an image of ``width`` x ``height`` pixels over the
    table (W, H metres; no camera geometry)."""
    from calibration.files import Calibration
    w, h = table
    H = np.array([[w / width, 0.0, 0.0], [0.0, -h / height, h], [0.0, 0.0, 1.0]])
    return Calibration(H)


class MarkerMeasurer:
    """``process`` for a camera source: grey frame -> markers -> puck measurements in table metres.

    ``calibration`` maps pixels to the table (None: the image is stretched over ``table``).
    ``predictions`` (optional, e.g. the puck tracker's ``predictions(t)``) gives each puck's
    expected table position at time t; they become pixel predictions for region-of-interest
    detection. ``keep_image`` attaches the frame to the observation.
    """

    def __init__(self, source: str, detector: Any, calibration: Any = None,
                 table: tuple[float, float] = (1.2, 0.8),
                 predictions: Callable[[float], Mapping[int, tuple[float, float]]] | None = None,
                 keep_image: bool = False) -> None:
        self.source, self.detector, self.calibration = source, detector, calibration
        self.table, self.predictions, self.keep_image = table, predictions, keep_image
        self._failed_predictions = False
        self.note = "" if calibration is not None else "uncalibrated"
        self._checked_size = False
        self._last: Observation | None = None   # the newest frame's, until after_publish

    def _predictions_px(self, t: float) -> dict[int, tuple[float, float]] | None:
        if self.predictions is None or self.calibration is None:
            return None
        try:
            preds = self.predictions(t)
        except Exception:
            if not self._failed_predictions:
                log.exception("%s: tracker predictions failed; using the detector's own",
                              self.source)
                self._failed_predictions = True
            return None
        if not preds:
            return None
        ids = list(preds)
        px = self.calibration.table_to_image(np.array([preds[i][:2] for i in ids], float))
        return {i: (float(p[0]), float(p[1])) for i, p in zip(ids, px) if np.all(np.isfinite(p))}

    def after_publish(self) -> Observation | None:
        """Work put off until the frame's observation is out (the detector's full-frame
        search), run by the camera thread. Returns the frame's observation again with the
        pucks that search added (same capture time), or None when it added none."""
        search = getattr(self.detector, "search_pending", None)
        last, self._last = self._last, None
        if search is None:
            return None
        found = search()
        if last is None or found is None or not len(found[0]):
            return None
        seen = {p.id for p in last.pucks}
        added = tuple(p for p in measurements(*found, self.calibration, last.t)
                      if p.id not in seen)
        return dataclasses.replace(last, pucks=last.pucks + added) if added else None

    def __call__(self, grey: np.ndarray, t: float, n: int) -> Observation:
        if self.calibration is None:
            self.calibration = stretch_calibration(grey.shape[1], grey.shape[0], self.table)
        if not self._checked_size:
            self._checked_size = True
            size = getattr(self.calibration, "image_size", None)
            if size is not None and tuple(size) != (grey.shape[1], grey.shape[0]):
                self.note = (f"calibrated for {size[0]}x{size[1]} but frames are "
                             f"{grey.shape[1]}x{grey.shape[0]}")
                log.warning("%s: %s: positions will be wrong", self.source, self.note)
        ids, corners = self.detector.detect(grey, self._predictions_px(t))
        pucks = measurements(ids, corners, self.calibration, t)
        self._last = Observation(self.source, t, n, pucks=pucks,
                                 image=grey if self.keep_image else None)
        return self._last


def measurements(ids: np.ndarray, corners: np.ndarray, calibration: Any,
                 t: float) -> tuple[PuckMeasurement, ...]:
    """Markers (ids (N,), corners (N, 4, 2) px) -> puck measurements in table metres at ``t``.

    The centre is the mean of the corners mapped to the table; the heading is the table
    direction of the marker's c0 -> c1 edge (averaged with the parallel c3 -> c2 edge).
    """
    ids = np.asarray(ids, int).ravel()
    if len(ids) == 0:
        return ()
    table = calibration.image_to_table(np.asarray(corners, float).reshape(-1, 2)).reshape(-1, 4, 2)
    centres = table.mean(axis=1)
    edge = (table[:, 1] - table[:, 0]) + (table[:, 2] - table[:, 3])
    angles = np.arctan2(edge[:, 1], edge[:, 0])
    out = []
    for i, c, a in zip(ids, centres, angles):
        if np.all(np.isfinite(c)) and math.isfinite(a):
            out.append(PuckMeasurement(int(i), float(c[0]), float(c[1]), float(a), t))
    return tuple(out)


def tracker_predictions(
        ctx: BuildContext) -> Callable[[float], Mapping[int, tuple[float, float]]] | None:
    """The shared puck tracker's ``predictions(t)`` (table metres per puck id) if it has one."""
    fn = getattr(ctx.shared.get("tracker"), "predictions", None)
    return fn if callable(fn) else None


def share_calibration(ctx: BuildContext, calibration: Any) -> None:
    """Offer a loaded calibration to the view (projector homography) and the recorder header."""
    ctx.shared.setdefault("calibration", calibration)
    ctx.shared.setdefault("calibration_dict", calibration.to_dict())
    if calibration.table_to_projector is not None:
        ctx.shared.setdefault("table_to_projector", calibration.table_to_projector)


def build(options: dict, ctx: BuildContext) -> CameraSource:
    from calibration.files import load_calibration
    from tracking.camera import CameraSource, settings_from_options

    path: Path | None = options["calibration"] or ctx.config.get("calibration")
    calibration = load_calibration(path) if path is not None else None
    if calibration is None:
        log.warning("camera %s: no calibration; the image is stretched over the table",
                    options["name"])
    else:
        share_calibration(ctx, calibration)
    measurer = MarkerMeasurer(options["name"], make_detector(ctx), calibration, ctx.table,
                              tracker_predictions(ctx), options["keep_image"])
    settings = settings_from_options(options)
    return CameraSource(options["name"], settings, measurer)
