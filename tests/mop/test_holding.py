"""Holds inside an action (:mod:`behaviors.mop.holding`): the size taken where a performer rests."""

import numpy as np

from bench.follow_quality import puck_follower, run, true_metrics
from bench.motions import mocap_templates, performance
from behaviors.mop.holding import hold_maps

#: A wrist path whose straight first stroke ends in a hold (states 15-18 of 90).
HOLDS_AFTER_A_STROKE = (("getup_facedown", "right_wrist"),)


def test_a_smaller_action_resting_on_its_hold_is_sized_there_from_short_of_it(gestures):
    # drawn 0.7x, its size stays near 1 along the stroke, so the performer resting on the hold
    # is followed 6.4 states short of it (state 8.6 of 15) and the action stalled there while
    # others led. Measured valid after 30% (seeds 0 / 2): 0.978 / 0.961 with the hold 9 states
    # ahead (holding.HOLD_AHEAD), 0.0 / 0.0 with it 6 ahead
    templates = {**gestures, **mocap_templates(joints=HOLDS_AFTER_A_STROKE)}
    name = "getup_facedown_right_wrist"
    f = puck_follower(templates)
    draws = [performance(np.random.default_rng(seed), templates[name], 0.7) for seed in (0, 2)]
    shares = {}
    for ahead in ("kept", 6):
        if ahead != "kept":
            f._holds = hold_maps(f.bank, ahead)
        shares[ahead] = [true_metrics(run(f, x), name, prog)["valid_after30"] for x, prog in draws]
    assert min(shares["kept"]) >= 0.9 and max(shares[6]) <= 0.1, shares
