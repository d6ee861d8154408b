"""Calibration files: the synthetic camera's true calibration saved, loaded and used to map
pixels to the table (undistorting), and every malformed file refused naming file and key."""

import math

import numpy as np
import pytest
import yaml

from calibration.files import (Calibration, CalibrationError, load_calibration,
                               save_calibration)
from tracking.markers import marker_measurements
from tracking.synthetic import CameraSettings, SyntheticCamera

DIST = (-0.12, 0.03, 0.0005, -0.0005, 0.0)


def true_calibration(cam: SyntheticCamera, with_lens: bool = True) -> Calibration:
    t2p = np.array([[1000.0, 0.0, 40.0], [0.0, -1000.0, 840.0], [0.0, 0.0, 1.0]])
    return Calibration(cam.image_to_table_homography(), t2p,
                       cam.K if with_lens else None, cam.dist if with_lens else None,
                       (cam.w, cam.h), {"intrinsics_px": 0.2, "camera_to_table_m": 0.0007},
                       "2026-11-22T10:00:00+00:00")


def test_round_trip_maps_pixels_to_table(tmp_path):
    cam = SyntheticCamera(CameraSettings(tilt_deg=18.0, distortion=DIST))
    path = tmp_path / "calib.yaml"
    save_calibration(path, true_calibration(cam))
    cal = load_calibration(path)
    assert list(tmp_path.iterdir()) == [path]  # no temporary file left behind
    rng = np.random.default_rng(0)
    table = np.column_stack([rng.uniform(0, 1.2, 200), rng.uniform(0, 0.8, 200)])
    px = cam.project(table)
    assert np.abs(cal.image_to_table(px) - table).max() <= 1e-5  # 10 micrometres
    assert np.abs(cal.table_to_image(table) - px).max() <= 0.01
    # Without undistorting, the lens bends the image corners by millimetres: the lens matters.
    plain = Calibration(cal.camera_to_table)
    assert np.abs(plain.image_to_table(px) - table).max() >= 0.005
    assert cal.image_size == (cam.w, cam.h)
    assert cal.reprojection_error["intrinsics_px"] == pytest.approx(0.2)
    assert cal.reprojection_error["table_to_projector_px"] is None
    assert cal.date == "2026-11-22T10:00:00+00:00"
    assert np.allclose(cal.table_to_projector, true_calibration(cam).table_to_projector)
    # Heading: an image direction along the marker's c0 -> c1 is the puck's table angle.
    c = cam.project(cam.marker_corners_table(0.5, 0.4, 2.0).T)
    (m,) = marker_measurements(np.array([0]), c[None], 0.0, cal.image_to_table)
    assert math.isclose(m.angle, 2.0, abs_tol=1e-6)


def test_ideal_camera_needs_no_intrinsics(tmp_path):
    cam = SyntheticCamera(CameraSettings(resolution=(640, 360)))
    path = tmp_path / "c.yaml"
    cal = true_calibration(cam, with_lens=False)
    cal.table_to_projector = None
    save_calibration(path, cal)
    back = load_calibration(path)
    assert back.camera_matrix is None and back.table_to_projector is None
    pts = np.array([[0.1, 0.1], [1.1, 0.7]])
    assert np.abs(back.image_to_table(cam.project(pts)) - pts).max() <= 1e-9
    assert back.image_to_table(np.zeros((0, 2))).shape == (0, 2)


def test_saving_over_a_file_replaces_it_whole(tmp_path):
    cam = SyntheticCamera(CameraSettings(resolution=(640, 360)))
    path = tmp_path / "c.yaml"
    path.write_text("old content\n")
    save_calibration(path, true_calibration(cam))
    assert load_calibration(path).image_size == (640, 360)


def lens(f: float, k1: float = 0.0, cx: float = 640.0, skew: float = 0.0) -> dict:
    """Intrinsics of a 1280x720 camera."""
    return {"camera_matrix": [[f, skew, cx], [0, f, 360.0], [0, 0, 1]],
            "distortion": [k1, 0.0, 0.0, 0.0, 0.0]}


def sized(**entries):
    """A change giving a 1280x720 image and ``entries``."""
    return lambda d: d.update(image_size=[1280, 720], **entries)


def good() -> dict:
    return {"format": "tabletop-calibration", "version": 1, "date": "2026-01-01",
            "camera_to_table": [[0.001, 0, 0], [0, 0.001, 0], [0, 0, 1]]}


@pytest.mark.parametrize("change, expected", [
    (lambda d: d.pop("camera_to_table"), "camera_to_table: missing"),
    (lambda d: d.update(camera_to_table=[[1, 0], [0, 1]]), "camera_to_table: expected a 3x3"),
    (lambda d: d.update(camera_to_table=[[1, 0, 0], [0, 1, 0], [0, 0, 0]]), "singular"),
    (lambda d: d.update(camera_to_table=[[1e300, 0, 0], [0, 1e300, 0], [0, 0, 1]]), "singular"),
    (lambda d: d.update(table_to_projector=[[1e200, 0, 0], [0, 1e-200, 0], [0, 0, 1]]),
     "table_to_projector: the homography is singular"),
    (lambda d: d.update(camera_to_table="identity"), "camera_to_table: expected a 3x3"),
    (lambda d: d.update(table_to_projector=[[1, 0, 0], [0, 1, 0], [0, 0, ".nan"]]),
     "table_to_projector"),
    (lambda d: d.update(format="other"), "format: expected"),
    (lambda d: d.update(version=7), "version: expected 1"),
    (lambda d: d.update(version=True), "version: expected 1, got True"),
    (lambda d: d.update(colour="red"), "colour: unknown key"),
    (lambda d: d.update(image_size=[1280]), "image_size: expected"),
    (lambda d: d.update(intrinsics={"camera_matrix": [[0, 0, 1], [0, 1, 1], [0, 0, 1]]}),
     "intrinsics.camera_matrix"),
    (lambda d: d.update(intrinsics={"camera_matrix": [[9, 0, 1], [0, 9, 1], [0, 0, 1]],
                                    "distortion": [0.1, 0.2, 0.3]}), "intrinsics.distortion"),
    (lambda d: d.update(reprojection_error={"intrinsics_px": -1}),
     "reprojection_error.intrinsics_px"),
    (lambda d: d.update(reprojection_error={"intrinsics_pxx": 0.2}),   # (it was accepted)
     r"reprojection_error.intrinsics_pxx: unknown key \(known: intrinsics_px, "
     r"camera_to_table_m, table_to_projector_px\)"),
    # numbers no camera has (each would map every marker to one point, NaN or nowhere)
    (sized(intrinsics=lens(1e300)), r"intrinsics: fx = 1e\+300, fy = 1e\+300 px with this "
     r"distortion give a 0.000\d+ degree field of view across the image's short side; "
     r"expected 1 to 179"),
    (sized(intrinsics=lens(900.0, k1=1e9)), r"intrinsics: .* 0.08\d+ degree field"),
    (sized(intrinsics=lens(900.0, k1=-50.0)), r"intrinsics.distortion: \[-50.0, 0.0, 0.0, 0.0, "
     r"0.0\] folds the image back on itself 14% of the way from its centre to its long edges "
     r"\(no lens does"),
    (sized(intrinsics=lens(900.0, cx=1e300)), r"intrinsics.camera_matrix: the principal point "
     r"\(1e\+300, 360\) px lies outside the 1280x720 image"),
    (sized(intrinsics=lens(900.0, skew=1e300)), r"intrinsics.camera_matrix: the skew 1e\+300 px "
     r"exceeds fx = 900 px"),
    (sized(camera_to_table=[[1e6, 0, 0], [0, 1e6, 0], [0, 0, 1]]), r"camera_to_table: a pixel "
     r"at the image's centre \(640, 360\) covers 1e\+06 m of table; expected 1e-06 to 20"),
])
def test_malformed_files_name_file_and_key(tmp_path, change, expected):
    data = good()
    change(data)
    path = tmp_path / "bad.yaml"
    path.write_text(yaml.safe_dump(data))
    with pytest.raises(CalibrationError, match=expected) as info:
        load_calibration(path)
    assert str(path) in str(info.value)


def test_unreadable_files(tmp_path):
    with pytest.raises(CalibrationError, match="not found"):
        load_calibration(tmp_path / "none.yaml")
    (tmp_path / "e.yaml").write_text("")
    with pytest.raises(CalibrationError, match="empty"):
        load_calibration(tmp_path / "e.yaml")
    (tmp_path / "s.yaml").write_text("camera_to_table: [[1, 0\n")
    with pytest.raises(CalibrationError, match="line"):
        load_calibration(tmp_path / "s.yaml")
    (tmp_path / "l.yaml").write_text("- 1\n- 2\n")
    with pytest.raises(CalibrationError, match="expected a mapping"):
        load_calibration(tmp_path / "l.yaml")


def test_a_calibration_loading_would_refuse_is_not_saved(tmp_path):
    """A forced result of numbers no camera has replaced a working file with one no table
    could start on; the working file now stays byte for byte."""
    path = tmp_path / "calib.yaml"
    good_cal = Calibration(np.diag([0.001, 0.001, 1.0]), image_size=(1280, 720))
    save_calibration(path, good_cal)
    before = path.read_bytes()
    absurd = Calibration(np.diag([0.001, 0.001, 1.0]), image_size=(1280, 720),
                         camera_matrix=np.array([[900.0, 0, 640], [0, 900, 360], [0, 0, 1]]),
                         distortion=np.array([-50.0, 0, 0, 0, 0]))
    with pytest.raises(CalibrationError, match=r"calib.yaml: intrinsics.distortion: \[-50.0, "):
        save_calibration(path, absurd)
    assert path.read_bytes() == before and list(tmp_path.iterdir()) == [path]
