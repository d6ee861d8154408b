"""The speed profile at a turn (behaviors/mop/speed_profile.py)."""

from __future__ import annotations

import numpy as np
import pytest

from behaviors.mop import speed_profile
from bench.follow_quality import puck_follower
from tests.mop.helpers import run, solo

#: Held-out twenty templates back to back, ``bench/follow_seeds.py``'s (seed, nth sequence, up
#: to sample) ending after the circle's recognition, and the valid ticks of that stream in a
#: group (measured): seed 112's sixth (a roll wrist, then the circle), seed 102's third (a
#: line, then the circle), seed 111's fifth (a spin kick wrist, then the circle) and seed 108's
#: sixth (a jump ankle, then the circle at 1.2x); each circle's start is the spin wrist's path
#: up to its turn.
STREAMS = {"112": (112, 6, 135, 81), "102": (102, 3, 200, 114), "111": (111, 5, 110, 63),
           "108": (108, 6, 110, 50)}


def _spin_on_circle_stream(name: str) -> tuple[dict, np.ndarray, list]:
    """Stream ``name`` of :data:`STREAMS`: templates, samples and truth."""
    from tests.mop.helpers import held_out_twenty
    seed, nth, end, _ = STREAMS[name]
    templates, x, truth, _ = held_out_twenty(seed, nth)
    return templates, x[:end], truth[:end]


@pytest.mark.parametrize("name", sorted(STREAMS))
def test_an_action_waiting_at_its_turn_is_not_shown_while_the_input_keeps_its_speed(name):
    # the spin is taken on the circle's start at 0.24-0.29 of itself and followed into its turn
    # (0.28-0.29) while the input goes on up the circle at its speed. Measured: it drives 1
    # tick on 112 (4 without speed_profile.outpaces, 3 without turns_on), 2 on 102 (5
    # without turns_on: its state advanced 1-3 states a sample into the turn, the input's step
    # off the spin's way on by a cosine of -0.71 to -0.76; 3 without speed_profile.quickens:
    # the input quickened as its template slowed into the turn), 2 on 111 (4 without quickens)
    # and 3 on 108 (4, in a run of 3, without speed_profile.QUICK_AHEAD: its state one short of
    # where its template slows, its size growing); the circle is recognised either way
    # (stepped by a group of one: equal to the follower alone on these streams, below)
    templates, x, truth = _spin_on_circle_stream(name)
    states = run(solo(puck_follower(templates)), x)
    spin = [i for i, s in enumerate(states)
            if truth[i] == "circle" and s.valid and s.best == "spin_left_wrist"]
    hit = [i for i, s in enumerate(states) if truth[i] == "circle" and s.valid
           and s.best == "circle"]
    assert len(spin) <= {"112": 1, "102": 2, "111": 2, "108": 3}[name] and hit, (spin, hit[:1])


@pytest.mark.parametrize("name", sorted(STREAMS))
def test_a_group_hides_an_action_at_its_turn_as_its_followers_alone(name):
    # member_validity.overruns calls speed_profile.outpaces, quickens and turns_on as the
    # follower does: every state equal (valid ticks 81, 114, 63 and 50; 51 on 108 without
    # speed_profile.QUICK_AHEAD; before shape_lead.CONFIRM_GAIN 79, 112 and 62, and 81 and 115
    # without turns_on, 82 on 112 without either, 113 on 102 without quickens)
    from tests.mop.helpers import group_beside_alone
    templates, x, _ = _spin_on_circle_stream(name)
    assert group_beside_alone(lambda: puck_follower(templates), [x]) == [STREAMS[name][3]]


def test_an_action_is_read_a_state_ahead_only_while_its_size_grows(monkeypatch):
    # speed_profile.QUICK_GROWN: on 108's stream the spin wrist's followed state is one short of
    # where its template slows (23.5, 0.26 of it) while its size grows 1.5 % in a sample, and the
    # input quickens against the state ahead; the same sample with the size the sample before's
    # is read at its own state alone and does not quicken (measured: the one such sample of the
    # four streams' 512 calls)
    calls = []
    quickens = speed_profile.quickens

    def recorded(*args):
        calls.append(args)
        return quickens(*args)

    monkeypatch.setattr(speed_profile, "quickens", recorded)
    templates, x, _ = _spin_on_circle_stream("108")
    run(puck_follower(templates), x)
    # quickens(..., g, progress, size, size_before, sigma)
    read_ahead = [a for a in calls if quickens(*a) and not quickens(*a[:14], a[13], a[15])]
    assert read_ahead, (len(calls), max(a[13] / a[14] for a in calls))
