"""The threshold model's lead over the templates carried across a new attempt
(:meth:`behaviors.mop.threshold_lead.ThresholdLead._threshold_lead`, the study in
:mod:`behaviors.mop.threshold`)."""

import numpy as np

from behaviors.mop import threshold
from bench.follow_quality import puck_follower, true_metrics
from bench.motions import MOCAP, gesture_templates, mocap_templates, performance
from tests.mop.helpers import run, solo, widened_mirrored


def test_a_mirrored_path_restarted_part_way_stays_refused(monkeypatch):
    # among the twenty templates, the spin ankle mirrored (bench/follow_widened.py, seed 203 at
    # 1.4x, 201 at 1x): the backflip wrist, followed back over itself, ends about 60% along and
    # a new attempt starts there; the walk ankle then drove 0.219 and 0.091 of the time with
    # the threshold model afresh (its lead of 73 nats at 203 gone; 0.228 and 0.124 before the
    # ideal observer's coverage, coverage.OBSERVER); measured 0 and 0 with the lead carried.
    # The spin ankle itself still drives: valid after 30% 0.87-1.0 (the same either way).
    # Stepped by a group of one (threshold.CARRY_LEAD read at each step), equal to the follower
    # alone at every tick of these seven runs (valid 3, 0, 53, 81, 64; afresh 25, 13)
    templates = {**gesture_templates(), **mocap_templates(joints=MOCAP)}
    f = solo(puck_follower(templates))
    for seed, scale in ((203, 1.4), (201, 1.0)):
        x = widened_mirrored(seed, "spin_right_ankle", scale)
        assert np.mean([s.valid for s in run(f, x)]) <= 0.05, seed
    monkeypatch.setattr(threshold, "CARRY_LEAD", False)   # the threshold model afresh
    for seed, scale in ((203, 1.4), (201, 1.0)):
        x = widened_mirrored(seed, "spin_right_ankle", scale)
        assert np.mean([s.valid for s in run(f, x)]) > 0.08, seed
    monkeypatch.undo()
    rng = np.random.default_rng(1)
    for s in (0.7, 1.0, 1.4):
        x, prog = performance(rng, templates["spin_right_ankle"], s)
        assert true_metrics(run(f, x), "spin_right_ankle", prog)["valid_after30"] >= 0.6, s
