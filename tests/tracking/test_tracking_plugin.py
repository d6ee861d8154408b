"""The ``tracking:`` config section: defaults, validation, builders."""

from __future__ import annotations

import pytest

from tabletop.frames import Observation, PuckMeasurement
from tabletop.plugins import tracking as plugin
from tabletop.schema import ConfigError
from tracking.scenes import CameraPipeline, grid_poses
from tracking.synthetic import CameraSettings, SyntheticCamera


def test_defaults_and_bad_values_name_the_key():
    o = plugin.complete({})
    assert o["coast_s"] == 0.5 and o["reacquire_step_m"] == 0.01
    assert o["dictionary"] == "DICT_4X4_50"
    import cv2    # (the default is taken without asking OpenCV: it must be one of its names)
    assert isinstance(getattr(cv2.aruco, o["dictionary"]), int)
    with pytest.raises(ConfigError, match="tracking.dictionary"):
        plugin.complete({"dictionary": "DICT_NOPE"})
    with pytest.raises(ConfigError, match="tracking.coast_s"):
        plugin.complete({"coast_s": -1})
    with pytest.raises(ConfigError, match="tracking.bogus"):
        plugin.complete({"bogus": 1})


def test_built_tracker_fuses_observations_and_predicts():
    tr = plugin.build_tracker(plugin.complete({"smooth": False}))
    obs = Observation("cam", 0.0, 1, pucks=(PuckMeasurement(3, 0.5, 0.4, 0.0, 0.0),))
    obs2 = Observation("cam", 0.1, 2, pucks=(PuckMeasurement(3, 0.55, 0.4, 0.0, 0.1),))
    tr.update([obs], 0.0)
    p = tr.update([obs2], 0.1)[0]
    assert p.state == "seen" and p.x == pytest.approx(0.55)
    assert tr.predictions(0.2)[3][0] > 0.55


def test_built_detector_finds_apriltags():
    cam = SyntheticCamera(CameraSettings(dictionary="DICT_APRILTAG_36h11", seed=3))
    f = cam.render(grid_poses(5, seed=2, first_id=200))
    det = plugin.build_detector({"dictionary": "DICT_APRILTAG_36h11"})
    ids, corners = det.detect(f.image, None)
    assert sorted(ids.tolist()) == list(range(200, 205)) and corners.shape == (5, 4, 2)


def test_puck_ids_map_marker_ids_and_predictions_come_back_by_marker_id():
    tr = plugin.build_tracker(plugin.complete({"puck_ids": {"17": 1}, "smooth": False}))
    obs = Observation("cam", 0.0, 1, pucks=(PuckMeasurement(17, 0.5, 0.4, 0.0, 0.0),
                                            PuckMeasurement(2, 0.2, 0.2, 0.0, 0.0)))
    assert [p.id for p in tr.update([obs], 0.0)] == [1, 2]
    assert set(tr.predictions(0.03)) == {17, 2}
    with pytest.raises(ConfigError, match="puck_ids.abc"):
        plugin.complete({"puck_ids": {"abc": 3}})


def test_markers_taken_for_one_puck_are_named_once(caplog):
    # puck_ids {"1": 2} with markers 1 and 2 both on the table: one puck was silently gone
    tr = plugin.build_tracker(plugin.complete({"puck_ids": {"1": 2}}))
    seen = (PuckMeasurement(1, 0.3, 0.3, 0.0, 0.0), PuckMeasurement(2, 0.9, 0.5, 0.0, 0.0))
    with caplog.at_level("WARNING", logger="tabletop"):
        for k in range(3):
            pucks = tr.update([Observation("camera", k / 60, k, pucks=seen)], k / 60)
    assert [p.id for p in pucks] == [2]
    said = [r.getMessage() for r in caplog.records]
    assert said == ["camera: markers 1 and 2 are each taken for puck 2 (tracking.puck_ids); the "
                    "tracker follows one of them: give each marker on the table its own puck"]
    caplog.clear()
    with caplog.at_level("WARNING", logger="tabletop"):   # one marker per puck: nothing said
        tr.update([Observation("camera", 0.1, 9, pucks=seen[:1])], 0.1)
    assert not caplog.records


def test_a_fresh_tracker_finds_every_marker_of_a_tilted_camera_in_its_first_frame():
    """The full-frame pass of the configured tracker (ArUco3 on by default) finds the far
    corner's markers (37 px on a side, 1280x720 camera tilted 14 degrees) in its very first
    frame, with no other marker known: a puck put down alone there is seen at once."""
    from tabletop.calibration_scenes import table_rig
    from tabletop.plugins.tracking import build_detector
    from tracking.rig import marker_layout
    for seed in (3, 5, 8):
        rig = table_rig(seed)
        rig.pucks = marker_layout(rig.camera.s.table)
        rig.show(None)
        ids, _ = build_detector({}).detect(rig.grab(), {})
        assert sorted(int(i) for i in ids) == list(range(12)), (seed, sorted(ids))


def test_named_pucks_keep_other_ids_off_the_table_but_the_studio_control_markers():
    """``pucks`` names the pucks (after ``puck_ids``): a reading of another id is no puck;
    ids ``also`` (the studio's control markers) pass. Unnamed, every id read is a puck."""
    seen = tuple(PuckMeasurement(i, 0.1 * i, 0.2, 0.0, 0.0) for i in (17, 5, 46))
    obs = Observation("cam", 0.0, 1, pucks=seen)
    named = plugin.complete({"pucks": [1], "puck_ids": {"17": 1}})
    assert [p.id for p in plugin.build_tracker(named, None, [46]).update([obs], 0.0)] == [1, 46]
    every = plugin.build_tracker(plugin.complete({"puck_ids": {"17": 1}}), None, [46])
    assert [p.id for p in every.update([obs], 0.0)] == [1, 5, 46]
    with pytest.raises(ConfigError, match=r"tracking.pucks\[0\]"):
        plugin.complete({"pucks": ["one"]})


def test_a_stray_marker_on_the_table_is_no_puck_when_the_pucks_are_named():
    """Rendered frames through the real detector: pucks 1 and 2 and a stray marker 7 (another
    installation's puck, a print). Named pucks [1, 2]: 7 is never shown (unnamed: on every
    frame)."""
    cam = SyntheticCamera(CameraSettings(blur_sigma=0.8, noise_sigma=3.0, seed=2))
    pipe = CameraPipeline(cam, plugin.tracker_settings({"pucks": [1, 2]}))
    shown = set()
    for k in range(10):
        frame = cam.render([(1, 0.3, 0.3, 0.0), (2, 0.8, 0.5, 1.0), (7, 0.6, 0.2, 2.0)], k / 30)
        shown |= {p.id for p in pipe.process(frame)}
    assert shown == {1, 2}
