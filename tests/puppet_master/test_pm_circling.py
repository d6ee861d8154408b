"""A character that circles its main (the playful friend) keeps its matched moments' distance:
its linear smooth averages its raw steps in the frame that turns with its bearing from the
main (generation.StepSmoother.turn), not as taken, whose earlier steps point out of the
circle."""

from __future__ import annotations

import math

import numpy as np

from behaviors.puppet_master import fidelity
from behaviors.puppet_master.behavior import Behavior
from behaviors.puppet_master.engine import Reactor
from behaviors.puppet_master.generation import StepSmoother, turn_between
from tabletop import examples, library
from tests.puppet_master.demos import unseen_main_paths

TABLE = (0.0, 0.0, *examples.TABLE)


def test_the_remembered_steps_turn_with_the_bearing():
    c, s = turn_between(0.2, 0.0, 0.0, 0.1)              # a quarter turn counter-clockwise
    assert math.isclose(c, 0.0, abs_tol=1e-15) and math.isclose(s, 1.0)
    assert turn_between(0.0, 0.0, 0.1, 0.0) == (1.0, 0.0)   # no bearing: no turn
    sm = StepSmoother(3)
    sm.push(0.01, 0.0)
    sm.turn(c, s)
    assert np.allclose([sm.xs[0], sm.ys[0]], [0.0, 0.01]) and sm.xs[1:] == [0.0, 0.0]


def _outside_matched(b: Behavior, seed: int) -> float:
    """Mean over the unseen paths of ``seed`` of the live distance to the main less the
    matched moment's demonstrated distance (metres), the main fed on the generation grid."""
    gaps = []
    for main in unseen_main_paths(seed, 40.0, examples.TABLE).values():
        t = np.arange(0.0, main[-1, 0], 1.0 / b.params.rate_hz)
        reactor = Reactor(b, TABLE, max_backlog=None)
        for ti, (x, y, d) in zip(t, fidelity.main_on_grid(main, t)):
            rows = reactor.advance(float(ti), float(x), float(y), float(d))
            if reactor.source >= 0 and len(rows) == 1:
                gaps.append(math.hypot(rows[0][1] - x, rows[0][2] - y)
                            - b.distance[reactor.source])
    return float(np.mean(gaps))


def test_the_playful_friend_circles_at_its_matched_moments_distance():
    stored = library.load_behavior(examples.DEFAULT_OUT / "playful_friend")
    b = Behavior.train(stored.demonstration, **stored.parameters)
    assert b.circling
    gaps = [_outside_matched(b, seed) for seed in (0, 1)]
    # measured with the steps averaged as taken: 0.0107 / 0.0093 m beyond, turned with the
    # bearing 0.0044 / 0.0068 m (with the steps since its last touch among the features,
    # Behavior.circling; without them 0.0088 / 0.0093 against 0.0037 / 0.0038, its contact
    # 0.032 against 0.041 shown over 54 unseen paths as taken)
    assert max(gaps) < 0.008, gaps
    assert min(gaps) > -0.003, gaps                      # not pulled inside either
