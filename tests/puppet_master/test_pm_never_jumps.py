"""No generated step is longer than the demonstration's largest (Behavior.largest_step), whatever
shoves the reactor: a main faster than any character was shown to move that runs into its
personal space makes it give way at that step (step_detail.py), in the Python step and the
compiled one alike, the lover (test_pm_never_shoved.py) and every other character."""

import numpy as np
import pytest

from behaviors.puppet_master import fidelity
from behaviors.puppet_master.behavior import Behavior
from behaviors.puppet_master.engine import Reactor
from tabletop import examples, library
from tracking.visitor import ScriptedVisitor

TABLE = (1.2, 0.8)          # metres; an unseen table and main (the visitor at 0.5-1x its pace)


def _generate(b: Behavior, main: np.ndarray, compiled: bool) -> np.ndarray:
    r = Reactor(b, (0.0, 0.0, *TABLE), max_backlog=None)
    r.compiled = compiled
    rows = []
    for t, x, y, d in main:
        rows.extend(r.advance(float(t), float(x), float(y), float(d)))
    return np.asarray(rows, dtype=float)


def fast_main_run(name: str, seed: int) -> tuple[Behavior, np.ndarray, np.ndarray, np.ndarray]:
    """A shipped character beside the visitor of ``seed`` at 0.5-1x its pace (first 8 s, 60 Hz):
    its behaviour, the main path, the compiled step's rows (equal to the Python step's to the
    bit) and each step's distance to the main (metres)."""
    stored = library.load_behavior(examples.DEFAULT_OUT / name)
    b = Behavior.train(stored.demonstration, **stored.parameters)
    v = ScriptedVisitor(TABLE, [1], seed=seed, speed=(0.5, 1.0))
    main = np.array([(t, *v.poses(t)[0][1:]) for t in np.arange(0.0, 8.0, 1.0 / 60.0)])
    fast, slow = _generate(b, main, True), _generate(b, main, False)
    assert np.array_equal(fast.view(np.uint64), slow.view(np.uint64))
    mg = fidelity.main_on_grid(main, fast[:, 0])
    return b, main, fast, np.hypot(fast[1:, 1] - mg[1:, 0], fast[1:, 2] - mg[1:, 1])


# without the give-way (only the lover had it) the first 8 s of these paths shoved the stalker
# 3.01x its largest step (10 steps over), the afraid one 1.28x (7), the bully 1.46x (2), the
# playful friend 1.35x (2)
@pytest.mark.parametrize("name, seed", [("stalker", 27), ("afraid", 27), ("bully", 27),
                                        ("playful_friend", 30)])
def test_a_fast_main_never_shoves_a_character_past_its_largest_step(name, seed):
    b, _, fast, dist = fast_main_run(name, seed)
    step = np.hypot(*np.diff(fast[:, 1:3], axis=0).T)
    assert step.max() <= b.largest_step * (1.0 + 1e-9), step.max() / b.largest_step
    # where the main runs it over (nearer than its personal space), it flees at that step
    inside = dist < b.main_disc - 0.005
    assert np.allclose(step[inside], b.largest_step), step[inside] / b.largest_step
