"""Table and projector fits through the simulated projector-camera rig, and the morning check:
crosses land under the pucks across the whole table, and a knocked projector fails."""

import numpy as np
import pytest

from calibration.files import Calibration
from calibration.fits import CHECK_MM, fit_table
from calibration.transforms import FitError, apply_homography, table_grid
from tabletop.procam import run_check
from tracking.markers import DetectorSettings, make_detector

from .rigs import CORNER_PUCKS, fit_rig, table_rig, true_calibration


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


def test_view_draws_pucks_through_table_to_projector(rig):
    import pygame
    from tabletop.frames import Frame, Puck
    from tabletop.view import Renderer
    size = rig.size
    H = rig.projector.H
    r = Renderer((1.2, 0.8), size, homography=H, puck_radius=0.02)
    surf = pygame.Surface(size)
    frame = Frame(seq=0, t=0.0, pucks=(Puck(1, 0.1, 0.7, 0.0),))
    r.draw(surf, frame)
    px = apply_homography(H, [[0.1, 0.7]])[0]
    at = surf.get_at((int(round(px[0])), int(round(px[1]))))[:3]
    assert tuple(at) != (12, 12, 16) and sum(at) > 200  # the puck is drawn there
    plain = Renderer((1.2, 0.8), size, puck_radius=0.02)
    surf.fill((0, 0, 0))
    plain.draw(surf, frame)
    assert tuple(surf.get_at((int(round(px[0])), int(round(px[1]))))[:3]) != tuple(at)
