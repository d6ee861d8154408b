"""Taken only while the last samples fit (:mod:`behaviors.mop.take_rule`), on a held-out
sequence of twenty templates back to back: a take after an end is read also from where the input
came nearest the ended template's last point, by a group as by its followers alone."""

import numpy as np

from bench.follow_quality import puck_follower
from behaviors.mop import take_rule
from tests.mop.helpers import run, solo


def _ended_short_stream() -> tuple[dict, np.ndarray, list, np.ndarray]:
    """The held-out twenty templates and ``bench/follow_seeds.py``'s seed 103, its first
    sequence of twenty back to back (a walk wrist, a punch ankle, a dance ankle at 1.14x, a jump
    ankle at 0.96x) to the jump's end: samples, truth, true progress."""
    from tests.mop.helpers import held_out_twenty
    templates, x, truth, prog = held_out_twenty(103, 1)
    cut = max(i for i, t in enumerate(truth) if t == "jump_left_ankle") + 1
    return templates, x[:cut], truth[:cut], prog[:cut]


def test_a_take_after_an_end_is_read_from_where_the_input_came_nearest_it(monkeypatch):
    # the follower reaches the dance's end 2.8 mm short of where the performer ends it; read
    # from that anchor, the jump's last samples stray 0.2-0.5 sigma^2 from its path (0.02-0.09
    # from where it began) and its take is refused on every tick (take_rule._fits_take). Read
    # also from where the input came nearest the dance's last point
    # (take_rule.TAKE_FROM_NEAREST): measured, the jump recognised at 0.37 of it (47 valid
    # ticks); without, never (at 0.73 with shape_lead.CONFIRM_GAIN: one sample fits there)
    templates, x, truth, prog = _ended_short_stream()
    g = "jump_left_ankle"

    def hits(grouped: bool = False) -> list[float]:   # (patched: the follower alone)
        f = puck_follower(templates)
        states = run(solo(f) if grouped else f, x)
        return [prog[i] for i, s in enumerate(states) if truth[i] == g and s.valid and s.best == g]

    now = hits(grouped=True)   # (equal to the follower alone on this stream, below)
    monkeypatch.setattr(take_rule, "TAKE_FROM_NEAREST", 0.0)
    plain = hits()
    assert now and now[0] <= 0.4 and len(now) >= 40, (now[:1], len(now))
    assert not plain or plain[0] >= 0.7, plain[:1]


def test_a_group_reads_a_take_after_an_end_as_its_followers_alone():
    # member_validity.takes' form of take_rule.TAKE_FROM_NEAREST: every state equal (valid
    # ticks measured: 187, one fewer with coverage.LATE_FIT than without)
    from tests.mop.helpers import group_beside_alone
    templates, x, _, _ = _ended_short_stream()
    assert group_beside_alone(lambda: puck_follower(templates), [x]) == [187]
