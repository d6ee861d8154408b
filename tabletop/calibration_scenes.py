"""Simulated calibration scenes (the calibration tests and benchmark): a known lens with its
rendered board views, and a simulated projector-camera rig over a table with a distorting
camera lens."""

from __future__ import annotations

from pathlib import Path
from typing import Iterable

import cv2
import numpy as np

from calibration.charuco import DEFAULT_BOARD, make_board, parse_board
from calibration.files import Calibration
from tracking.rig import LensRenderer, SimulatedRig, board_poses, lens_camera
from tracking.synthetic import CameraSettings

LENS_SIZE = (640, 480)
DIST = (-0.12, 0.03, 0.0005, -0.0005, 0.0)
SQUARE_PX = 40  # texture pixels per printed square


def board_views(n: int, seed: int = 2, size: tuple[int, int] = LENS_SIZE,
                fov_deg: float = 60.0) -> tuple[np.ndarray, np.ndarray, list[np.ndarray]]:
    """(K, dist, n grey views) of the default printed board before a known lens: views of
    ``size`` (W, H) pixels, ``fov_deg`` degrees across."""
    spec = parse_board(DEFAULT_BOARD)
    texture = make_board(spec).generateImage((spec.cols * SQUARE_PX, spec.rows * SQUARE_PX),
                                             marginSize=0, borderBits=1)
    K, dist = lens_camera(size, fov_deg)
    renderer = LensRenderer(K, dist, size, seed=seed)
    board_m = (spec.cols * spec.square_m, spec.rows * spec.square_m)
    views = [renderer.view(texture, SQUARE_PX, spec.square_m, r, t)
             for r, t in board_poses(K, size, board_m, n, seed, dist)]
    return K, dist, views


def write_views(folder: Path, views: Iterable[np.ndarray]) -> None:
    """Each grey view as ``folder``/view-NN.png (the folder made)."""
    folder.mkdir(parents=True, exist_ok=True)
    for i, v in enumerate(views):
        cv2.imwrite(str(folder / f"view-{i:02d}.png"), v)


def table_rig(seed: int = 3) -> SimulatedRig:
    """A 1280x720 camera tilted 14 degrees with barrel distortion, and the default projector."""
    return SimulatedRig(CameraSettings(tilt_deg=14.0, distortion=DIST, seed=seed))


def lens_only(rig: SimulatedRig) -> Calibration:
    """The rig camera's true lens, as a lens-only calibration file holds it."""
    cam = rig.camera
    return Calibration(None, None, cam.K, cam.dist, (cam.w, cam.h))


def true_calibration(rig: SimulatedRig) -> Calibration:
    """The rig's exact calibration (lens, camera -> table, table -> projector)."""
    cam = rig.camera
    return Calibration(cam.image_to_table_homography(), rig.projector.H, cam.K, cam.dist,
                       (cam.w, cam.h))


CORNER_PUCKS = [(1, 0.06, 0.06, 0.0), (2, 1.14, 0.06, 1.0), (3, 1.14, 0.74, 2.0),
                (4, 0.06, 0.74, -1.0), (5, 0.6, 0.4, 0.5), (6, 0.3, 0.55, 2.5)]


def fit_rig(rig: SimulatedRig) -> tuple[Calibration, int]:
    """Camera -> table from 12 rendered markers (true lens), then table -> projector from the
    projected pattern: (calibration, markers found)."""
    from calibration.charuco import pattern_image
    from calibration.fits import diagonal_centres, fit_table
    from calibration.transforms import undistort_pixels
    from tabletop.procam import fit_projector_images
    from tracking.markers import DetectorSettings, detect_markers, make_detector, refine_corners
    from tracking.rig import marker_layout
    cam = rig.camera
    rig.pucks = marker_layout(cam.s.table)
    rig.show(None)
    grey = rig.grab()
    ids, corners = detect_markers(grey, make_detector(DetectorSettings()))
    corners = refine_corners(grey, corners)
    where = {p[0]: p[1:3] for p in rig.pucks}
    ideal = diagonal_centres(undistort_pixels(corners.reshape(-1, 2), cam.K, cam.dist)
                             .reshape(-1, 4, 2))
    table_fit = fit_table(ideal, np.array([where[int(i)] for i in ids]))
    cal = Calibration(table_fit.H, None, cam.K, cam.dist, (cam.w, cam.h))
    rig.pucks = []
    pattern = pattern_image(rig.size)
    rig.show(pattern)
    fit = fit_projector_images(pattern, "pattern", [("seen", rig.grab())], cal, cam.s.table)
    return Calibration(table_fit.H, fit.H, cam.K, cam.dist, (cam.w, cam.h)), len(ids)
