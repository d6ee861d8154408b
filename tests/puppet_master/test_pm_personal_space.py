"""A character whose demonstration never touched its main keeps it out of its personal space
(Behavior.personal_space, applied in Reactor._step) on unseen main paths; the characters that
touch (the bully charges, the stalker and the playful friend come close) have none."""

import numpy as np

from behaviors.puppet_master import fidelity, visitors
from behaviors.puppet_master.behavior import TOUCH_M
from tabletop import examples
from tests.puppet_master.test_pm_fidelity import TABLE, shipped  # noqa: F401 (fixture)


def test_personal_space_is_the_demonstrations_nearest_percentile_beyond_a_touch(shipped):
    for name, b in shipped.items():
        near = float(np.percentile(b.distance, 1.0))
        if name in ("lover", "afraid"):      # measured 0.081 and 0.105 m
            assert b.personal_space == near >= TOUCH_M
        else:                                # 0.05-0.06 m: they touch
            assert near < TOUCH_M and b.personal_space == 0.0


def test_the_lover_is_not_walked_into_on_unseen_paths(shipped):
    # an unseen main walking into the lover faster than the lover's demonstrated speed made
    # it touch 3-20% of the time on the fast and loops paths (seed 0: 0.046 and 0.034 against
    # 0.008 demonstrated); with its personal space: 0.001 and 0.001
    b = shipped["lover"]
    demo = fidelity.demonstration_figures(b)
    paths = visitors.unseen_main_paths(0, 40.0, examples.TABLE)
    for path in ("fast_reversals_60hz", "loops_spins_45hz"):
        main = paths[path]
        rows = fidelity.generate(b, main, TABLE)
        mg = fidelity.main_on_grid(main, rows[:, 0])
        dist = np.hypot(rows[:, 1] - mg[:, 0], rows[:, 2] - mg[:, 1])
        # the main's position on the grid is interpolated here, extrapolated live: a few mm
        assert dist.min() > b.personal_space - 0.01, (path, dist.min())
        row = fidelity.evaluate(b, main, TABLE, demo)
        assert row["ok_contact"], (path, row["gen_contact"], row["demo_contact"])
