"""Which of the six example gestures any follower could recognise within 20% of them
(``bench/follow_sequences.py``'s construction figures, the ideal observer of
``bench/spotting_reach.py``)."""

import numpy as np
import pytest

from bench.follow_sequences import construction, opens, started_by
from bench.motions import gesture_templates
from bench.spotting_reach import straight_until


@pytest.fixture(scope="module")
def built():
    return construction(gesture_templates())


def test_a_path_is_straight_until_it_bends_off_its_chord():
    # 10 cm straight, then a quarter circle of 5 cm radius: 2 mm off the chord soon after the bend
    t = np.linspace(0, np.pi / 2, 50)
    bend = np.stack([0.1 + 0.05 * np.sin(t), 0.05 * (1 - np.cos(t))], 1)
    path = np.concatenate([np.stack([np.linspace(0, 0.1, 100), np.zeros(100)], 1), bend])
    at = straight_until(path, 0.002)
    assert 100 / 149 < at < 120 / 149, at
    assert straight_until(path[:100], 0.002) == 1.0


def test_the_line_and_the_square_cannot_be_told_apart_by_20_percent(built):
    # each is a start of the other at some size and tempo until 0.35 / 0.37 of it (2 mm)
    assert built["line"]["told_apart"] >= 0.3 and built["square"]["told_apart"] >= 0.3
    assert not opens(built["line"]) and not opens(built["square"])


def test_the_figure_eight_is_the_diagonal_until_past_20_percent(built):
    assert built["figure_eight"]["told_apart"] <= 0.2   # told from the other gestures
    assert built["figure_eight"]["told_from_unrelated"] > 0.2   # not from the diagonal
    assert not opens(built["figure_eight"])
    assert started_by(gesture_templates())["diagonal"] == {"figure_eight"}


def test_the_circle_zigzag_and_wave_are_open_at_20_percent(built):
    assert {g for g, b in built.items() if opens(b)} == {"circle", "zigzag", "wave"}
    # every gesture is still a straight stroke (within 2 mm at 1.2x) up to 0.2 of it
    assert all(b["straight_until"] >= 0.2 for b in built.values())
