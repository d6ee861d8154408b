"""A designer who records the same character twice gets the same character: every take of a
scripted designer reads as its shipped behaviour does (Behavior.personal_space, keeps_pace,
walks_with_main, keeps_away, charging; bench/character_reading.py counts 30 takes each).

By the 1st-percentile distance to the main, MIN_CHARGES 3 and the pace ratio alone, of the 10
takes of each designer here the lover lost its personal space in 3 (its main walked into it
a few times), the stalker read one in 1, the afraid one walked with its main in 1, and the
playful friend (3) and the stalker (1) read as charging."""

import numpy as np
import pytest

from bench.character_reading import take
from behaviors.puppet_master.behavior import Behavior
from behaviors.puppet_master.character import MIN_OWN_TOUCHES, TOUCH_M
from behaviors.puppet_master.demonstrated import own_touches
from behaviors.puppet_master.designers import PERSONALITIES
from tabletop import examples, library

TAKES = tuple(range(5000, 5010))


def _reading(b: Behavior) -> tuple[bool, ...]:
    return (b.personal_space > 0.0, b.keeps_pace, b.walks_with_main, b.keeps_away, b.charging)


@pytest.mark.parametrize("name", PERSONALITIES)
def test_every_take_of_a_designer_reads_as_its_shipped_character(name):
    stored = library.load_behavior(examples.DEFAULT_OUT / name)
    shipped = _reading(Behavior.train(stored.demonstration, **stored.parameters))
    assert shipped == {"lover": (True, False, True, False, False),
                       "bully": (False, False, False, False, True),
                       "playful_friend": (False, False, False, False, False),
                       "stalker": (False, True, False, False, False),
                       "afraid": (True, False, False, True, False)}[name]
    for seed in TAKES:
        b = Behavior.train(take(name, seed))
        assert _reading(b) == shipped, (name, seed, _reading(b), b.own_touches)


def _pair(main_x: np.ndarray, react_x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    z = np.zeros_like(main_x)
    return np.column_stack([main_x, z]), np.column_stack([react_x, z])


def test_a_touch_counts_as_the_reactors_own_only_where_it_closed_the_gap():
    t = np.arange(200) / 40.0                       # 5 s at 40 Hz
    walk_in = np.clip(0.3 - 0.1 * t, 0.05, None)    # 0.1 m/s from 0.3 m to a touch
    # its main walks into a reactor that stands: none of its own
    main, react = _pair(0.5 - walk_in, np.full_like(t, 0.5))
    assert own_touches(main, react, 40.0, TOUCH_M) == 0
    # the reactor walks into a main that stands: its own
    main, react = _pair(np.full_like(t, 0.5), 0.5 - walk_in)
    assert own_touches(main, react, 40.0, TOUCH_M) == 1
    # a main that reverses into a reactor following it at 0.05 m/s: the main's doing
    react_x = 0.05 * t
    main, react = _pair(np.maximum(0.6 - 0.15 * t, react_x + 0.055), react_x)
    assert own_touches(main, react, 40.0, TOUCH_M) == 0


def test_the_shipped_lover_is_only_ever_touched_by_its_main():
    # the lover's 5 contacts are all its main's (it backs off); the stalker walks into its
    # stopping or reversing main 3 times, the bully 16, the playful friend 6
    counts = {}
    for name in PERSONALITIES:
        stored = library.load_behavior(examples.DEFAULT_OUT / name)
        counts[name] = Behavior.train(stored.demonstration, **stored.parameters).own_touches
    assert counts == {"lover": 0, "bully": 16, "playful_friend": 6, "stalker": 3, "afraid": 0}
    assert max(counts["lover"], counts["afraid"]) < MIN_OWN_TOUCHES <= counts["stalker"]
