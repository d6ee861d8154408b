"""Where the character is drawn: a figure placed (``at``) near the table's edges is drawn whole on
the table, not cut by the edge."""

import numpy as np
import pytest

from behaviors.touch_pose.engine import TABLE_MARGIN


@pytest.mark.parametrize("at", [(0.6, 0.05), (0.6, 0.78), (0.0, 0.0), (1.2, 0.8), (0.02, 0.4)])
@pytest.mark.parametrize("view", [(90.0, 15.0), (0.0, 15.0), (30.0, 60.0)])
def test_a_figure_placed_at_the_edge_is_drawn_on_the_table(make, at, view):
    e = make(view=view, physics=False, at=at)
    e.step(0.0, {})
    pts = e.table_points()
    # the standing figure's points, at least TABLE_MARGIN (0.02 m) inside every edge
    # (at (0.6, 0.05), view 90,15, the feet were drawn at y = -0.091 m)
    assert pts.min(axis=0) == pytest.approx(np.maximum(pts.min(axis=0), TABLE_MARGIN), abs=1e-3)
    assert pts.max(axis=0) == pytest.approx(np.minimum(pts.max(axis=0), (1.2 - TABLE_MARGIN,
                                                                        0.8 - TABLE_MARGIN)),
                                            abs=1e-3)


def test_a_figure_that_fits_is_drawn_with_its_middle_at_its_place(make):
    e = make(physics=False, at=(0.5, 0.45))
    mid = e.camera.table(np.array([0.0, e.stand_height / 2, 0.0]))
    assert mid == pytest.approx([0.5, 0.45], abs=1e-9)
