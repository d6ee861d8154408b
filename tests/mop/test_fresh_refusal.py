"""A template judged afresh is not refused on its fresh memory's first samples
(:mod:`behaviors.mop.fresh_refusal`), alone and in a group alike."""

from bench.follow_quality import puck_follower, run, true_metrics
from tests.mop.helpers import group_beside_alone, held_out_draw


def test_a_template_judged_afresh_is_not_refused_on_its_next_sample():
    # the backflip's ankle at 1.2x, judged afresh at 0.50 of it (size 1.20): its next sample
    # read at 2.68 sigma refused it for the rest of the stroke, until the performer paused;
    # measured: valid after 30% 0.08 refused so, 0.36 waiting for three samples' weight
    templates, x, prog = held_out_draw(102, "backflip_left_ankle", 1.2)
    m = true_metrics(run(puck_follower(templates), x), "backflip_left_ankle", prog)
    assert m["valid_after30"] >= 0.3, m["valid_after30"]


def test_a_group_waits_to_refuse_a_template_judged_afresh_as_its_follower_alone():
    templates, x, _ = held_out_draw(102, "backflip_left_ankle", 1.2)
    (valid,) = group_beside_alone(lambda: puck_follower(templates), [x])
    # measured: 18 valid samples (4 refused at once)
    assert valid >= 15, valid
