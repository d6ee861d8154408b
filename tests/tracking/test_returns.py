"""A puck lifted and put back elsewhere, read by OpenCV on rendered frames: once a second reading
at the same place confirms it, the shown pose is where the puck lies, whether it is read every
frame or every other; one reading alone (it may be false) does not put it there."""

from __future__ import annotations

import math

import pytest

from tabletop.frames import PuckMeasurement
from tracking.pucks import PuckTracker
from tracking.scenes import CameraPipeline
from tracking.hands import Occluder
from tracking.synthetic import CameraSettings, SyntheticCamera

FPS = 30.0


def _shown_after_return(every: int) -> list[float]:
    """Errors (m) of the shown pose at each reading after a still puck, hidden from 0.2 to
    0.5 s, is put back 0.14 m away and read on every ``every``-th frame."""
    cam = SyntheticCamera(CameraSettings(blur_sigma=0.8, noise_sigma=3.0, seed=5))
    pipe = CameraPipeline(cam)
    errors = []
    for k in range(int(0.8 * FPS)):
        t = k / FPS
        back = t >= 0.5
        x, y = 0.5, 0.3 + (0.14 if back else 0.0)
        drawn = not (0.2 <= t < 0.5) and not (back and k % every)
        pucks = pipe.process(cam.render([(3, x, y, 0.7)] if drawn else [], t))
        if back and drawn and pucks[0].state == "seen":   # read (a crop may miss it)
            errors.append(math.hypot(pucks[0].x - x, pucks[0].y - y))
    return errors


@pytest.mark.parametrize("every", [1, 2])
def test_a_puck_put_back_elsewhere_is_shown_where_it_is_from_its_second_reading(every):
    """Measured: 0.13 m off at the first reading, then under 0.2 mm (every frame, the shown
    pose had crept 1 cm a reading: still 20 mm off after 12 readings; every other frame it
    reached the puck after 4)."""
    errors = _shown_after_return(every)
    assert len(errors) >= 3 and errors[0] > 0.12
    assert max(errors[1:]) < 0.002, errors


def test_one_far_reading_after_a_coast_does_not_put_the_puck_there():
    """A false reading of a coasting puck's id 0.5 m away (inside the gate, which has grown
    with the time unseen) leaves the shown pose 0.14 m short of it; the puck read again where
    it was (relocated by two consistent readings) is shown there at once (crept back a step a
    frame, it was 0.33 m off)."""
    tr = PuckTracker()
    for k in range(10):
        tr.step([PuckMeasurement(1, 0.3, 0.4, 0.0, k / FPS)], k / FPS)
    for k in range(10, 16):
        tr.step([], k / FPS)
    p = tr.step([PuckMeasurement(1, 0.8, 0.4, 0.0, 16 / FPS)], 16 / FPS)[0]
    assert p.raw_x == pytest.approx(0.8) and 0.66 - 1e-9 <= p.x < 0.67
    for k in range(17, 19):
        p = tr.step([PuckMeasurement(1, 0.3, 0.4, 0.0, k / FPS)], k / FPS)[0]
    assert p.state == "seen" and p.x == pytest.approx(0.3, abs=1e-9)


def _circling_under_a_hand(fps: float) -> tuple[list[float], list[float]]:
    """Errors (m) of the shown pose of a puck circling at 0.5 m/s (radius 0.09 m) while a hand
    covers it from 0.3 to 0.6 s: at each coasting frame, and at each reading after."""
    cam = SyntheticCamera(CameraSettings(blur_sigma=0.8, noise_sigma=3.0, seed=3,
                                         exposure_s=0.002))
    pipe = CameraPipeline(cam)
    w = 0.5 / 0.09
    coasting, after = [], []
    for k in range(int(0.9 * fps)):
        t = k / fps
        x, y = 0.5 + 0.09 * math.cos(w * t), 0.4 + 0.09 * math.sin(w * t)
        vel = (-0.5 * math.sin(w * t), 0.5 * math.cos(w * t))
        hand = (Occluder(x + 0.02, y + 0.01, 0.3),) if 0.3 <= t < 0.6 else ()
        pucks = pipe.process(cam.render([(2, x, y, 0.4)], t, [vel], hand))
        err = math.hypot(pucks[0].x - x, pucks[0].y - y)
        if pucks[0].state == "coasting":
            coasting.append(err)
        elif t >= 0.6:
            after.append(err)
    return coasting, after


@pytest.mark.parametrize("fps", [30.0, 60.0])
def test_a_circling_puck_under_a_hand_coasts_along_its_circle(fps):
    """Coasting turns with the puck's measured rate of turn. Measured: at most 53-55 mm off
    while hidden (on its tangent, 118-122 mm) and 50-58 mm at its first reading."""
    coasting, after = _circling_under_a_hand(fps)
    assert len(coasting) >= 5 and max(coasting) < 0.07, coasting
    assert after[0] < 0.07, after


@pytest.mark.parametrize("fps", [30.0, 60.0])
def test_a_moving_puck_back_from_under_a_hand_is_shown_where_it_is_from_its_second_reading(
        fps):
    """Measured: under 0.1 mm at the second reading, then the filter's lag, under 4 mm (crept
    back a step a reading, it was 108-129 mm off at the third)."""
    coasting, after = _circling_under_a_hand(fps)
    assert len(after) >= 6 and max(after[1:]) < 0.006, after
