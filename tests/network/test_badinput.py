"""Rejected input is counted always and logged sparingly: a sender that never stops sending
something refused writes about a thousand lines a week, not sixty thousand."""

import logging
import math

from tracking.badinput import BadInput, LogGaps

WEEK_S = 7 * 24 * 3600


def test_a_week_of_refused_input_keeps_the_log_small_and_a_new_episode_is_said_at_once(caplog):
    now = [0.0]
    bad = BadInput("osc", clock=lambda: now[0])
    with caplog.at_level(logging.WARNING, logger="tabletop.input"):
        for k in range(WEEK_S):                 # one refused packet a second for a week
            now[0] = float(k)
            bad.count("unknown_address", "'/lights/dim' from 10.0.0.7")
        lines = [r.getMessage() for r in caplog.records]
        assert bad.counts() == {"unknown_address": WEEK_S}
        # at 0, 10, 30, 70, 150, 310, 630 s, then every 600 s (every 10 s before: 60,480)
        last = 630 + (WEEK_S - 1 - 630) // 600 * 600
        assert len(lines) == 7 + (last - 630) // 600 == 1013
        assert "(1 so far)" in lines[0] and "(11 so far)" in lines[1]
        assert f"({last + 1} so far)" in lines[-1]
        caplog.clear()
        now[0] = WEEK_S + 1200.0                # quiet for 20 minutes, then one more
        bad.count("unknown_address")
        now[0] += 5.0
        bad.count("unknown_address")            # within log_every_s: counted, not said
        bad.count("malformed")                  # another kind: said at once
    lines = [r.getMessage() for r in caplog.records]
    assert len(lines) == 2 and f"({WEEK_S + 1} so far)" in lines[0] and "malformed" in lines[1]


def test_log_gaps_without_a_longest_gap():
    """``max_s`` infinite: the first line at once, then doubling for ever (it raised KeyError)."""
    gaps = LogGaps(first_s=10.0, max_s=math.inf)
    said = [t for t in range(0, 200) if gaps.due("k", float(t))]
    assert said == [0, 10, 30, 70, 150]
