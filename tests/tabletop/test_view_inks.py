"""A character's inks: its colours faded over the table (or over black, a hinted pose's light) at
its opacity, remembered by the opacity's 1/128 step, worked out as palette.fade works them."""

from bench.inks import cases, faded
from tabletop.drawing import characters as C


def test_inks_are_the_colours_palette_fade_makes():
    """2,000 random colours, opacities and grounds, every ink equal to the bit (faults of the
    rounding, the step's width or the clamp fail within the first 20: 5-87% of the cases
    each); the long form, 200,000 cases: bench/inks.py."""
    for c, a, g in cases(2000):
        assert C.inks(c, a, g) == faded(c, a, g), (c, a, g)
    assert C.inks([200, 90, 30], 0.5, [0, 0, 0]) == faded((200, 90, 30), 0.5, (0, 0, 0))


def test_an_opacity_moving_within_its_step_finds_the_inks_remembered():
    """A hinted pose's strength creeps toward its probability: a new opacity every frame, in
    the same 1/128 step (bench/view.py's hinted scene: 6.4 of 10.6 inks a frame made anew,
    0.59 ms, in its first pass before)."""
    first = C.inks((90, 220, 120), 0.3125, (0, 0, 0))
    assert C.inks((90, 220, 120), 0.3125 + 1e-7, (0, 0, 0)) is first
    assert C.inks((90, 220, 120), 0.3125 + 1 / 128, (0, 0, 0)) != first
