"""A mirror image that is another template performed with its own holds: not an unrelated motion
to ``bench/follow_quality.py`` (``bench.motions.mirror_copies``), and followed as that template.
"""

import numpy as np
import pytest

from bench.follow_quality import puck_follower, run
from bench.motions import (ALIGNED_GAP_M, _path_gap, aligned_gap, mocap_templates, performance,
                           unrelated_motions)


@pytest.fixture(scope="module")
def punch_ankle() -> np.ndarray:
    """The punch's left ankle (held out): out to the left, held at its far end, most of the way
    back."""
    return mocap_templates(joints=(("punch", "left_ankle"),))["punch_left_ankle"]


def test_a_mirrored_template_that_is_another_held_is_not_unrelated(gestures, punch_ankle):
    line, circle = gestures["line"], gestures["circle"]
    mirrored = punch_ankle * np.array([-1.0, 1.0])
    # measured: 0.045 m apart at equal phase (the ankle holds at its far end), 0.0115 aligned
    assert _path_gap(mirrored, line) > 0.03
    assert aligned_gap(mirrored, line) <= ALIGNED_GAP_M
    paths = unrelated_motions(np.random.default_rng(0),
                              {"line": line, "punch_left_ankle": punch_ankle, "circle": circle})
    assert "mirrored_punch_left_ankle" not in paths and "mirrored_line" not in paths
    assert "mirrored_circle" in paths   # (a circle drawn the other way round)


def test_the_mirrored_punch_ankle_is_followed_as_the_line_held(gestures, punch_ankle):
    # what the held-out bench counted as unrelated (valid 0.247 among twenty): the line drawn
    # out, held, and back three quarters of the way; measured here at 1.0x: valid 0.47 of the
    # time, the line's alone, at 0.46 at the far point and 0.79 at the end
    f = puck_follower({"line": gestures["line"], "punch_left_ankle": punch_ankle})
    x, _ = performance(np.random.default_rng(5), punch_ankle * np.array([-1.0, 1.0]), 1.0)
    states = run(f, x)
    valid = [s for s in states if s.valid]
    assert len(valid) >= 0.3 * len(states) and {s.best for s in valid} == {"line"}
    far = int(np.argmax(x[:, 0]))
    assert 0.4 <= states[far].progress_by["line"] <= 0.6
    assert states[-1].progress_by["line"] >= 0.7
