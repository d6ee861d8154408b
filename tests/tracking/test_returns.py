"""A puck lifted and put back elsewhere, read by OpenCV on rendered frames: once a second reading
at the same place confirms it, the shown pose is where the puck lies, whether it is read every
frame or every other; one reading alone (it may be false) does not put it there."""

from __future__ import annotations

import math

import pytest

from tabletop.frames import PuckMeasurement
from tracking.pucks import PuckTracker
from tracking.scenes import CameraPipeline
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
