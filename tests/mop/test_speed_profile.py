"""The speed profile at a turn (behaviors/mop/speed_profile.py)."""

from __future__ import annotations

import numpy as np

from bench.follow_quality import puck_follower, run


def _spin_on_circle_stream() -> tuple[dict, np.ndarray, list]:
    """The held-out twenty templates and ``bench/follow_seeds.py``'s seed 112, its sixth
    sequence of twenty back to back up to the circle's end (a roll wrist, then a circle whose
    start is the spin wrist's path up to its turn): samples and truth."""
    from tests.mop.helpers import held_out_twenty
    templates, x, truth, _ = held_out_twenty(112, 6)
    return templates, x[:135], truth[:135]


def test_an_action_waiting_at_its_turn_is_not_shown_while_the_input_keeps_its_speed():
    # the spin is taken on the circle's start at 0.29 of itself, at its turn, and waits there
    # while the input goes on up the circle at its speed. Measured: it drives 3 ticks (4
    # without speed_profile.outpaces); the circle is recognised at 0.43 either way
    templates, x, truth = _spin_on_circle_stream()
    states = run(puck_follower(templates), x)
    spin = [i for i, s in enumerate(states)
            if truth[i] == "circle" and s.valid and s.best == "spin_left_wrist"]
    hit = [i for i, s in enumerate(states) if truth[i] == "circle" and s.valid
           and s.best == "circle"]
    assert len(spin) <= 3 and hit, (spin, hit[:1])


def test_a_group_hides_an_action_waiting_at_its_turn_as_its_followers_alone():
    # member_validity.overruns calls speed_profile.outpaces as the follower does: every state
    # equal (81 valid ticks; 82 without the rule)
    from tests.mop.helpers import group_beside_alone
    templates, x, _ = _spin_on_circle_stream()
    assert group_beside_alone(lambda: puck_follower(templates), [x]) == [VALID]


#: The valid ticks of the stream above in a group (measured).
VALID = 81
