"""The projector and the camera together: fitting the projector and the morning check.

A ``ProCam`` shows an image on the projector and grabs what the camera sees. ``LiveProCam`` is a
real one (a pygame window fullscreen on the projector's display, an OpenCV camera);
``tracking.rig.SimulatedRig`` is the simulated one the tests use. The steps here run on either.
"""

from __future__ import annotations

import logging
import os
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Protocol, Sequence

import numpy as np

from calibration.charuco import CalibrationInputError
from calibration.fits import Fit

log = logging.getLogger("tabletop")


class ProCam(Protocol):
    """A projector (``size`` W, H pixels; ``show``) and a camera (``grab``) over one table."""

    size: tuple[int, int]

    def show(self, image: np.ndarray | None) -> None: ...

    def grab(self) -> np.ndarray: ...


# ------------------------------------------------------------------------------ the projector
def pattern_correspondences(image: np.ndarray, features: dict[int, np.ndarray], detector: Any,
                            calibration: Any, table: tuple[float, float] | None
                            ) -> tuple[np.ndarray, np.ndarray]:
    """(table metres (N, 2), projector pixels (N, 2)) of the pattern corners seen in a camera
    image; corners beyond the table's edge (when ``table`` is known) are left out."""
    from calibration.charuco import detect_board
    from calibration.fits import on_table
    corners, ids = detect_board(detector, image)
    keep = np.array([int(i) in features for i in ids], bool)
    if not keep.any():
        return np.zeros((0, 2)), np.zeros((0, 2))
    table_m = calibration.image_to_table(corners[keep])
    proj = np.array([features[int(i)] for i in ids[keep]])
    if table is not None:
        inside = on_table(table_m, table)
        table_m, proj = table_m[inside], proj[inside]
    return table_m, proj


def fit_projector_images(pattern: np.ndarray, pattern_name: str,
                         images: Sequence[tuple[Any, np.ndarray]], calibration: Any,
                         table: tuple[float, float] | None) -> Fit:
    """``table_to_projector`` from camera images of the projected pattern (named, grey)."""
    from calibration.charuco import pattern_detector, pattern_features
    from calibration.fits import fit_projector
    from calibration.transforms import FitError
    h, w = pattern.shape[:2]
    features = pattern_features(pattern)
    if len(features) < 4:
        raise CalibrationInputError(f"{pattern_name}: not a calibration pattern (make one with "
                                    "`tabletop calibrate pattern`)")
    detector = pattern_detector((w, h))
    all_t, all_p = [], []
    for name, img in images:
        t, p = pattern_correspondences(img, features, detector, calibration, table)
        if len(t) < 4:
            raise CalibrationInputError(f"{name}: the projected pattern is not visible ({len(t)} "
                                        "corners found; is the projector on, showing "
                                        f"{pattern_name} unscaled?)")
        print(f"  {name}: {len(t)} pattern corners")
        all_t.append(t)
        all_p.append(p)
    try:
        fit, _ = fit_projector(np.concatenate(all_t), np.concatenate(all_p))
    except FitError as exc:
        raise CalibrationInputError(f"the projected pattern: {exc}") from None
    return fit


def stable_projector_fit(procam: ProCam, calibration: Any, table: tuple[float, float] | None,
                         stable_mm: float = 0.5, needed: int = 3, max_frames: int = 60) -> Fit:
    """Show the pattern, grab frames and fit each, until ``needed`` fits in a row agree within
    ``stable_mm`` over the whole table; the last fit is returned."""
    from calibration.charuco import pattern_image
    from calibration.fits import stability_mm
    pattern = pattern_image(procam.size)
    procam.show(pattern)
    last, agreeing = None, 0
    for i in range(max_frames):
        try:
            fit = fit_projector_images(pattern, "the pattern", [(f"frame {i}", procam.grab())],
                                       calibration, table)
        except CalibrationInputError:
            last, agreeing = None, 0
            continue
        span = table or _span(fit.H, procam.size)
        if last is not None and stability_mm(last.H, fit.H, span) <= stable_mm:
            agreeing += 1
            if agreeing + 1 >= needed:
                procam.show(None)
                return fit
        else:
            agreeing = 0
        last = fit
    procam.show(None)
    raise CalibrationInputError(f"the projected pattern was not seen steadily in {max_frames} "
                                "camera frames (is the camera's auto exposure locked?)")


def _span(H: np.ndarray, size: tuple[int, int]) -> tuple[float, float]:
    """The table's extent (m) the projector covers, when the table's size is not given."""
    from calibration.transforms import apply_homography, inverse
    w, h = size
    t = apply_homography(inverse(H), np.array([[0, 0], [w, 0], [w, h], [0, h]], float))
    return float(np.ptp(t[:, 0])), float(np.ptp(t[:, 1]))


# ---------------------------------------------------------------------------------- the check
@dataclass
class CheckResult:
    """Marker ids (N,), their table positions (N, 2) m and how far each cross landed (N,) mm
    (inf: not seen)."""

    ids: np.ndarray
    pucks_m: np.ndarray
    offsets_mm: np.ndarray


def check_lines(result: CheckResult, tolerance_mm: float) -> tuple[list[str], bool]:
    """The check as text (one line per puck, then ``PASS``/``FAIL`` with the worst figure), for
    the command line or an overlay, and whether it passed."""
    lines = []
    for pid, p, off in zip(result.ids, result.pucks_m, result.offsets_mm):
        figure = f"{off:.2f} mm" if np.isfinite(off) else "cross not seen"
        lines.append(f"  puck {pid} at {p[0]:.3f}, {p[1]:.3f} m: {figure}")
    worst = float(np.max(result.offsets_mm)) if len(result.offsets_mm) else float("inf")
    passed = bool(np.isfinite(worst) and worst <= tolerance_mm)
    figure = f"{worst:.2f} mm" if np.isfinite(worst) else "a cross not seen"
    lines.append(f"{'PASS' if passed else 'FAIL'}: worst {figure} over {len(result.ids)} pucks "
                 f"(tolerance {tolerance_mm:g} mm)")
    return lines, passed


def run_check(procam: ProCam, calibration: Any, detector: Any) -> CheckResult:
    """Find the pucks (markers, with the projector dark), project a cross under each through
    ``table_to_projector`` and measure through the camera where each lands."""
    from calibration.fits import check_offsets_mm, cross_image, diagonal_centres, locate_cross
    from tracking.markers import detect_markers, refine_corners
    if calibration.table_to_projector is None:
        raise CalibrationInputError("the calibration has no table_to_projector; run `tabletop "
                                    "calibrate projector` first")
    procam.show(None)
    dark = procam.grab()
    size = calibration.image_size
    if size is not None and tuple(size) != (dark.shape[1], dark.shape[0]):
        raise CalibrationInputError(f"the camera delivers {dark.shape[1]}x{dark.shape[0]} "
                                    f"pixels, the calibration is for {size[0]}x{size[1]}")
    ids, corners = detect_markers(dark, detector)
    if len(ids) == 0:
        raise CalibrationInputError("no puck is seen by the camera: put pucks on the table, "
                                    "including near its corners")
    corners = refine_corners(dark, corners)
    table_corners = calibration.image_to_table(corners.reshape(-1, 2)).reshape(-1, 4, 2)
    pucks = diagonal_centres(table_corners)
    procam.show(cross_image(procam.size, calibration.table_to_projector, pucks))
    lit = procam.grab()
    procam.show(None)
    landed = [locate_cross(lit, dark, calibration.image_to_table, p, calibration.table_to_image)
              for p in pucks]
    return CheckResult(ids, pucks, check_offsets_mm(pucks, landed))


def check_setup(cfg: dict, where: str) -> tuple[Any, Any, Any]:
    """(ProCam, calibration, marker detector) for the check of a validated config (``where``
    names it in messages): its calibration, marker dictionary, first camera source and the
    view's display. A ``synthetic_camera`` source gets the simulated rig, with a projector at
    the view's size; a ``camera`` source is returned as its options (opened live by the
    caller)."""
    from calibration.files import load_calibration
    from tracking.markers import DetectorSettings, make_detector
    if cfg.get("calibration") is None:
        raise CalibrationInputError(f"{where}: calibration: none given; the check needs the "
                                    "installation's calibration file")
    cal = load_calibration(cfg["calibration"])
    cal.check_projector_size(tuple(cfg["view"]["size"]))
    from tabletop.plugins.camera import tracking_dictionary
    detector = make_detector(DetectorSettings(dictionary=tracking_dictionary(cfg)))
    cams = [s for s in cfg["sources"] if s["kind"] in ("camera", "synthetic_camera")]
    if not cams:
        raise CalibrationInputError(f"{where}: sources: no camera or synthetic_camera source to "
                                    "check through")
    src, view = cams[0], cfg["view"]
    if src["kind"] == "synthetic_camera":
        return simulated_procam(src, cfg, tuple(view["size"])), cal, detector
    return src, cal, detector


def check_from_config(path: str) -> CheckResult:
    """The check for the installation of config ``path`` (see :func:`check_setup`); a real
    camera source is checked live on the projector display."""
    from tabletop.config import load_config
    cfg = load_config(path)
    procam, cal, detector = check_setup(cfg, path)
    if isinstance(procam, dict):
        view = cfg["view"]
        procam = LiveProCam(procam["device"], int(view["display"]), tuple(view["size"]),
                            resolution=procam.get("resolution"))
    try:
        return run_check(procam, cal, detector)
    finally:
        close = getattr(procam, "close", None)
        if close is not None:
            close()


class LiveCheck:
    """Sink: the morning check measured during ``tabletop run`` every ``every_s`` seconds (in a
    thread, so the loop never waits), with the pucks where the tracker has them; ``lines()``
    is the text for the operator overlay (:func:`check_lines`). Runs on a simulated rig; with a
    real camera the running view owns the projector, so the overlay says to use
    ``tabletop calibrate check``."""

    name = "calibration-check"

    def __init__(self, procam: Any, calibration: Any, detector: Any,
                 tolerance_mm: float | None = None, every_s: float = 10.0) -> None:
        from calibration.fits import CHECK_MM
        import threading
        self.procam, self.calibration, self.detector = procam, calibration, detector
        self.tolerance = CHECK_MM if tolerance_mm is None else tolerance_mm
        self.every_s, self._next_t = every_s, None
        self._lock = threading.Lock()
        self._thread: threading.Thread | None = None
        self.measured = 0  # checks completed (for tests and the overlay)
        self._lines = ["calibration check: waiting for the first measurement"]
        if isinstance(procam, dict):
            self._lines = ["calibration check: with a real camera the running view holds the "
                           "projector; stop the run and use `tabletop calibrate check`"]
            self.procam = None

    def lines(self) -> list[str]:
        """The newest check as overlay lines (one per puck, then PASS/FAIL)."""
        with self._lock:
            return list(self._lines)

    def consume(self, frame: Any) -> None:
        import threading
        if self.procam is None or (self._thread is not None and self._thread.is_alive()):
            return
        if self._next_t is not None and frame.t < self._next_t:
            return
        if not frame.pucks:
            with self._lock:
                self._lines = ["calibration check: no puck tracked yet (put pucks on the "
                               "table, a few near its corners)"]
            return
        self._next_t = frame.t + self.every_s
        poses = [(p.id, p.x, p.y, p.angle) for p in frame.pucks]
        self._thread = threading.Thread(target=self._measure, args=(poses,),
                                        name="calibration-check", daemon=True)
        self._thread.start()

    def _measure(self, poses: list[tuple[int, float, float, float]]) -> None:
        when = time.strftime("%H:%M:%S")
        if hasattr(self.procam, "pucks"):
            self.procam.pucks = poses  # the simulated rig: pucks where the tracker has them
        try:
            lines, _ = check_lines(run_check(self.procam, self.calibration, self.detector),
                                   self.tolerance)
            lines = [f"calibration check at {when}:"] + lines
        except CalibrationInputError as exc:
            lines = [f"calibration check at {when}: {exc}"]
        except Exception as exc:  # the running installation never crashes over its check
            log.exception("calibration check failed")
            lines = [f"calibration check at {when} failed: {exc}"]
        with self._lock:
            self._lines, self.measured = lines, self.measured + 1

    def close(self) -> None:
        if self._thread is not None:
            self._thread.join(timeout=10.0)


def simulated_procam(source: dict, cfg: dict, size: tuple[int, int]) -> Any:
    """The simulated rig of a ``synthetic_camera`` source: its camera, a projector of ``size``
    pixels, and its scripted pucks where they start."""
    from tabletop.plugins import scripted
    from tabletop.plugins.synthetic_camera import camera_settings
    from tabletop.registry import BuildContext
    from tracking.rig import ProjectorSettings, SimulatedRig
    table = (cfg["table"]["width"], cfg["table"]["height"])
    ctx = BuildContext(table=table, rate_hz=cfg["loop"]["rate_hz"], config=cfg,
                       base=Path(cfg.get("_base", ".")))
    rig = SimulatedRig(camera_settings(source, ctx), ProjectorSettings(resolution=size))
    script = scripted.build({k: source[k] for k in ("name", *scripted.SCHEMA.fields)}, ctx)
    rig.pucks = list(script.poses(0.0))
    return rig


# --------------------------------------------------------------------------------- live parts
class LiveProCam:
    """A real projector and camera: a pygame window fullscreen on display ``display`` and an
    OpenCV camera ``device``. Each ``grab`` waits ``settle_s`` after the last ``show`` (the
    projector and the camera's exposure need a few frames)."""

    def __init__(self, device: Any, display: int, size: tuple[int, int] | None = None,
                 settle_s: float = 0.4, resolution: Sequence[int] | None = None) -> None:
        import cv2
        os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
        import pygame
        from tabletop.view import headless_needed
        if headless_needed(False):
            raise CalibrationInputError("no display: the live projector steps need the "
                                        "projector connected as a display")
        self.cap = cv2.VideoCapture(int(device) if str(device).isdigit() else device)
        if not self.cap.isOpened():
            raise CalibrationInputError(f"camera {device}: cannot be opened")
        if resolution:
            self.cap.set(cv2.CAP_PROP_FRAME_WIDTH, int(resolution[0]))
            self.cap.set(cv2.CAP_PROP_FRAME_HEIGHT, int(resolution[1]))
        pygame.display.init()
        if display >= pygame.display.get_num_displays():
            raise CalibrationInputError(f"display {display}: only "
                                        f"{pygame.display.get_num_displays()} connected")
        if size is None:
            size = tuple(pygame.display.get_desktop_sizes()[display])
        self.size = (int(size[0]), int(size[1]))
        self.screen = pygame.display.set_mode(self.size, pygame.FULLSCREEN, display=display)
        pygame.mouse.set_visible(False)
        self.settle_s, self._shown_at = settle_s, time.monotonic()

    def show(self, image: np.ndarray | None) -> None:
        import pygame
        self.screen.fill((0, 0, 0))
        if image is not None:
            rgb = np.repeat(image[..., None], 3, axis=2) if image.ndim == 2 else image[..., ::-1]
            self.screen.blit(pygame.surfarray.make_surface(rgb.swapaxes(0, 1)), (0, 0))
        pygame.display.flip()
        pygame.event.pump()
        self._shown_at = time.monotonic()

    def grab(self) -> np.ndarray:
        import cv2
        import pygame
        while time.monotonic() < self._shown_at + self.settle_s:
            pygame.event.pump()
            self.cap.grab()
        ok, frame = self.cap.read()
        if not ok:
            raise CalibrationInputError("the camera delivered no frame")
        return cv2.cvtColor(frame, cv2.COLOR_BGR2GRAY) if frame.ndim == 3 else frame

    def close(self) -> None:
        import pygame
        self.cap.release()
        pygame.display.quit()


def live_projector(device: str, display: int, size: tuple[int, int] | None, calibration: Any,
                   table: tuple[float, float] | None) -> tuple[Fit, tuple[int, int]]:
    """``calibrate projector --live``: the pattern fullscreen on ``display``, camera ``device``
    frames fitted until the fit is stable; (the fit, the projector's (W, H) pixels)."""
    procam = LiveProCam(device, display, size)
    try:
        return stable_projector_fit(procam, calibration, table), procam.size
    finally:
        procam.close()


def capture_views(device: str, detector: Any, save_dir: str | None) -> list[tuple[str, np.ndarray]]:
    """``calibrate camera --device N``: the live camera image with the detected board corners
    and a coverage map of the views taken so far; Space grabs a view, Enter solves, Esc quits."""
    from tabletop.calibrate_ui import CaptureWindow
    return CaptureWindow(device, detector, save_dir).run()
