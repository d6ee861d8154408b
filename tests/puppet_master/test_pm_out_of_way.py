"""A character steps out of the way a main faster than it was ever shown to move is about to
take (apart.out_of_way, in the Python step and the compiled one alike): it keeps its
disc round the main without stepping further than its largest demonstrated step."""

import numpy as np
import pytest

from behaviors.puppet_master import apart, generation_kernel
from tests.puppet_master.test_pm_never_jumps import fast_main_run


def test_the_way_ahead_of_a_fast_main_pushes_across_its_line():
    table = (0.0, 0.0, 1.2, 0.8)
    c = np.array(table)
    # a main at (0.3, 0.4) stepping 0.03 m along +x; the character's largest step 0.02 m and
    # disc 0.1 m: its way over the next 5 steps (0.15 m) widened by 0.1 m
    cases = [((0.4, 0.45), (0.4, 0.5)),      # beside its line: across it, to 0.1 m
             ((0.42, 0.4), (0.42, 0.5)),     # on its line: to the main's left
             ((0.42, 0.3999), (0.42, 0.3)),  # a hair to its right: the right
             ((0.5, 0.4), (0.55, 0.4)),      # ahead of the way's end: on ahead
             ((0.5, 0.55), (0.5, 0.55)),     # out of the way
             ((0.22, 0.42), (0.22, 0.42))]   # behind the main: its own disc (keep_apart)
    for (x, y), want in cases:
        got = apart.out_of_way(x, y, 0.3, 0.4, 0.03, 0.0, 0.1, 0.02, table)
        assert got == generation_kernel.out_of_way(x, y, 0.3, 0.4, 0.03, 0.0, 0.1, 0.02, c)
        assert np.allclose(got, want, atol=1e-12), ((x, y), got)
    # beside a main along the top edge: across only as far as the edge lets it
    got = apart.out_of_way(0.42, 0.79, 0.3, 0.75, 0.03, 0.0, 0.1, 0.02, table)
    assert np.allclose(got, (0.42, 0.8), atol=1e-12), got
    # a main no faster than the character's largest step: nothing (its disc is enough)
    assert apart.out_of_way(0.4, 0.45, 0.3, 0.4, 0.02, 0.0, 0.1, 0.02,
                                     table) == (0.4, 0.45)


# least distance to the main over its disc without the way ahead (given way at the largest step
# only once run into): stalker 0.21 / 0.66, afraid 0.50 / 0.73 / 0.77, lover 0.32; with it
# 1.14 / 1.11, 1.00 / 1.00 / 1.00, 0.87
@pytest.mark.parametrize("name, seed", [("stalker", 27), ("stalker", 30), ("afraid", 23),
                                        ("afraid", 27), ("afraid", 30), ("lover", 23)])
def test_a_fast_main_does_not_run_over_a_character(name, seed):
    b, _, fast, dist = fast_main_run(name, seed)     # compiled == Python, to the bit
    step = np.hypot(*np.diff(fast[:, 1:3], axis=0).T)
    assert step.max() <= b.largest_step * (1.0 + 1e-9), step.max() / b.largest_step
    assert dist.min() >= 0.8 * b.main_disc, dist.min() / b.main_disc


def test_a_slow_main_pressing_a_character_into_an_edge_slides_it_along_the_edge():
    table = (0.0, 0.0, 1.2, 0.8)
    c = np.array(table)
    # a main at (0.6, 0.75) stepping 5 mm a step (slower than the largest step, 0.02 m) into
    # the top edge; the character's disc 0.1 m. Pinned on the edge 5.4 cm from the main's
    # centre (the line from it runs into the edge): along the edge, away from the main, to
    # 0.1 m from it
    got = apart.out_of_way(0.62, 0.8, 0.6, 0.75, 0.0, 0.005, 0.1, 0.02, table)
    assert got == generation_kernel.out_of_way(0.62, 0.8, 0.6, 0.75, 0.0, 0.005, 0.1, 0.02, c)
    assert got[1] == 0.8 and abs(np.hypot(got[0] - 0.6, got[1] - 0.75) - 0.1) < 1e-12, got
    assert got[0] > 0.62
    # the same main standing, stepping along the edge, or away from the character; a
    # position with room inside (keep_apart pushes it); a corner with no edge to slide on
    kept = [((0.62, 0.8), (0.0, 0.0)), ((0.62, 0.8), (0.005, 0.0)),
            ((0.62, 0.8), (0.0, -0.005)), ((0.62, 0.7), (0.0, 0.005))]
    for (x, y), (vx, vy) in kept:
        for out_of_way, t in ((apart.out_of_way, table), (generation_kernel.out_of_way, c)):
            assert out_of_way(x, y, 0.6, 0.75, vx, vy, 0.1, 0.02, t) == (x, y), (x, y, vx, vy)
    assert apart.out_of_way(1.2, 0.8, 1.17, 0.77, 0.003, 0.003, 0.1, 0.02, table) == (1.2, 0.8)
