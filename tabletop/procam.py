"""The projector and the camera together: fitting the projector and the morning check.

A ``ProCam`` shows an image on the projector and grabs what the camera sees. ``LiveProCam`` is a
real one (a pygame window fullscreen on the projector's display, an OpenCV camera);
``tracking.rig.SimulatedRig`` is the simulated one the tests use. The steps here run on either.
"""

from __future__ import annotations

import os
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Protocol, Sequence

import numpy as np

from calibration.charuco import CalibrationInputError
from calibration.fits import Fit
from tabletop.drawing.images import image_surface

MOVED_MM = 1.0  # a puck found this much further in the lit frame moved during the check
# what to do when the projector's display cannot be opened
WITHOUT_PROJECTOR = ("project the pattern another way and give camera images of it (--image, "
                     "without --live)")


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
    (inf: not seen); ``moved`` (N,) marks pucks that moved during the check (not measured)."""

    ids: np.ndarray
    pucks_m: np.ndarray
    offsets_mm: np.ndarray
    moved: np.ndarray | None = None

    def __post_init__(self) -> None:
        if self.moved is None:
            self.moved = np.zeros(len(self.ids), bool)


def check_lines(result: CheckResult, tolerance_mm: float) -> tuple[list[str], bool]:
    """The check as text (one line per puck, then ``PASS``/``FAIL`` with the worst figure), for
    the command line or an overlay, and whether it passed."""
    lines = []
    for pid, p, off, moved in zip(result.ids, result.pucks_m, result.offsets_mm, result.moved):
        figure = ("moved during the check, not measured" if moved
                  else f"{off:.2f} mm" if np.isfinite(off) else "cross not seen")
        lines.append(f"  puck {pid} at {p[0]:.3f}, {p[1]:.3f} m: {figure}")
    still = result.offsets_mm[~result.moved]
    if len(still) == 0:
        lines.append("NOT MEASURED: every puck moved during the check (hold them still)")
        return lines, False
    worst = float(np.max(still))
    passed = bool(np.isfinite(worst) and worst <= tolerance_mm)
    figure = f"{worst:.2f} mm" if np.isfinite(worst) else "a cross not seen"
    n = len(still)
    lines.append(f"{'PASS' if passed else 'FAIL'}: worst {figure} over {n} "
                 f"{'puck' if n == 1 else 'pucks'} (tolerance {tolerance_mm:g} mm)")
    return lines, passed


def run_check(procam: ProCam, calibration: Any, detector: Any) -> CheckResult:
    """Find the pucks (markers, with the projector dark), project a cross under each through
    ``table_to_projector`` and measure through the camera where each lands."""
    from calibration.fits import check_offsets_mm, cross_image, diagonal_centres, locate_cross
    from tracking.markers import detect_markers, refine_corners
    if calibration.table_to_projector is None:
        raise CalibrationInputError(f"{calibration.path or '<calibration>'}: table_to_projector: "
                                    "null; run `tabletop calibrate projector` first")
    procam.show(None)
    dark = procam.grab()
    size = calibration.image_size
    if size is not None and tuple(size) != (dark.shape[1], dark.shape[0]):
        raise CalibrationInputError(
            f"{calibration.path or '<calibration>'}: image_size: the calibration is for "
            f"{size[0]}x{size[1]} camera pixels but the camera delivers "
            f"{dark.shape[1]}x{dark.shape[0]}; set the camera source's resolution to "
            f"[{size[0]}, {size[1]}] or calibrate the camera again at its new size")
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
    return CheckResult(ids, pucks, check_offsets_mm(pucks, landed),
                       moved_pucks(lit, ids, pucks, calibration, detector))


def moved_pucks(lit: np.ndarray, ids: np.ndarray, pucks_m: np.ndarray, calibration: Any,
                detector: Any, limit_mm: float = MOVED_MM) -> np.ndarray:
    """(N,) True for the pucks seen in the ``lit`` frame more than ``limit_mm`` from where the
    dark frame had them (moved by a hand: their crosses cannot be compared)."""
    from calibration.fits import diagonal_centres
    from tracking.markers import detect_markers, refine_corners
    found, corners = detect_markers(lit, detector)
    moved = np.zeros(len(ids), bool)
    if len(found) == 0:
        return moved
    corners = refine_corners(lit, corners)
    now = diagonal_centres(calibration.image_to_table(corners.reshape(-1, 2)).reshape(-1, 4, 2))
    where = {int(i): c for i, c in zip(found, now)}
    for k, (pid, p) in enumerate(zip(ids, pucks_m)):
        if int(pid) in where:
            moved[k] = np.linalg.norm(where[int(pid)] - p) * 1e3 > limit_mm
    return moved


def check_inputs(cfg: dict, where: str) -> tuple[Any, Any, dict]:
    """(calibration, marker detector, camera source options) for the check of a validated
    config (``where`` names it in messages): its calibration, its marker dictionary and its
    first ``camera`` or ``synthetic_camera`` source."""
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
    return cal, detector, cams[0]


def check_from_config(path: str) -> CheckResult:
    """The check for the installation of config ``path`` (see :func:`check_inputs`): a real
    camera source live on the view's display; a ``synthetic_camera`` source on the simulated
    rig, with a projector at the view's size."""
    from tabletop.config import load_config
    cfg = load_config(path)
    cal, detector, src = check_inputs(cfg, path)
    view = cfg["view"]
    if src["kind"] == "synthetic_camera":
        procam = simulated_procam(src, cfg, tuple(view["size"]))
    else:
        procam = LiveProCam(src["device"], int(view["display"]), tuple(view["size"]),
                            resolution=src.get("resolution"))
    try:
        return run_check(procam, cal, detector)
    finally:
        close = getattr(procam, "close", None)
        if close is not None:
            close()


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
        from tabletop.display import headless_needed, start_display
        if headless_needed(False):
            raise CalibrationInputError("no display: the live projector steps need the "
                                        "projector connected as a display")
        start_display(False, instead=WITHOUT_PROJECTOR)   # as the projector view opens it
        try:
            n = pygame.display.get_num_displays()
            if not 0 <= display < n:
                raise CalibrationInputError(f"--display {display}: this machine has {n} "
                                            f"display(s), 0 to {n - 1}")
            self.cap = cv2.VideoCapture(int(device) if str(device).isdigit() else device)
            if not self.cap.isOpened():
                raise CalibrationInputError(f"camera {device}: cannot be opened")
        except BaseException:
            pygame.display.quit()
            raise
        if resolution:
            self.cap.set(cv2.CAP_PROP_FRAME_WIDTH, int(resolution[0]))
            self.cap.set(cv2.CAP_PROP_FRAME_HEIGHT, int(resolution[1]))
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
            self.screen.blit(image_surface(image), (0, 0))
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
