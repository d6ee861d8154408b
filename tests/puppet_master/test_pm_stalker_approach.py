"""A character that keeps pace with its main (the stalker) leaves to a live main coming at it
faster than the matched moment's main what that main's approach closes: its drift correction
loses its part into the main up to the difference (generation.less_approach). Its contact on
fast reversing mains stays within the issue's band as its designer's does."""

import math

import numpy as np
import pytest

from behaviors.puppet_master import fidelity, generation_kernel
from behaviors.puppet_master.demonstrated import main_approach
from behaviors.puppet_master.generation import less_approach
from tabletop import examples
from tests.puppet_master.demos import shipped, unseen_main_paths

TABLE = (0.0, 0.0, *examples.TABLE)
SEEDS = (0, 1, 2, 3, 4, 5, 8, 9, 10, 11, 12, 13)


def test_the_correction_loses_what_the_main_closes_beyond_the_moments_main():
    # reactor 0.2 m east of the main; the correction 0.006 m west (into the main), 0.002 north
    inward = (-0.006, 0.002)
    # the live main steps 0.01 m east (at the reactor), the moment's main did not: all of the
    # inward part goes, the sideways part stays
    assert less_approach(0.01, 0.0, 0.2, 0.0, 0.0, *inward) == pytest.approx((0.0, 0.002))
    # the moment's main came at its reactor as fast: nothing changes
    assert less_approach(0.01, 0.0, 0.2, 0.0, 0.01, *inward) == inward
    # 0.004 m beyond the moment's main's 0.006: 0.004 of the inward part goes
    assert less_approach(0.01, 0.0, 0.2, 0.0, 0.006, *inward) == pytest.approx((-0.002, 0.002))
    # a moment whose main stepped away counts as none; a correction outward is kept whole
    assert less_approach(0.01, 0.0, 0.2, 0.0, -0.02, *inward) == pytest.approx((0.0, 0.002))
    assert less_approach(0.01, 0.0, 0.2, 0.0, 0.0, 0.006, 0.0) == (0.006, 0.0)
    # a main walking away, or a reactor on its main, changes nothing
    assert less_approach(-0.01, 0.0, 0.2, 0.0, 0.0, *inward) == inward
    assert less_approach(0.01, 0.0, 0.0, 0.0, 0.0, *inward) == inward


@pytest.mark.parametrize("fn", [less_approach, generation_kernel.less_approach],
                         ids=["python", "compiled"])
def test_a_moment_whose_main_stepped_away_counts_as_none(fn):
    # the live main steps 0.005 m away from its reactor, the moment's main stepped 0.01 m away:
    # the live main comes at it 0.005 m faster than the moment's main, but not at it at all,
    # so nothing is lost (the moment's step away counted as an approach of -0.01 m would cut
    # 0.005 m of the inward part)
    inward = (-0.006, 0.002)
    assert fn(-0.005, 0.0, 0.2, 0.0, -0.01, *inward) == inward
    assert fn(0.0, 0.0, 0.2, 0.0, -0.01, *inward) == inward


def test_the_demonstrated_mains_approach_is_its_step_along_the_bearing():
    main = np.array([[0.0, 0.0], [0.01, 0.0], [0.01, 0.02], [0.0, 0.0]])
    react = np.array([[0.3, 0.0], [0.3, 0.0], [0.3, 0.0], [0.3, 0.0]])
    got = main_approach(main, react)
    assert got[0] == 0.0 and got[1] == pytest.approx(0.01)
    assert got[2] == pytest.approx(0.0)                  # across the bearing
    # back from (0.01, 0.02) to the origin, the reactor at (0.29, -0.02) from it: away
    assert got[3] == pytest.approx((-0.01 * 0.29 + 0.02 * 0.02) / math.hypot(0.29, 0.02))


def test_the_stalkers_contact_on_fast_reversing_mains_stays_in_its_band():
    # Measured on the fast reversing paths of these 12 seeds: mean contact 0.0336 (its
    # designer's own character 0.0456, the demonstration 0.022, the band up to 0.042),
    # over the band on 2 paths; 0.0425 and 6 over without the loss (the correction closed in
    # on a main already coming at it: half of its contact replayed the demonstration's three
    # passes, matched where the live main walked at it at 0.21 m/s against 0.10 shown)
    b = shipped("stalker")
    demo = fidelity.demonstration_figures(b)
    contact = [fidelity.evaluate(b, unseen_main_paths(seed, 40.0, examples.TABLE)[
        "fast_reversals_60hz"], TABLE, demo)["gen_contact"] for seed in SEEDS]
    assert np.mean(contact) <= 0.038, contact
    assert sum(c > demo["contact"] + 0.02 for c in contact) <= 3, contact
