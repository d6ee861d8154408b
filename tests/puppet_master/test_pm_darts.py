"""A circling character's darts into its main (behaviors/puppet_master/darts.py): the
playful friend's demonstrated darts found in its run-ups, and a dart the match has entered
kept whole while its live main closes in no faster than the moment's main did."""

from __future__ import annotations

from collections import deque

import numpy as np
import pytest

from behaviors.puppet_master.behavior import Behavior
from behaviors.puppet_master.character import TOUCH_M
from behaviors.puppet_master.darts import (DART_DEPTH, DART_MARGIN, dart_goes_on,
                                           span_approaches)
from tests.puppet_master.demos import shipped


@pytest.fixture(scope="module")
def friend() -> Behavior:
    return shipped("playful_friend")


def test_the_friends_run_ups_point_at_their_darts_bottoms(friend):
    b = friend
    assert b.darts and b.circling and not b.charging
    d, ends = np.asarray(b.distance), np.asarray(b.dart_end)
    run_up = np.flatnonzero(ends >= 0)
    # its designer's 10 darts (0.052-0.078 m at their bottoms), 106 run-up samples
    assert len(set(ends[run_up])) == 10 and len(run_up) > 80
    for i in run_up:
        j = ends[i]
        assert i < j and d[j] < TOUCH_M and d[i] - d[j] > DART_DEPTH
        assert d[i + 1] < d[i] and d[j] <= min(d[j - 1], d[j + 1])


def test_only_the_circling_character_keeps_its_darts():
    for name in ("lover", "bully", "stalker", "afraid"):
        b = shipped(name)
        assert not b.darts and max(b.dart_end) == -1, name


def test_a_kept_dart_ends_when_the_live_main_walks_in():
    n, dt = 10, 1.0 / 40.0
    friend_at = (0.2, 0.0)                       # from the main's last position (metres)
    walking_in = deque([(0.01 * k, 0.0) for k in range(n)], maxlen=20)   # 0.4 m/s at it
    standing = deque([(0.0, 0.0)] * n, maxlen=20)
    # the moment's main stood: a main closing 0.4 m/s over the span ends the dart, one
    # closing within DART_MARGIN of it or standing does not
    assert not dart_goes_on(walking_in, n, 0.0, dt, 0.1, 0.0, *friend_at)
    assert dart_goes_on(standing, n, 0.0, dt, 0.0, 0.0, *friend_at)
    slow = deque([(0.5 * DART_MARGIN * dt * k, 0.0) for k in range(n)], maxlen=20)
    assert dart_goes_on(slow, n, 0.0, dt, 0.5 * DART_MARGIN * dt * n, 0.0, *friend_at)
    # the moment's main walked in as fast: the dart goes on
    assert dart_goes_on(walking_in, n, 0.1, dt, 0.1, 0.0, *friend_at)
    # fewer positions than the span known: it goes on
    assert dart_goes_on(deque(list(walking_in)[:n - 1]), n, 0.0, dt, 0.1, 0.0, *friend_at)


def test_the_demonstrated_main_approach_is_read_over_the_span():
    main = np.column_stack([np.linspace(0.0, 0.3, 31), np.zeros(31)])   # 1 cm a sample
    react = np.column_stack([np.full(31, 0.5), np.zeros(31)])           # ahead of it
    a = span_approaches(main, react, 10)
    assert a[:10] == [0.0] * 10
    assert a[10:] == pytest.approx([0.1] * 21)
    away = span_approaches(main, -react, 10)                            # behind it
    assert away[10:] == pytest.approx([-0.1] * 21)
