"""Puck tracker: jitter, lag, occlusion, reappearance, duplicates, velocities."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tabletop.frames import Observation, PuckMeasurement, wrap_angle
from tracking.pucks import PuckTracker, TrackerSettings
from tracking.scenes import CameraPipeline, grid_poses
from tracking.synthetic import CameraSettings, Occluder, SyntheticCamera

FPS = 30.0


@pytest.fixture
def cam():
    return SyntheticCamera(CameraSettings(resolution=(1280, 720), blur_sigma=0.8,
                                          noise_sigma=3.0, seed=11))


def test_still_puck_filtered_std_at_least_five_times_smaller_than_raw(cam):
    pipe = CameraPipeline(cam)
    poses = grid_poses(4, seed=3)
    raw, smooth = [], []
    for k in range(120):
        pucks = pipe.process(cam.render(poses, k / FPS))
        p = [q for q in pucks if q.id == 0][0]
        assert p.state == "seen"
        raw.append((p.raw_x, p.raw_y))
        smooth.append((p.x, p.y))
    raw, smooth = np.array(raw[30:]), np.array(smooth[30:])
    assert np.hypot(*raw.std(axis=0)) > 0  # the measurement really jitters
    assert np.hypot(*smooth.std(axis=0)) * 5 <= np.hypot(*raw.std(axis=0))


def test_moving_puck_lags_less_than_10ms(cam):
    pipe = CameraPipeline(cam)
    v = 0.5
    lags = []
    for k in range(60):
        t = k / FPS
        x = 0.1 + v * t
        f = cam.render([(5, x, 0.4, 0.3)], t, velocities=[(v, 0.0)])
        p = pipe.process(f)[0]
        if k >= 40:
            lags.append((x - p.x) / v)
            assert p.vx == pytest.approx(v, abs=0.05) and abs(p.vy) < 0.05
    assert abs(np.median(lags)) < 0.010


def _run_occlusion(cam, covered_s, pipe=None):
    pipe = pipe or CameraPipeline(cam)
    states, visible = [], []
    x, y = 0.6, 0.4
    start = int(0.5 * FPS)
    stop = start + int(round(covered_s * FPS))
    for k in range(stop + 12):
        hand = [Occluder(x - 0.03, y, 0.0, 0.13)] if start <= k < stop else []
        f = cam.render([(7, x, y, 1.0), (8, 0.2, 0.2, 0.0)], k / FPS, occluders=hand)
        pucks = {p.id: p for p in pipe.process(f)}
        states.append(pucks[7].state if 7 in pucks else None)
        visible.append(bool(f.visible[0]))
    return states, visible, pipe


def _first_visible_after_cover(visible):
    k = visible.index(False)
    return k + visible[k:].index(True)


def test_covered_for_0_3_s_coasts_then_is_seen_within_3_frames(cam):
    states, visible, _ = _run_occlusion(cam, 0.3)
    back = _first_visible_after_cover(visible)
    for s, vis in zip(states, visible):
        if not vis:
            assert s == "coasting"  # predicted the whole time, never seen
    assert "seen" in states[back:back + 3]


def test_covered_for_1_s_is_dropped_then_found_within_3_frames(cam):
    states, visible, _ = _run_occlusion(cam, 1.0)
    back = _first_visible_after_cover(visible)
    hidden = [s for s, v in zip(states, visible) if not v]
    assert "seen" not in hidden and "coasting" in hidden and hidden[-1] is None
    assert "seen" in states[back:back + 3]


def test_puck_leaving_the_image_and_coming_back_is_found_within_3_frames(cam):
    pipe = CameraPipeline(cam)
    path = [(0.6 - 0.03 * k, 0.4) for k in range(30)]  # slides out past the left edge
    path += [(-0.3, 0.4)] * 20 + [(1.0, 0.6)] * 8      # away, then put down elsewhere
    states, visible = [], []
    for k, (x, y) in enumerate(path):
        f = cam.render([(3, x, y, 0.5)], k / FPS, velocities=[(-0.9, 0.0)] if k < 30 else None)
        pucks = {p.id: p for p in pipe.process(f)}
        states.append(pucks[3].state if 3 in pucks else None)
        visible.append(bool(f.visible[0]))
    back = len(path) - 8
    assert not any(s == "seen" for s, v in zip(states, visible) if not v)
    assert visible[back] and "seen" in states[back:back + 3]


def test_duplicate_false_detection_far_from_the_track_does_not_move_the_puck():
    tr = PuckTracker(TrackerSettings(smooth=False))
    for k in range(10):
        t = k / FPS
        ms = [PuckMeasurement(1, 0.5 + 0.1 * t, 0.3, 0.2, t)]
        if k >= 5:  # a false reading of the same id elsewhere, listed first
            ms.insert(0, PuckMeasurement(1, 1.0, 0.7, -2.0, t))
        p = tr.step(ms, t)[0]
        assert p.x == pytest.approx(0.5 + 0.1 * t) and p.y == pytest.approx(0.3)
        assert p.state == "seen"
    # A lone far reading (the real one hidden) is ignored: the puck coasts.
    p = tr.step([PuckMeasurement(1, 0.05, 0.75, 0.0, 10 / FPS)], 10 / FPS)[0]
    assert p.state == "coasting" and abs(p.x - 0.5 - 0.1 * 10 / FPS) < 0.01


def test_a_puck_really_moved_far_is_relocated_after_consistent_sightings():
    tr = PuckTracker()
    tr.step([PuckMeasurement(2, 0.2, 0.2, 0.0, 0.0)], 0.0)
    states = []
    for k in range(1, 6):
        t = k / FPS
        p = tr.step([PuckMeasurement(2, 1.0, 0.6, 0.0, t)], t)[0]
        states.append(p.state)
        assert p.raw_x == pytest.approx(1.0) or p.state == "coasting"
    assert states[0] == "coasting" and states[1] == "seen"


def test_reappearing_puck_reports_measurement_at_once_moves_a_step_then_is_shown_there():
    """Put back 6 cm away: the first reading (it may be false) moves the shown pose 1 cm
    (``reacquire_step_m``); a second reading at the same place confirms it and the puck is
    shown where it lies."""
    tr = PuckTracker()
    t = 0.0
    for k in range(10):
        t = k / FPS
        tr.step([PuckMeasurement(4, 0.4, 0.4, 0.0, t)], t)
    for k in range(10, 15):  # hidden
        t = k / FPS
        assert tr.step([], t)[0].state == "coasting"
    prev = tr.pucks[0]
    for k in range(15, 30):  # back 6 cm away
        t = k / FPS
        p = tr.step([PuckMeasurement(4, 0.46, 0.4, 0.3, t)], t)[0]
        assert p.state == "seen" and p.raw_x == pytest.approx(0.46)
        if k == 15:
            assert math.hypot(p.x - prev.x, p.y - prev.y) <= 0.01 + 1e-9
        else:
            assert p.x == pytest.approx(0.46, abs=1e-9) and p.angle == pytest.approx(0.3)


def test_coasting_prediction_decays_and_expires():
    tr = PuckTracker(TrackerSettings(coast_s=0.5))
    for k in range(10):
        t = k / FPS
        tr.step([PuckMeasurement(9, 0.3 + 0.5 * t, 0.4, 0.1 * k, t)], t)
    last = tr.pucks[0]
    assert last.vx == pytest.approx(0.5, abs=0.05) and last.omega == pytest.approx(3.0, abs=0.3)
    xs = []
    for k in range(10, 40):
        t = k / FPS
        pucks = tr.step([], t)
        if t - 9 / FPS <= 0.5:
            assert pucks[0].state == "coasting"
            xs.append(pucks[0].x)
        else:
            assert pucks == ()
    steps = np.diff(xs)
    assert np.all(steps > 0) and steps[-1] < steps[0] / 2  # moving on, slowing down


def test_update_ignores_repeated_observations_and_tracks_each_source():
    tr = PuckTracker()
    obs_a = Observation("a", 0.0, 1, pucks=(PuckMeasurement(1, 0.1, 0.1, 0.0, 0.0),))
    obs_b = Observation("b", 0.0, 1, pucks=(PuckMeasurement(2, 0.9, 0.5, 0.0, 0.0),))
    assert [p.id for p in tr.update([obs_a, obs_b], 0.0)] == [1, 2]
    # Source a has nothing new; b delivers a frame without puck 1: puck 1 is still seen.
    obs_b2 = Observation("b", 0.03, 2, pucks=(PuckMeasurement(2, 0.9, 0.5, 0.0, 0.03),))
    pucks = tr.update([obs_a, obs_b2], 0.03)
    assert [p.state for p in pucks] == ["seen", "seen"]
    # Source a delivers a frame without puck 1: coasting.
    obs_a2 = Observation("a", 0.06, 2)
    assert tr.update([obs_a2, obs_b2], 0.06)[0].state == "coasting"
    # A source gone quiet: its pucks stop being seen, then expire.
    assert tr.update([obs_a2, obs_b2], 0.4)[-1].state == "coasting"
    assert tr.update([obs_a2, obs_b2], 1.0) == ()


def test_a_frame_published_again_with_more_pucks_adds_only_those():
    """A camera publishes a frame again (same seq and time) with the pucks a put-off search
    added: the tracker takes the new pucks at once and leaves the others as the first
    publication set them (a coasting puck found again is seen; nothing is applied twice)."""
    tr = PuckTracker(TrackerSettings(smooth=False))
    first = Observation("cam", 0.0, 1, pucks=(PuckMeasurement(1, 0.1, 0.1, 0.0, 0.0),
                                              PuckMeasurement(2, 0.5, 0.5, 0.0, 0.0)))
    tr.update([first], 0.0)
    quick = Observation("cam", 0.05, 2, pucks=(PuckMeasurement(1, 0.11, 0.1, 0.0, 0.05),))
    assert [p.state for p in tr.update([quick], 0.05)] == ["seen", "coasting"]
    again = Observation("cam", 0.05, 2, pucks=quick.pucks + (
        PuckMeasurement(2, 0.5, 0.52, 0.0, 0.05), PuckMeasurement(3, 0.9, 0.3, 0.0, 0.05)))
    pucks = tr.update([again], 0.05)
    assert [(p.id, p.state) for p in pucks] == [(1, "seen"), (2, "seen"), (3, "seen")]
    assert pucks[1].raw_y == 0.52 and pucks[2].raw_x == 0.9
    before = tr.tracks[1].t, tr.tracks[1].meas
    assert tr.update([again], 0.06) == pucks   # nothing new: the same pucks
    assert (tr.tracks[1].t, tr.tracks[1].meas) == before


def test_a_measurement_older_than_the_track_is_ignored():
    tr = PuckTracker(TrackerSettings(smooth=False))
    tr.step([PuckMeasurement(1, 0.5, 0.5, 0.0, 1.0)], 1.0, source="a")
    p = tr.update([Observation("b", 0.9, 1, pucks=(PuckMeasurement(1, 0.52, 0.5, 0.0, 0.9),),
                               complete=False)], 1.0)[0]
    assert p.raw_x == 0.5 and p.state == "seen"


def test_a_measured_velocity_beyond_belief_is_held_to_the_fastest_plausible_puck():
    """A source's own velocity (a TUIO sender's) is taken as measured, but one of 1e30 m/s
    (a sender's bug) would carry the prediction off the table: the next true positions fell
    outside the gate and the coasting puck flew away. It is held to ``max_speed`` (m/s) and
    the rotation to MAX_OMEGA."""
    from tracking.pucks import MAX_OMEGA
    s = TrackerSettings(smooth=False)
    tr = PuckTracker(s)
    for k in range(6):
        t = k / FPS
        p = tr.step([PuckMeasurement(3, 0.5, 0.4, 0.0, t, vx=1e30, vy=-1e30, omega=1e30)], t)[0]
        assert p.state == "seen" and p.x == pytest.approx(0.5), p
    assert math.hypot(p.vx, p.vy) == pytest.approx(s.max_speed) and p.omega == MAX_OMEGA
    p = tr.step([], 6 / FPS)[0]                       # hidden: coasts a plausible way
    assert p.state == "coasting" and abs(p.x - 0.5) < s.max_speed / FPS


def test_a_fast_puck_found_again_is_shown_where_it_is_from_its_second_reading():
    """A puck moving at 0.9 m/s (60 Hz) hidden for 0.3 s reappears about 12 cm from its shown
    pose. Its first reading moves the shown pose at most the puck's own step plus the reacquire
    step (1 cm) and keeps it within 0.15 m of the reading; the second reading confirms it and
    the puck is shown where it is, then behind it by the filter's lag (measured: 0 mm, then
    3.2-3.9 mm; crept back a step a frame, it was 116-119 mm off for the next 3 frames)."""
    tr, fps = PuckTracker(), 60.0
    errors, prev = [], None
    for k in range(80):
        t = k / fps
        x, y = 0.1 + 0.9 * t, 0.3 + 0.1 * math.sin(3 * t)
        p = tr.step([] if 30 <= k < 48 else [PuckMeasurement(1, x, y, 0.0, t)], t)[0]
        if k >= 48:
            errors.append(math.hypot(p.x - x, p.y - y))
        if k == 48:
            assert math.hypot(p.x - prev[0], p.y - prev[1]) <= 0.9 / fps * 1.05 + 0.01 + 0.003
        prev = (p.x, p.y)
    assert 0.1 < errors[0] <= 0.15 + 1e-9 and max(errors[1:]) < 0.005, errors


def test_puck_read_every_sixth_frame_under_blur_is_shown_near_where_it_is_read():
    """A puck at 1 m/s read at 60 Hz, then every 6th frame (motion blur): shown within 40 mm
    of each reading (measured 13.8 mm; taken as returns each time, 172 mm)."""
    tr, errs = PuckTracker(), []
    for k in range(60):
        t = k / 60.0
        x = 0.2 + 1.0 * t
        seen = k < 10 or k % 6 == 0
        p = tr.step([PuckMeasurement(1, x, 0.4, 0.0, t)] if seen else [], t)[0]
        if seen and k >= 10:
            errs.append(math.hypot(p.x - x, p.y - 0.4))
    assert max(errs) < 0.04


def test_a_coasting_puck_reports_the_velocity_it_is_shown_moving_at():
    """A puck on a 0.1 m circle at 1 m/s (60 Hz) hidden for 0.2 s: the reported velocity of the
    coasting puck turns with its shown pose. Measured: its direction within 0.5 deg of the
    puck's and of the shown pose's own motion (the chord between two frames, 4.8 deg back),
    its speed 2.7% under the chord's (it fades within the frame)."""
    tr, fps, r, w = PuckTracker(), 60.0, 0.1, 10.0
    prev = None
    for k in range(42):
        t = k / fps
        x, y = 0.5 + r * math.cos(w * t), 0.4 + r * math.sin(w * t)
        p = tr.step([] if k >= 30 else [PuckMeasurement(1, x, y, 0.0, t)], t)[0]
        if k > 30:
            heading = math.atan2(p.vy, p.vx)
            assert abs(wrap_angle(heading - (w * t + math.pi / 2))) < math.radians(1.0)
            chord = (p.x - prev[0], p.y - prev[1])
            turned = wrap_angle(heading - math.atan2(chord[1], chord[0]))
            assert abs(turned - 0.5 * w / fps) < math.radians(0.5)
            assert math.hypot(p.vx, p.vy) == pytest.approx(math.hypot(*chord) * fps, rel=0.035)
        prev = (p.x, p.y)
    assert p.state == "coasting"
