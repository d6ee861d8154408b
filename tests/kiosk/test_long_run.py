"""A table runs for weeks: the scripted pucks of attract mode and of the synthetic camera keep
a bounded past, and the poses they give do not change for it."""

import numpy as np

from tracking.visitor import HISTORY_S, GesturePerformer, PuckScript

CIRCLE = np.array([[k / 20, 0.05 * np.cos(k / 3) - 0.05, 0.05 * np.sin(k / 3)]
                   for k in range(40)])


def test_scripted_pucks_remember_a_bounded_past_and_move_as_before():
    day = 6 * 3600.0              # six hours of table time
    ts = np.arange(0.0, day, 3.0)
    script, performer = PuckScript((1.2, 0.8), seed=3), GesturePerformer([CIRCLE], (0.6, 0.4))
    for t in ts:
        script.pose(t)
        performer.pose(t)
    # bounded: only the last HISTORY_S (and a few stale entries) are kept
    assert script.starts[0] > day - 2 * HISTORY_S and len(script.segments) < 1500
    assert performer.starts[0] > day - 2 * HISTORY_S and len(performer.plan) < 3000
    assert len(performer.performed) < 1500
    # the same poses as scripts that never forgot (asked only now: generated from the start)
    fresh, fresh_performer = PuckScript((1.2, 0.8), seed=3), GesturePerformer([CIRCLE], (0.6, 0.4))
    recent = day - 0.5 * HISTORY_S + np.arange(0.0, 0.5 * HISTORY_S, 0.7)
    assert [script.pose(t) for t in recent] == [fresh.pose(t) for t in recent]
    assert [performer.pose(t) for t in recent] == [fresh_performer.pose(t) for t in recent]
