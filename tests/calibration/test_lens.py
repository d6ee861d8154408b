"""The lens solve: intrinsics recovered from rendered ChArUco views of a known camera with
lens distortion, and the view-level refusals."""

import cv2
import numpy as np
import pytest

from calibration.charuco import (DEFAULT_BOARD, MIN_CORNERS, CalibrationInputError, board_image,
                                 coverage, coverage_gaps, detect_board, make_board, parse_board,
                                 solve_lens)
from calibration.transforms import fit_homography, residuals
from tabletop.calibration_scenes import LENS_SIZE, board_views


@pytest.fixture(scope="module")
def solved():
    """20 views as the README asks for them (tracking.rig.board_poses: the centre, every corner
    and edge of the image, tilted 25-40 degrees); the first of the benchmark's ten sets."""
    K, dist, views = board_views(20, seed=1)
    board = make_board(parse_board(DEFAULT_BOARD))
    det = cv2.aruco.CharucoDetector(board)
    found = [detect_board(det, v) for v in views]
    used = [f for f in found if len(f[1]) >= MIN_CORNERS]
    assert coverage_gaps([c for c, _ in used], LENS_SIZE) == []  # the command would take it
    return K, dist, solve_lens(board, used, LENS_SIZE), len(used)


def test_focal_and_principal_point_recovered(solved):
    K, _, s, used = solved
    assert used >= 19
    assert abs(s.camera_matrix[0, 0] / K[0, 0] - 1) <= 0.01
    assert abs(s.camera_matrix[1, 1] / K[1, 1] - 1) <= 0.01
    assert np.abs(s.camera_matrix[:2, 2] - K[:2, 2]).max() <= 2.0
    assert s.rms_px <= 0.3
    assert len(s.view_rms_px) == used and max(s.view_rms_px) <= 0.6


def test_points_undistorted_within_a_third_of_a_pixel_across_the_image(solved):
    """Every pixel of the image, corners included, undistorted with the solved lens lands where
    the true lens puts it, up to a homography (which the table fit absorbs)."""
    K, dist, s, _ = solved
    w, h = LENS_SIZE
    grid = np.stack(np.meshgrid(np.linspace(0, w - 1, 33), np.linspace(0, h - 1, 25)), -1)
    grid = grid.reshape(-1, 1, 2).astype(np.float64)
    true = cv2.undistortPoints(grid, K, dist, P=K).reshape(-1, 2)
    got = cv2.undistortPoints(grid, s.camera_matrix, s.distortion,
                              P=s.camera_matrix).reshape(-1, 2)
    H = fit_homography(got, true)
    assert residuals(H, got, true).max() <= 0.3
    # Ignoring the lens would be off by many pixels in the corners: the check can fail.
    assert residuals(fit_homography(grid.reshape(-1, 2), true), grid.reshape(-1, 2),
                     true).max() >= 5.0


def test_board_spec_and_printed_size():
    spec = parse_board("9x6:25:18:DICT_6X6_250")
    assert (spec.cols, spec.rows, spec.square_m, spec.marker_m) == (9, 6, 0.025, 0.018)
    img, (w_mm, h_mm) = board_image(spec, 300)
    assert img.shape == (round(h_mm / 25.4 * 300), round(w_mm / 25.4 * 300))
    assert w_mm == pytest.approx(9 * 25 + 20, abs=0.2) \
        and h_mm == pytest.approx(6 * 25 + 20, abs=0.2)
    det = cv2.aruco.CharucoDetector(make_board(spec))
    assert len(detect_board(det, img)[1]) == 8 * 5  # every inner corner of the printed board


@pytest.mark.parametrize("text, words", [
    ("7x5:40:30", "COLSxROWS:SQUARE_MM:MARKER_MM:DICTIONARY"),
    ("7by5:40:30:DICT_5X5_100", "COLSxROWS"),
    ("7x5:30:40:DICT_5X5_100", "smaller than the square"),
    ("7x5:40:30:DICT_NOPE", "unknown marker dictionary"),
    ("20x20:40:30:DICT_4X4_50", "fewer than"),
])
def test_bad_board_specs_are_refused_in_one_line(text, words):
    with pytest.raises(CalibrationInputError) as exc:
        parse_board(text)
    assert words in str(exc.value) and "\n" not in str(exc.value)


def test_coverage_gaps_name_the_image_corners_and_edges_without_views():
    w, h = 640, 480
    top_left = np.array([[10.0, 10.0], [100.0, 60.0]])  # top-left corner cell only
    top_edge = np.array([[320.0, 20.0]])
    centre = np.array([[320.0, 240.0]])
    gaps = dict(coverage_gaps([top_left, top_left, top_edge, centre], (w, h)))
    assert "top-left corner" not in gaps and gaps["top edge"] == 1
    assert gaps["bottom-right corner"] == 0 and len(gaps) == 7
    ring = [np.array([[x, y]]) for x in (5.0, 320.0, 635.0) for y in (5.0, 240.0, 475.0)]
    assert coverage_gaps(ring + ring, (w, h)) == []


def test_coverage_counts_views_per_cell():
    pts = [np.array([[1.0, 1.0], [639.0, 479.0]]), np.array([[2.0, 3.0]])]
    c = coverage(pts, (640, 480), (4, 3))
    assert c[0, 0] == 2 and c[2, 3] == 1 and c.sum() == 3


def test_command_line_default_board_is_the_library_default():
    from tabletop.commands import calibrate
    assert calibrate.DEFAULT_BOARD == DEFAULT_BOARD


@pytest.mark.parametrize("text, dpi",
                         [("7x5:40:30:DICT_5X5_100", 64), ("7x5:40:30:DICT_5X5_100", 97),
                          ("9x6:25:18:DICT_6X6_250", 100), ("9x6:25:18:DICT_6X6_250", 150)])
def test_the_board_draws_at_resolutions_whose_squares_are_not_whole_pixels(text, dpi):
    # OpenCV placed these boards' markers outside the image (an assertion, not a board)
    spec = parse_board(text)
    img, (w_mm, h_mm) = board_image(spec, dpi)
    pixel_mm = 25.4 / dpi   # drawn at most 2 pixels wider or taller, the margin rounded to one
    assert abs(w_mm - (spec.cols * spec.square_m * 1e3 + 20)) <= 3 * pixel_mm
    assert abs(h_mm - (spec.rows * spec.square_m * 1e3 + 20)) <= 3 * pixel_mm
    assert img.shape == (round(h_mm / 25.4 * dpi), round(w_mm / 25.4 * dpi))
    det = cv2.aruco.CharucoDetector(make_board(spec))
    assert len(detect_board(det, img)[1]) == (spec.cols - 1) * (spec.rows - 1)


def test_a_resolution_too_coarse_for_the_markers_is_refused():
    with pytest.raises(CalibrationInputError, match="too coarse"):
        board_image(parse_board("7x5:40:30:DICT_5X5_100"), 3)


def test_a_resolution_too_fine_for_an_image_is_refused_as_such():
    # 100,000 dpi made OpenCV fail on a 1181102 x 866142 image, which was called "too coarse"
    with pytest.raises(CalibrationInputError, match="1181102 x 866142 pixels.*lower --dpi"):
        board_image(parse_board("7x5:40:30:DICT_5X5_100"), 100000)
