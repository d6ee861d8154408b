"""The rhythm of a charging or darting character's pushes (issue 12, event figures): the steps
since the reactor last touched its main are a feature of the match (features.since_push,
Behavior.charging, Behavior.circling), counted alike for the demonstration's samples and live
(the live push of a character that only circles: where the pucks touch, Behavior.live_touch),
so the bully charges as often as its designer's own character beside slow and fast mains alike,
and the playful friend's darts touch its main as regularly as its designer's."""

import numpy as np

from behaviors.puppet_master import designers, features, fidelity
from behaviors.puppet_master.behavior import Behavior
from behaviors.puppet_master.character import PUCK_M, TOUCH_M
from tabletop import examples
from tests.puppet_master.demos import shipped, unseen_main_paths

TABLE = (0.0, 0.0, *examples.TABLE)


def _pushes(main: np.ndarray, react: np.ndarray) -> int:
    """Contact episodes: runs of samples nearer the main than TOUCH_M (positions (n, 2+))."""
    near = np.hypot(*(react[:, :2] - main[:, :2]).T) < TOUCH_M
    return int(near[0]) + int(np.sum(near[1:] & ~near[:-1]))


def test_the_steps_since_the_last_push_count_from_each_touch_up_to_the_longest_wait():
    d = np.array([0.3, 0.05, 0.2, 0.2, 0.2, 0.06, 0.2, 0.2, 0.2, 0.2, 0.2, 0.2])
    # the start counts as a push; the longest wait before a touch: 3 steps (samples 2-4)
    assert features.push_interval(d, TOUCH_M) == 3.0
    assert features.since_push(d, TOUCH_M, 3.0).tolist() == [0, 0, 1, 2, 3, 0, 1, 2, 3, 3, 3, 3]
    live, since = [0.0], 0.0
    for x in d[1:]:
        since = features.since_step(since, float(x), TOUCH_M, 3.0)
        live.append(since)
    assert live == features.since_push(d, TOUCH_M, 3.0).tolist()
    assert features.push_interval(np.full(5, 0.3), TOUCH_M) == 0.0


def test_only_a_character_that_charges_or_circles_and_darts_counts_the_steps_since_a_push():
    for name in ("bully", "lover", "playful_friend", "stalker", "afraid"):
        b = shipped(name)
        assert b.charging == (name == "bully") and b.circling == (name == "playful_friend")
        assert (b.scales.since > 0.0) == (name in ("bully", "playful_friend"))
    assert shipped("playful_friend").since_clip == 395.0   # its longest wait, 9.9 s
    b = shipped("bully")
    assert b.since_clip == 152.0           # its longest wait, 3.8 s
    col = features.since_column(b.scales)
    since = features.since_push(b.distance, TOUCH_M, b.since_clip)
    assert np.array_equal(b.situation_vectors[:, col], b.scales.since * since)
    col = features.since_column(b.scales, features.COHERENCE_DIMS)
    assert np.array_equal(b.coherence_vectors[:, col], b.scales.since * since)


def test_the_bully_pushes_as_often_as_its_designer_beside_slow_and_fast_mains():
    # contact episodes on the slow and fast paths of seeds 0-5 against its designer's own
    # character on the same paths: a path's count off the designer's by 0.92 on average
    # (slow 10.3, fast 10.7 against 10.0 and 11.5); 2.08 (slow 11.2, fast 9.2) while the lurk
    # between pushes lasted as long as the re-matching let it (no steps since the last push
    # among the features)
    b = shipped("bully")
    rate = b.params.rate_hz
    off, fast = [], []
    for seed in range(6):
        for path, main in unseen_main_paths(seed, 40.0, examples.TABLE).items():
            if path.startswith("loops"):
                continue
            rows = fidelity.generate(b, main, TABLE)
            gen = _pushes(fidelity.main_on_grid(main, rows[:, 0]), rows[:, 1:])
            t, react = designers.reaction_on_grid("bully", main, rate, examples.TABLE)
            own = _pushes(fidelity.main_on_grid(main, t), react)
            off.append(abs(gen - own))
            if path.startswith("fast"):
                fast.append(gen - own)
    assert len(off) == 12 and np.mean(off) <= 1.3, off
    assert np.mean(fast) >= -1.5, fast


def test_the_playful_friend_touches_its_main_as_regularly_as_its_designer():
    # contact share (within TOUCH_M) on the 18 unseen paths of seeds 0-5: spread (standard
    # deviation) over the paths 0.0127, mean 0.037, a path off its designer's own character
    # by 0.0116 on average (the designer: 0.0092, 0.035); its live push counted under TOUCH_M
    # as the demonstration's (Behavior.live_touch) 0.0079, 0.029 and 0.0093; 0.0149, 0.036
    # and 0.018 with the darts timed by the re-matching alone (no steps since the last touch
    # among the features)
    b = shipped("playful_friend")
    rate = b.params.rate_hz
    gen, own = [], []
    for seed in range(6):
        for main in unseen_main_paths(seed, 40.0, examples.TABLE).values():
            rows = fidelity.generate(b, main, TABLE)
            near = np.hypot(*(rows[:, 1:3] - fidelity.main_on_grid(main, rows[:, 0])[:, :2]).T)
            gen.append(float(np.mean(near < TOUCH_M)))
            t, react = designers.reaction_on_grid("playful_friend", main, rate, examples.TABLE)
            near = np.hypot(*(react[:, :2] - fidelity.main_on_grid(main, t)[:, :2]).T)
            own.append(float(np.mean(near < TOUCH_M)))
    gen_a, own_a = np.array(gen), np.array(own)
    assert len(gen) == 18 and np.std(gen_a) <= 0.014 and np.mean(gen_a) >= 0.033, gen
    assert np.mean(np.abs(gen_a - own_a)) <= 0.013, (gen, own)


def _mains(paths: tuple[tuple[int, str], ...]) -> list[np.ndarray]:
    """The unseen main paths named by (seed, path kind)."""
    out = []
    for seed, kind in paths:
        mains = unseen_main_paths(seed, 40.0, examples.TABLE)
        out.append(next(m for p, m in mains.items() if p.startswith(kind)))
    return out


def _friend_contact(b: Behavior, mains: list[np.ndarray]) -> list[float]:
    """Contact share (within TOUCH_M) of the friend generated beside each main."""
    out = []
    for main in mains:
        rows = fidelity.generate(b, main, TABLE)
        near = np.hypot(*(rows[:, 1:3] - fidelity.main_on_grid(main, rows[:, 0])[:, :2]).T)
        out.append(float(np.mean(near < TOUCH_M)))
    return out


def test_the_playful_friends_darts_reach_its_main_beside_a_looping_main():
    # contact on the loops paths where the engine alone once missed it (seeds 0, 4, 41, 42,
    # 46): 0.029, 0.037, 0.038, 0.023, 0.025 (mean 0.030), its entered darts kept whole
    # (darts.py); 0.025, 0.043, 0.024, 0.026, 0.034 (mean 0.030) before, its live push then
    # counted under TOUCH_M 0.019, 0.013, 0.018, 0.020, 0.013, all under the bench's band
    b = shipped("playful_friend")
    low = fidelity.demonstration_figures(b)["contact"] - fidelity.EVENT_FLOOR["contact"]
    darts = _friend_contact(b, _mains(tuple((s, "loops") for s in (0, 4, 41, 42, 46))))
    assert min(darts) >= low and np.mean(darts) >= 0.028, (darts, low)


def test_the_playful_friend_counts_its_live_push_only_where_the_pucks_touch(monkeypatch):
    # its live push counted only where the pucks touch (PUCK_M, Behavior.live_touch): a dart
    # stopping within TOUCH_M's slack no longer restarts the steps since the last push, so
    # the match takes the next run-up. Counted under TOUCH_M, the friend's own misses (its
    # designer meeting the band) summed over five runs (1, 1 +- 0.001, 1 +- 0.002 x the
    # demonstration's drift) on seeds 0-5 / 40-51 / 128-139 / 300-311: 13 / 25 / 15 / 14
    # against 3 / 11 / 15 / 11. On seed 48's loops and 129's fast path its contact falls
    # under the band (low edge 0.021): 0.036, 0.041 -> 0.016, 0.019 (the loops of seeds 5,
    # 45, 51: 0.046, 0.039, 0.029 -> 0.018, 0.018, 0.013)
    b = shipped("playful_friend")
    assert b.live_touch == PUCK_M and shipped("bully").live_touch == TOUCH_M
    low = fidelity.demonstration_figures(b)["contact"] - fidelity.EVENT_FLOOR["contact"]
    mains = _mains(((48, "loops"), (129, "fast")))
    touch = _friend_contact(b, mains)
    assert min(touch) >= low, (touch, low)
    monkeypatch.setattr(b, "live_touch", TOUCH_M)
    slack = _friend_contact(b, mains)
    assert max(slack) < low, (slack, low)
