"""Table and projector fits through the simulated projector-camera rig, and the morning check:
crosses land under the pucks across the whole table, and a knocked projector fails."""

import numpy as np
import pytest

from calibration.fits import CHECK_MM, fit_table
from calibration.transforms import FitError, apply_homography, table_grid
from tabletop.calibration_scenes import CORNER_PUCKS, fit_rig, table_rig, true_calibration
from tabletop.procam import run_check
from tracking.markers import DetectorSettings, make_detector


@pytest.fixture(scope="module")
def rig():
    return table_rig()


@pytest.fixture(scope="module")
def fitted(rig):
    return fit_rig(rig)


def test_table_fit_maps_every_point_back_within_a_millimetre(rig, fitted):
    cal, n = fitted
    assert n == 12
    grid = table_grid(rig.camera.s.table, 25, 17)  # edges and corners included
    err = np.linalg.norm(cal.image_to_table(rig.camera.project(grid)) - grid, axis=1)
    assert err.max() <= 0.001


def test_projector_fit_within_two_millimetres_corners_included(rig, fitted):
    cal, _ = fitted
    grid = table_grid(rig.camera.s.table, 25, 17)
    landed = cal.projector_to_table(rig.projector.table_to_projector(grid))
    assert np.linalg.norm(landed - grid, axis=1).max() <= 0.002


def test_crosses_land_under_pucks_and_a_knocked_projector_fails(rig, fitted):
    cal, _ = fitted
    rig.pucks = CORNER_PUCKS
    detector = make_detector(DetectorSettings())
    good = run_check(rig, cal, detector)
    assert sorted(good.ids.tolist()) == [1, 2, 3, 4, 5, 6]
    truth = {p[0]: p[1:3] for p in CORNER_PUCKS}
    for i, p in zip(good.ids, good.pucks_m):
        assert np.linalg.norm(p - truth[int(i)]) <= 0.001
    assert good.offsets_mm.max() <= CHECK_MM
    knocked = run_check(rig.with_projector(rig.projector.shifted(0.004, -0.003)), cal, detector)
    assert knocked.offsets_mm.min() >= 3.5 and knocked.offsets_mm.max() <= 6.5  # 5 mm shift


def test_a_perfect_calibration_checks_near_zero(rig):
    rig.pucks = CORNER_PUCKS[:3]
    res = run_check(rig, true_calibration(rig), make_detector(DetectorSettings()))
    assert res.offsets_mm.max() <= 0.8


def test_collinear_or_too_few_points_are_refused():
    line = np.column_stack([np.linspace(0, 1, 6), np.linspace(0, 0.5, 6)])
    with pytest.raises(FitError, match="one line"):
        fit_table(line * 500, line)
    with pytest.raises(FitError, match="at least 4"):
        fit_table(line[:3] * 500, line[:3])


def _drawn_centre(renderer, size, frame) -> np.ndarray:
    """Centroid (px) of what drawing ``frame`` adds to an empty table."""
    import pygame
    from tabletop.frames import Frame
    empty, surf = pygame.Surface(size), pygame.Surface(size)
    renderer.draw(empty, Frame(seq=0, t=frame.t))
    renderer.draw(surf, frame)
    diff = np.abs(pygame.surfarray.array3d(surf).astype(int)
                  - pygame.surfarray.array3d(empty).astype(int)).sum(axis=2)
    xs, ys = np.nonzero(diff > 60)
    assert xs.size > 20, "nothing drawn for the puck"
    return np.array([xs.mean(), ys.mean()])


def test_view_draws_pucks_through_table_to_projector(rig):
    from tabletop.frames import Frame, Puck
    from tabletop.view import Renderer
    size = rig.size
    H = rig.projector.H
    frame = Frame(seq=0, t=0.0, pucks=(Puck(1, 0.1, 0.7, 0.0),))
    px = apply_homography(H, [[0.1, 0.7]])[0]
    centre = _drawn_centre(Renderer((1.2, 0.8), size, homography=H, puck_radius=0.02), size, frame)
    assert np.hypot(*(centre - px)) < 4.0   # the halo is centred where the projector lands
    plain = _drawn_centre(Renderer((1.2, 0.8), size, puck_radius=0.02), size, frame)
    assert np.hypot(*(plain - px)) > 10.0   # without the calibration it would land elsewhere


def test_live_projector_loop_settles_on_a_stable_fit(rig, fitted):
    """The ``--live`` loop on the simulated rig: pattern shown, frames fitted until three agree."""
    from tabletop.procam import stable_projector_fit
    cal, _ = fitted
    rig.pucks = CORNER_PUCKS[4:]  # pucks left on the table hide a few corners
    lens_and_table = type(cal)(cal.camera_to_table, None, cal.camera_matrix, cal.distortion)
    fit = stable_projector_fit(rig, lens_and_table, rig.camera.s.table, max_frames=6)
    grid = table_grid(rig.camera.s.table, 13, 9)
    back = type(cal)(cal.camera_to_table, fit.H).projector_to_table(
        rig.projector.table_to_projector(grid))
    assert np.linalg.norm(back - grid, axis=1).max() <= 0.002
    assert rig._shown is None  # the projector is dark again


def test_capture_window_grabs_views_and_fills_the_coverage_map():
    import cv2
    import pygame
    from calibration.charuco import DEFAULT_BOARD, make_board, parse_board
    from tabletop.calibrate_ui import CaptureWindow, coverage_colours
    from tabletop.calibration_scenes import board_views
    _, _, views = board_views(2, seed=2)
    det = cv2.aruco.CharucoDetector(make_board(parse_board(DEFAULT_BOARD)))
    win = CaptureWindow("0", det)
    assert not win.grab_view(np.full((480, 640), 128, np.uint8))  # no board: not kept
    assert win.grab_view(views[0]) and win.grab_view(views[1])
    pygame.font.init()
    screen = pygame.Surface((640, 480))
    win.draw(screen, views[0], pygame.font.Font(None, 20))
    from calibration.charuco import coverage
    counts = coverage(win.points, (640, 480), (8, 6))
    colours = coverage_colours(counts)
    assert counts.max() >= 1 and (counts == 0).any() and len(win.views) == 2
    assert (colours[counts == 0] == (220, 40, 40)).all() \
        and (colours[counts == 1] == (230, 170, 30)).all()
    needs = win.needs((640, 480))  # the centre and the top-left corner only: the rest is short
    assert needs.startswith("still needed (2 views each): ") and "bottom-right corner (0)" in needs


def test_a_camera_image_becomes_a_surface_of_its_pixels():
    """Grey and BGR images as the calibration windows show them: (W, H) pixels, x across."""
    from tabletop.drawing.images import image_surface
    grey = np.zeros((3, 5), np.uint8)
    grey[1, 4] = 200
    bgr = np.zeros((3, 5, 3), np.uint8)
    bgr[2, 0] = (10, 20, 30)
    a, b = image_surface(grey), image_surface(bgr)
    assert a.get_size() == b.get_size() == (5, 3)
    assert tuple(a.get_at((4, 1)))[:3] == (200, 200, 200) \
        and tuple(a.get_at((0, 0)))[:3] == (0, 0, 0)
    assert tuple(b.get_at((0, 2)))[:3] == (30, 20, 10)


def test_sprites_turn_with_the_projector_homography():
    """Headings are turned into screen angles (radians, y down) through the homography."""
    from tabletop.view import TableToScreen
    plain = TableToScreen((1.2, 0.8), (1280, 720))
    assert plain.screen_angle(0.6, 0.4, 0.5) == pytest.approx(-0.5)  # table y up the screen
    mirrored = TableToScreen((1.2, 0.8), (1280, 720),
                             homography=np.array([[1000.0, 0, 40], [0, 1000.0, 40], [0, 0, 1]]))
    assert mirrored.screen_angle(0.6, 0.4, 0.5) == pytest.approx(0.5)  # table y down the screen
