"""A print of a puck's marker on the table (tracking.rivals), seen through the real detector
on rendered frames: the puck is the place that moves with the visitor's hand."""

from __future__ import annotations

import math

import pytest

from tracking.hands import Occluder
from tracking.rivals import follow
from tracking.scenes import CameraPipeline
from tracking.synthetic import CameraSettings, SyntheticCamera

PRINT = (2, 0.9, 0.6, 1.0)   # a copy of puck 2's marker lying on the table
W = 0.5 / 0.09               # rad/s: 0.5 m/s on a 9 cm circle


def _errors(fps: float, scene, seconds: float) -> list[float]:
    """Error (m) of puck 2's shown pose at every frame (inf when it is not shown)."""
    cam = SyntheticCamera(CameraSettings(blur_sigma=0.8, noise_sigma=3.0, seed=3,
                                         exposure_s=0.002))
    pipe = CameraPipeline(cam)
    errors = []
    for k in range(int(seconds * fps)):
        t = k / fps
        poses, vels, hands = scene(t)
        pucks = {p.id: p for p in pipe.process(cam.render(poses, t, vels, hands))}
        p = pucks.get(2)
        errors.append(math.hypot(p.x - poses[0][1], p.y - poses[0][2]) if p else math.inf)
    return errors


def _moved_from_beside_the_print(t: float):
    """Puck and print lie still from the start; the visitor moves the puck at 0.4 m/s from
    0.3 s."""
    s = 0.4 * max(t - 0.3, 0.0)
    return [(2, 0.3 + s, 0.3, 0.2), PRINT], [(0.4 if t > 0.3 else 0.0, 0.0), (0.0, 0.0)], ()


def _circling_hidden_by_a_hand(t: float):
    """The print is under a hand at first; the puck circles and a hand hides it 0.5-0.8 s."""
    x, y = 0.4 + 0.09 * math.cos(W * t), 0.4 + 0.09 * math.sin(W * t)
    hands = (Occluder(0.92, 0.61, 0.3),) if t < 0.3 else ()
    if 0.5 <= t < 0.8:
        hands = (Occluder(x + 0.02, y + 0.01, 0.3),)
    vel = (-0.5 * math.sin(W * t), 0.5 * math.cos(W * t))
    return [(2, x, y, 0.4), PRINT], [vel, (0.0, 0.0)], hands


@pytest.mark.parametrize("fps", [30.0, 60.0])
def test_the_puck_moved_away_from_a_print_of_its_marker_is_shown_under_the_hand(fps):
    """The track starts on the print (nothing tells the two apart while both lie still). Once
    the puck has moved a gate's width (6 cm, 0.15-0.2 s) it is taken. Measured: at most 5-11 mm
    off from 0.6 s on (held by the print, 0.47-0.57 m)."""
    errors = _errors(fps, _moved_from_beside_the_print, 0.9)
    assert max(errors[int(0.6 * fps):]) < 0.02, errors


@pytest.mark.parametrize("fps", [30.0, 60.0])
def test_a_print_read_while_a_moving_puck_is_hidden_does_not_take_its_track(fps):
    """Measured: at most 53-57 mm off while it coasts hidden, under 4 mm from 0.9 s on
    (relocated to the print after two readings, it was 0.47-0.63 m off from then on)."""
    errors = _errors(fps, _circling_hidden_by_a_hand, 1.1)
    assert max(errors) < 0.07, errors
    assert max(errors[int(0.9 * fps):]) < 0.01, errors


def test_a_rival_is_followed_within_its_reach_and_counts_its_moves_from_a_still_track():
    r = follow(None, 0.5, 0.5, 0.0, 0.1, [0.0, 0.0], 0.06)
    r = follow(r, 0.55, 0.5, 0.1, 0.1, [0.01, 0.0], 0.06)
    assert r.moved() == pytest.approx(0.05)
    r = follow(r, 0.6, 0.5, 0.2, 0.1, [0.2, 0.0], 0.06)    # the track moved: counted anew
    assert r.moved() == pytest.approx(0.05) and (r.tx, r.ty) == (0.2, 0.0)
    assert follow(r, 0.9, 0.5, 0.3, 0.1, [0.2, 0.0], 0.06).moved() == 0.0   # out of reach
