"""Coverage counts only arc the performance went along (:mod:`behaviors.mop.coverage`): a still
puck drives nothing whatever the forward window, through ``tabletop follow`` and in a group."""

import csv

import numpy as np

from behaviors.mop.follower import ActionFollower
from behaviors.mop.group import FollowerGroup
from tabletop.cli import main as cli

from tests.mop.helpers import EXAMPLES
from tests.mop.test_group import _step_both

NAMES = ("circle", "zigzag", "figure_eight", "line", "square", "wave")


def _still(seed: int, n: int = 300) -> np.ndarray:
    """``n`` samples (10 s at 30 Hz) of a puck lying still: dx, dy metres, 0.7 mm jitter."""
    return np.random.default_rng(seed).normal(0.0, 0.0007, (n, 2))


def test_tabletop_follow_with_a_wide_window_drives_nothing_on_a_still_puck(tmp_path):
    # follow's defaults (features as recorded) with the six example gestures: a window of
    # half-width 40 holds the whole line, whose end lies 0.11 sigma from its start; the end
    # won after 3-8 s, its progress 0 -> 0.99 counted as covered arc: 200 of 300 rows valid
    # on this draw (231 on draw 3), none with --window 15; none at either with the bound
    path = tmp_path / "still.csv"
    with path.open("w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["t", "dx", "dy"])
        w.writerows([i / 30.0, *x] for i, x in enumerate(_still(1)))
    gestures = EXAMPLES / "mop" / "gestures"
    templates = [a for n in NAMES for a in ("--template", f"{n}={gestures / f'{n}.csv'}")]
    out = tmp_path / "out.csv"
    assert cli(["follow", *templates, "--input", str(path), "--out", str(out),
                "--window", "40"]) == 0
    with out.open(newline="") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 300
    assert sum(r["valid"] == "1" for r in rows) <= 3


def test_a_group_with_a_wide_window_drives_nothing_on_still_pucks_as_its_followers_alone(
        gestures):
    # the compiled group bounds the covered arc as the follower does (draws 1 and 3: 200 and
    # 231 of 300 samples valid without the bound)
    streams = [_still(1), _still(3)]
    alone = [ActionFollower(gestures, window=40) for _ in streams]
    group = FollowerGroup([ActionFollower(gestures, window=40) for _ in streams])
    assert _step_both(alone, group, streams) <= 6
