"""An input reversal sizes the templates that turn back where the input does; one the input
goes on through the way it came (a shake or a pause) gives its sizes back
(:mod:`behaviors.mop.reversal`; the group: ``test_group.py``)."""

from behaviors.mop import invariance
from tests.mop.helpers import held_out_group_valid, held_out_valid


def test_a_reversal_the_input_goes_on_through_gives_its_sizes_back(monkeypatch):
    # held-out 105's dance ankle at 1.2x: 2.7 mm back over three samples at 0.37 of it, read as
    # a reversal, sized it 1.22 -> 1.43 (a wave and the figure eight led then); the input went
    # on the way it came two samples later. Measured valid after 30% 0.978, 0.565 kept
    valid = held_out_valid(105, "dance_a_right_ankle", 1.2)
    monkeypatch.setattr(invariance, "went_on", lambda *args: False)
    kept = held_out_valid(105, "dance_a_right_ankle", 1.2)
    assert valid >= 0.9 and kept <= 0.7, (valid, kept)


def test_a_group_gives_a_reversal_s_sizes_back_as_its_follower_alone():
    # the dance ankle above, a group of one follower beside it (the undo compiled; without it
    # the group parts from its follower at tick 32). Measured 53 valid samples
    valid = held_out_group_valid(105, "dance_a_right_ankle", 1.2)
    assert valid >= 48, valid
