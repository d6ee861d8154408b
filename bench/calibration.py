"""Calibration benchmark: the lens solve's time for 20 views, and the accuracy of every step.

1. Lens: 20 rendered views (640x480) of the default ChArUco board before a known camera with
   barrel distortion, for twenty pose sets (seeds) a technician following the README takes
   (``tracking.rig.board_poses``): detection time per view, solve time
   (``cv2.calibrateCamera`` twice, with stray corners left out), focal error (%), principal
   point error (px) and the worst undistortion error over the whole image (px, up to a
   homography, which the table fit absorbs).
2. Table: 12 markers rendered by the 1280x720 synthetic camera (tilted, distorting lens); the
   worst error (mm) of the fitted camera -> table over a 25 x 17 grid covering the table.
3. Projector: the pattern seen through the simulated rig; the worst error (mm) over that grid of
   the fitted table -> projector, corners included.
4. Check: crosses under six pucks (four in the table's corners), the worst offset (mm) with the
   fitted calibration and with the projector knocked 5 mm aside.

Solve and detection timings of the seeds are interleaved (A B A B) so drift favours none.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

import cv2  # noqa: E402
import numpy as np  # noqa: E402

from bench.common import check_flags, emit  # noqa: E402
from calibration.charuco import (DEFAULT_BOARD, MIN_CORNERS, coverage_gaps,  # noqa: E402
                                 detect_board, make_board, parse_board, solve_lens)
from calibration.transforms import fit_homography, residuals, table_grid  # noqa: E402
from tabletop.calibration_scenes import (CORNER_PUCKS, LENS_SIZE, board_views,  # noqa: E402
                                         fit_rig, table_rig)

SEEDS = tuple(range(1, 21))  # twenty pose sets a technician following the README takes


def lens_figures() -> dict[str, float]:
    board = make_board(parse_board(DEFAULT_BOARD))
    det = cv2.aruco.CharucoDetector(board)
    scenes = {s: board_views(20, seed=s) for s in SEEDS}
    detect_s, solve_s, views = [], {s: [] for s in SEEDS}, {}
    for s, (_, _, imgs) in scenes.items():
        found = []
        for img in imgs:
            t = time.perf_counter()
            found.append(detect_board(det, img))
            detect_s.append(time.perf_counter() - t)
        views[s] = [f for f in found if len(f[1]) >= MIN_CORNERS]
    solves = {}
    for _ in range(3):
        for s in SEEDS:  # interleaved: seed 1, 2, ... then again
            t = time.perf_counter()
            solves[s] = solve_lens(board, views[s], LENS_SIZE)
            solve_s[s].append(time.perf_counter() - t)
    focal, pp, undist, rms = [], [], [], []
    w, h = LENS_SIZE
    grid = np.stack(np.meshgrid(np.linspace(0, w - 1, 33), np.linspace(0, h - 1, 25)), -1)
    grid = grid.reshape(-1, 1, 2).astype(np.float64)
    for s, (K, dist, _) in scenes.items():
        sol = solves[s]
        focal.append(100 * max(abs(sol.camera_matrix[0, 0] / K[0, 0] - 1),
                               abs(sol.camera_matrix[1, 1] / K[1, 1] - 1)))
        pp.append(float(np.linalg.norm(sol.camera_matrix[:2, 2] - K[:2, 2])))
        true = cv2.undistortPoints(grid, K, dist, P=K).reshape(-1, 2)
        got = cv2.undistortPoints(grid, sol.camera_matrix, sol.distortion,
                                  P=sol.camera_matrix).reshape(-1, 2)
        undist.append(float(residuals(fit_homography(got, true), got, true).max()))
        rms.append(sol.rms_px)
    med_solve = [float(np.median(v)) for v in solve_s.values()]
    return {"lens_views": 20, "lens_seeds": len(SEEDS),
            "lens_solve_20_views_median_s": float(np.median(med_solve)),
            "lens_solve_20_views_max_s": float(max(max(v) for v in solve_s.values())),
            "lens_detect_per_view_median_ms": float(np.median(detect_s) * 1e3),
            "lens_rms_px_median": float(np.median(rms)),
            "focal_error_pct_median": float(np.median(focal)),
            "focal_error_pct_worst": float(max(focal)),
            "principal_point_error_px_median": float(np.median(pp)),
            "principal_point_error_px_worst": float(max(pp)),
            "undistortion_error_px_worst_median": float(np.median(undist)),
            "undistortion_error_px_worst": float(max(undist)),
            "undistortion_sets_within_0_3px": int(sum(u <= 0.3 for u in undist)),
            "lens_sets_short_of_coverage": int(sum(bool(coverage_gaps([c for c, _ in v], LENS_SIZE))
                                                   for v in views.values()))}


def rig_figures() -> dict[str, float]:
    from tabletop.procam import run_check
    from tracking.markers import DetectorSettings, make_detector
    rig = table_rig()
    t = time.perf_counter()
    cal, _ = fit_rig(rig)
    fit_s = time.perf_counter() - t
    grid = table_grid(rig.camera.s.table, 25, 17)
    table_mm = np.linalg.norm(cal.image_to_table(rig.camera.project(grid)) - grid, axis=1) * 1e3
    proj = cal.projector_to_table(rig.projector.table_to_projector(grid))
    proj_mm = np.linalg.norm(proj - grid, axis=1) * 1e3
    rig.pucks = CORNER_PUCKS
    det = make_detector(DetectorSettings())
    good = run_check(rig, cal, det)
    knocked = run_check(rig.with_projector(rig.projector.shifted(0.004, -0.003)), cal, det)
    return {"table_error_mm_worst": float(table_mm.max()),
            "table_error_mm_median": float(np.median(table_mm)),
            "projector_error_mm_worst": float(proj_mm.max()),
            "projector_error_mm_median": float(np.median(proj_mm)),
            "check_offset_mm_worst": float(good.offsets_mm.max()),
            "check_offset_mm_worst_projector_knocked_5mm": float(knocked.offsets_mm.max()),
            "check_offset_mm_least_projector_knocked_5mm": float(knocked.offsets_mm.min()),
            "table_and_projector_fit_s": fit_s}


def main() -> None:
    check_flags("calibration", sys.argv[1:])
    t0 = time.perf_counter()
    figures = lens_figures()
    figures.update(rig_figures())
    figures["bench_seconds"] = time.perf_counter() - t0
    budgets = {"lens_solve_20_views_median_s": 2.0, "focal_error_pct_worst": 1.0,
               "principal_point_error_px_worst": 2.0, "undistortion_error_px_worst": 0.3,
               "table_error_mm_worst": 1.0, "projector_error_mm_worst": 2.0,
               "check_offset_mm_worst": 2.0}
    emit("calibration", figures, budgets)


if __name__ == "__main__":
    main()
