"""A character that walks with its main keeping a personal space round it
(Behavior.walks_with_main: the lover) is never shoved faster than it was shown to move: an
unseen main faster than its largest demonstrated step that walks into it makes it give way at
that step (Behavior.largest_step, step.py), in the Python step and the compiled one alike."""

import numpy as np

from behaviors.puppet_master import fidelity
from behaviors.puppet_master.engine import Reactor
from tabletop import examples
from tests.puppet_master.demos import unseen_main_paths
from tests.puppet_master.test_pm_fidelity import TABLE, shipped  # noqa: F401 (fixture)


def _generate(b, main, compiled: bool) -> np.ndarray:
    r = Reactor(b, TABLE, max_backlog=None)
    r.compiled = compiled
    rows = []
    for t, x, y, d in main:
        rows.extend(r.advance(float(t), float(x), float(y), float(d)))
    return np.asarray(rows, dtype=float)


def test_the_lover_gives_way_at_its_largest_step(shipped):
    # seed 2's fast reversing hand (0.46 m/s into the lover at 11 s) pushed it out of its
    # personal space 1.13x its largest demonstrated step (0.0098 m) here (1.25x over 40 s,
    # on 10 steps, checked with Behavior.largest_step = inf, which turns it off); on the fast
    # paths of 9 of the 18 seeds 0-5, 8-13, 26-31 (1.05-1.25x), on the loops of 5 (1.0-1.04x)
    b = shipped["lover"]
    assert b.largest_step == float(np.max(np.hypot(*np.diff(b.react[:, :2], axis=0).T)))
    main = unseen_main_paths(2, 40.0, examples.TABLE)["fast_reversals_60hz"]
    main = main[main[:, 0] < 12.0]
    fast, slow = _generate(b, main, True), _generate(b, main, False)
    assert np.array_equal(fast.view(np.uint64), slow.view(np.uint64))
    step = np.hypot(*np.diff(fast[:, 1:3], axis=0).T)
    assert step.max() <= b.largest_step * (1.0 + 1e-9), step.max() / b.largest_step
    # the main then comes nearer than the personal space for a few steps (measured: at
    # least 0.078 m over those 18 seeds, against 0.081; pucks are 0.075 m across)
    mg = fidelity.main_on_grid(main, fast[:, 0])
    dist = np.hypot(fast[:, 1] - mg[:, 0], fast[:, 2] - mg[:, 1])
    assert dist.min() > b.personal_space - 0.01
