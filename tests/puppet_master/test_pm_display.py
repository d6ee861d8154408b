"""The reactor as displayed between generation steps (engine.Reactor.update): a 60 Hz frame
moves it no farther than the demonstration's largest step, on the bus as in the view."""

import numpy as np
import pytest

from tests.puppet_master.test_plugin import build, run, visitor_frames


@pytest.mark.parametrize("name", ["bully", "afraid"])
def test_a_displayed_frame_never_jumps_past_the_largest_demonstrated_step(name):
    # moved on by the latest step's velocity, the displayed reactor overshot where the next
    # step turned and came back: on this visitor (40 s at 60 Hz) the bully moved up to 1.3x
    # its largest demonstrated step (1.5 frames' time) in one frame, the afraid one 1.5x
    (e,) = build([{"kind": "puppet_master", "name": name,
                   "behavior": f"behaviors/library/{name}"}])
    out = run([e], visitor_frames(40))[name]
    assert out[:, 3].all()
    moved = np.hypot(*np.diff(out[:, :2], axis=0).T)
    largest = e.behavior.largest_step
    # measured: at most 0.49 (bully) and 0.55 (afraid) of it; 40 Hz steps in 60 Hz frames
    # move 2/3 of a step a frame at the most
    assert moved.max() <= largest, (moved.max(), largest)
