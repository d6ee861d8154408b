"""The input halting where the template goes on (behaviors/mop/halts.py)."""

from __future__ import annotations

import numpy as np

from bench.follow_quality import puck_follower, run


def _punch_on_getup_stream() -> tuple[dict, np.ndarray, list]:
    """The held-out twenty templates and ``bench/follow_seeds.py``'s seed 103, its seventh
    sequence of twenty back to back up to 0.4 of its first gesture (a getup wrist from rest,
    whose first stroke is the punch ankle's start): samples and truth."""
    from tests.mop.helpers import held_out_twenty
    templates, x, truth, _ = held_out_twenty(103, 7)
    return templates, x[:60], truth[:60]


def _longest(flags: list[bool]) -> int:
    best = run_len = 0
    for f in flags:
        run_len = run_len + 1 if f else 0
        best = max(best, run_len)
    return best


def test_an_action_just_taken_is_not_shown_while_the_input_halts_where_it_goes_on():
    # the punch is taken at 0.23 of itself as the getup's stroke ends, and its template goes
    # on at speed while the input stands there. Measured: it drives 3 ticks in a row (7
    # without halts.halts); the getup is recognised at the same tick either way
    templates, x, truth = _punch_on_getup_stream()
    states = run(puck_follower(templates), x)
    wrong = [s.valid and s.best != g for s, g in zip(states, truth)]
    hit = [i for i, (s, g) in enumerate(zip(states, truth)) if s.valid and s.best == g]
    assert _longest(wrong) <= 3 and hit and hit[0] <= 40, (np.flatnonzero(wrong), hit[:1])


def test_a_group_hides_an_action_while_its_input_halts_as_its_followers_alone():
    # member_validity.overruns calls halts.halts as the follower does: every state equal (25
    # valid ticks; 28 without the rule)
    from tests.mop.helpers import group_beside_alone
    templates, x, _ = _punch_on_getup_stream()
    assert group_beside_alone(lambda: puck_follower(templates), [x]) == [VALID]


#: The valid ticks of the stream above in a group (measured).
VALID = 25
