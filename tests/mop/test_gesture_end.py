"""Where a gesture ends (behaviors/mop/gesture_end.py)."""

from __future__ import annotations

import numpy as np

from bench.follow_quality import puck_follower, run

#: ``bench/follow_seeds.py``'s seed 107, its third sequence of twenty held-out templates back to
#: back, up to the wave's first samples: the backflip ankle's performer stands at its eased end
#: (within 2 still radii) from the sample before its last on, the follower reaches ``end`` at
#: its tempo three samples after that last, at the wave's third (0.033 of it).
SEED, NTH, UNTIL = 107, 3, 118
#: That stream's valid ticks in a group (measured; 64 without gesture_end.stood).
VALID = 63


def _backflip_into_wave() -> tuple[dict, np.ndarray, list]:
    """Templates, samples and truth of that stream."""
    from tests.mop.helpers import held_out_twenty
    templates, x, truth, _ = held_out_twenty(SEED, NTH)
    return templates, x[:UNTIL], truth[:UNTIL]


def test_an_end_reached_at_its_tempo_after_its_performer_stood_there_is_not_shown():
    # measured: the backflip drives the wave's first 2 samples (3 without gesture_end.stood:
    # also the sample at which its follower reaches the end)
    templates, x, truth = _backflip_into_wave()
    states = run(puck_follower(templates), x)
    wrong = [i for i, s in enumerate(states)
             if truth[i] == "wave" and s.valid and s.best == "backflip_left_ankle"]
    assert 0 < len(wrong) <= 2, wrong


def test_a_group_hides_an_end_over_its_grace_as_its_followers_alone():
    # members.conclude applies gesture_end.stood as the follower does: every state equal
    from tests.mop.helpers import group_beside_alone
    templates, x, _ = _backflip_into_wave()
    assert group_beside_alone(lambda: puck_follower(templates), [x]) == [VALID]
