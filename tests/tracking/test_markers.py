"""Marker detection on rendered synthetic frames with ground truth."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tracking.markers import (DetectorSettings, detect_markers, dictionary_by_name,
                              make_detector, marker_centres, marker_poses, refine_corners,
                              track_corners, verify_markers)
from tracking.scenes import grid_poses, moving_scene, score_detections
from tracking.synthetic import Occluder
from tracking.synthetic import CameraSettings, SyntheticCamera


def _score(frames, detect):
    return score_detections(frames, [detect(f.image) for f in frames])


@pytest.fixture(scope="module")
def blurred_frames():
    cam = SyntheticCamera(CameraSettings(resolution=(1280, 720), blur_sigma=0.8, noise_sigma=3.0,
                                         exposure_s=0.01, seed=3))
    return [cam.render(p, t, v) for t, p, v in moving_scene(16, 12, 30.0, speed=0.4, seed=2)]


def test_detection_rate_and_accuracy_at_720p_with_blur_noise_and_motion_blur(blurred_frames):
    det = make_detector(DetectorSettings(corner_refinement="none"))

    def detect(img):
        ids, corners = detect_markers(img, det)
        return ids, refine_corners(img, corners)

    rate, errs, heads, false_ids = _score(blurred_frames, detect)
    assert rate >= 0.99
    assert np.median(errs) <= 0.5
    assert np.percentile(errs, 95) <= 1.5
    assert math.degrees(np.median(heads)) <= 1.0
    assert false_ids == 0


def test_refinement_beats_integer_corners(blurred_frames):
    det = make_detector(DetectorSettings(corner_refinement="none"))
    _, raw, _, _ = _score(blurred_frames[:4], lambda img: detect_markers(img, det))
    _, ref, _, _ = _score(blurred_frames[:4], lambda img: (
        lambda ids, c: (ids, refine_corners(img, c)))(*detect_markers(img, det)))
    assert np.median(ref) < np.median(raw)


def test_apriltag_dictionary_detects_its_own_markers():
    cam = SyntheticCamera(CameraSettings(dictionary="DICT_APRILTAG_36h11",
                                         seed=1))
    poses = grid_poses(6, seed=4, first_id=100)
    f = cam.render(poses)
    det = make_detector(DetectorSettings(dictionary="DICT_APRILTAG_36h11"))
    ids, corners = detect_markers(f.image, det)
    assert sorted(ids.tolist()) == list(range(100, 106))
    order = [int(np.flatnonzero(ids == i)[0]) for i in f.ids]
    assert np.max(np.hypot(*(marker_centres(corners[order]) - f.centres).T)) <= 1.0


def test_other_dictionary_reads_no_false_ids():
    cam = SyntheticCamera(CameraSettings(dictionary="DICT_6X6_250", seed=5))
    f = cam.render(grid_poses(12, seed=5))
    ids, _ = detect_markers(f.image, make_detector(DetectorSettings(dictionary="DICT_4X4_50")))
    assert len(ids) == 0


def test_pose_convention_centre_and_heading():
    # A square with c0 -> c1 along +x (image) has heading 0; rotated by +90 deg (image y down).
    sq = np.array([[[10.0, 10.0], [20.0, 10.0], [20.0, 20.0], [10.0, 20.0]]])
    p = marker_poses(sq)[0]
    assert p[:2] == pytest.approx([15.0, 15.0]) and p[2] == pytest.approx(0.0)
    rot = np.array([[[20.0, 10.0], [20.0, 20.0], [10.0, 20.0], [10.0, 10.0]]])
    assert marker_poses(rot)[0, 2] == pytest.approx(math.pi / 2)
    # Under perspective the diagonal intersection differs from the corner mean.
    trap = np.array([[[0.0, 0.0], [10.0, 0.0], [8.0, 10.0], [2.0, 10.0]]])
    c = marker_centres(trap)[0]
    assert abs(c[0] - 5.0) < 1e-9 and c[1] != pytest.approx(5.0)


def test_unknown_dictionary_is_refused_by_name():
    with pytest.raises(ValueError, match="DICT_NOPE"):
        dictionary_by_name("DICT_NOPE")


def _moved(poses, dx, dy, da=0.0):
    return [(i, x + dx, y + dy, a + da) for i, x, y, a in poses]


def test_known_marker_moved_a_few_pixels_is_refined_and_verified_without_detection():
    cam = SyntheticCamera(CameraSettings(resolution=(1280, 720), blur_sigma=0.8, noise_sigma=3.0,
                                         seed=6))
    poses = grid_poses(9, seed=6)
    before = cam.render(poses)
    step = 2.0 / cam.pixels_per_metre()  # about 2 pixels each way
    after = cam.render(_moved(poses, step, -step, 0.02))
    # Start from the true corners of the earlier frame: no detection on the new one.
    corners, ok = track_corners(after.image, before.corners)
    assert ok.all()
    assert verify_markers(after.image, after.ids, corners, dictionary_by_name("DICT_4X4_50")).all()
    errs = np.hypot(*(marker_centres(corners) - after.centres).T)
    assert np.median(errs) <= 0.5 and errs.max() <= 1.5


def test_covered_replaced_or_misnamed_marker_fails_verification():
    cam = SyntheticCamera(CameraSettings(resolution=(1280, 720), seed=8))
    d = dictionary_by_name("DICT_4X4_50")
    poses = grid_poses(6, seed=8)
    f = cam.render(poses)
    assert verify_markers(f.image, f.ids, f.corners, d).all()
    # Every marker read under another id of the dictionary fails.
    for shift in (1, 7, 23):
        assert not verify_markers(f.image, (f.ids + shift) % 50, f.corners, d).any()
    # A hand over marker 0, and marker 1 swapped for marker 40 at the same pose.
    _, x, y, _ = poses[0]
    swapped = [(40 if i == 1 else i, px, py, a) for i, px, py, a in poses]
    g = cam.render(swapped, occluders=[Occluder(x - 0.02, y, 0.0, 0.12)])
    corners, ok = track_corners(g.image, f.corners)
    verified = ok.copy()
    verified[ok] = verify_markers(g.image, f.ids[ok], corners[ok], d)
    assert verified.tolist() == [False, False, True, True, True, True]


def test_apriltag_markers_verify_under_their_own_ids_only():
    cam = SyntheticCamera(CameraSettings(dictionary="DICT_APRILTAG_36h11", seed=1))
    f = cam.render(grid_poses(6, seed=4, first_id=100))
    d = dictionary_by_name("DICT_APRILTAG_36h11")
    assert verify_markers(f.image, f.ids, f.corners, d).all()
    assert not verify_markers(f.image, f.ids + 1, f.corners, d).any()


def test_marker_patterns_follow_their_dictionary_after_another_is_freed():
    """Patterns are remembered per dictionary object; a dictionary made after another was freed
    (it may get the same id) still gets its own patterns. A dictionary is freed by ``del``
    (reference counting: no cycle to collect), so the next one made may take its id."""
    from tracking.markers import dictionary_by_name, marker_pattern
    for _ in range(20):
        small = dictionary_by_name("DICT_4X4_50")
        assert marker_pattern(small, 3).shape == (6, 6)
        del small
        big = dictionary_by_name("DICT_APRILTAG_36h11")
        assert marker_pattern(big, 3).shape == (8, 8)
        del big
