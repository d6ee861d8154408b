"""A character's inks: its colours faded over the table (or over black, a hinted pose's light) at
its opacity, remembered by the opacity's 1/128 step, worked out as palette.fade works them."""

import random

from tabletop.drawing import characters as C
from tabletop.drawing.palette import EYE_WHITE, INK, TABLE, fade, lighten, rgb, shade


def faded(c, alpha, g):
    """The inks as palette.fade's remembered layers make them."""
    eyes = (lighten(c, 0.35), c) if g == (0, 0, 0) else (EYE_WHITE, INK)
    return tuple(rgb(fade(shade(c, k), alpha, g)) for k in (0.62, 0.68, 0.7, 0.72, 1.0)) + tuple(
        rgb(fade(x, alpha, g)) for x in (lighten(c, 0.18), lighten(c, 0.35), *eyes))


def test_inks_are_the_colours_palette_fade_makes():
    rnd = random.Random(0)
    for _ in range(20000):
        c = tuple(rnd.randrange(256) for _ in range(3))
        g = rnd.choice([TABLE, (0, 0, 0), tuple(rnd.randrange(256) for _ in range(3))])
        a = rnd.choice([rnd.random(), rnd.random() * 1.2 - 0.1, rnd.randrange(129) / 128])
        assert C.inks(c, a, g) == faded(c, a, g), (c, a, g)
    assert C.inks([200, 90, 30], 0.5, [0, 0, 0]) == faded((200, 90, 30), 0.5, (0, 0, 0))


def test_an_opacity_moving_within_its_step_finds_the_inks_remembered():
    """A hinted pose's strength creeps toward its probability: a new opacity every frame, in
    the same 1/128 step (bench/view.py's hinted scene: 6.4 of 10.6 inks a frame made anew,
    0.59 ms, in its first pass before)."""
    first = C.inks((90, 220, 120), 0.3125, (0, 0, 0))
    assert C.inks((90, 220, 120), 0.3125 + 1e-7, (0, 0, 0)) is first
    assert C.inks((90, 220, 120), 0.3125 + 1 / 128, (0, 0, 0)) != first
