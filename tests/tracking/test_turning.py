"""Constant turn-rate coasting (tracking.turning)."""

from __future__ import annotations

import math

import pytest

from tracking.turning import extend_trail, turn_sample, turned_travel


def test_a_turning_velocity_without_fading_travels_along_its_circle():
    """1 m/s turning at 10 rad/s: a circle of 0.1 m; after a quarter turn the puck is 0.1 m
    along and 0.1 m across (a straight line would put it 0.157 m along)."""
    dx, dy = turned_travel(1.0, 0.0, 10.0, math.pi / 20.0, 1e9)
    assert dx == pytest.approx(0.1, abs=1e-6) and dy == pytest.approx(0.1, abs=1e-6)
    assert turned_travel(1.0, 0.0, 0.0, 0.3, 0.3) == pytest.approx(
        (0.3 * (1.0 - math.exp(-1.0)), 0.0))


def test_the_rate_of_turn_of_a_circle_is_measured_from_three_readings_at_any_spacing():
    w, r = 16.7, 0.09   # 1.5 m/s on a 9 cm circle
    for times in ([0.0, 1 / 60, 2 / 60], [0.0, 0.03, 0.1], [0.0, 0.1, 0.13]):
        trail = [(t, r * math.cos(w * t), r * math.sin(w * t)) for t in times]
        assert turn_sample(trail, 0.1) == pytest.approx(w, rel=1e-9)


def test_a_reversal_is_no_turn_and_a_still_puck_does_not_turn():
    assert turn_sample([(0.0, 0.0, 0.0), (0.05, 0.04, 0.0), (0.1, 0.0, 0.0)], 0.1) is None
    assert turn_sample([(0.0, 0.0, 0.0), (0.05, 0.001, 0.0), (0.1, 0.001, 0.001)], 0.1) == 0.0


def test_the_trail_keeps_the_last_tenth_of_a_second_or_the_last_two_readings():
    trail = []
    for k in range(10):
        trail = extend_trail(trail, k / 60, 0.0, 0.0)
    assert [round(p[0] * 60) for p in trail] == [3, 4, 5, 6, 7, 8, 9]
    assert len(extend_trail(trail, 0.35, 0.0, 0.0)) == 3       # sparse: the last two kept
    assert len(extend_trail(trail[-1:], 0.9, 0.0, 0.0)) == 1   # too far apart: none

