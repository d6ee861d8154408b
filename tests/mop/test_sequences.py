"""Gesture after gesture with no rest: an action whose performer finished it hands over."""

import math

import numpy as np
import pytest

from behaviors.mop import handover, spotting, take_rule
from behaviors.mop.follower import ActionFollower
from behaviors.mop.group import FollowerGroup
from behaviors.mop.follower_validity import Validity
from bench.follow_sequences import wrong_valid
from bench.motions import MOCAP, back_to_back, gesture_templates, mocap_templates


@pytest.fixture(scope="module")
def wave_then_run():
    """A wave at 0.88x, then a run's wrist stroke back along it at once (bench/motions.py's
    twenty-template draw, seed 2, its first two gestures), with the six gestures and the run
    loaded: the follower lags the wave to 0.94 and never reaches its end."""
    everything = {**gesture_templates(), **mocap_templates(joints=MOCAP)}
    x, truth, prog, order = back_to_back(np.random.default_rng(2), everything, 4)
    cut = truth.index(order[2])
    names = [*gesture_templates(), "run_left_wrist"]
    return {n: everything[n] for n in names}, x[:cut], truth[:cut], prog[:cut], order[:2]


def _wrong_run(templates, x, truth, prog, order) -> tuple[int, list]:
    f = ActionFollower(templates, units=np.ones(2), invariance="scale")
    states = [f.step(s) for s in x]
    return wrong_valid(states, truth, prog, order, templates)["longest"], states


def test_an_action_finished_short_of_its_end_hands_over(wave_then_run, monkeypatch):
    # with the rule: the wave stops as its progress slides back from 0.95, the run is followed
    # from where the wave ended; without it the wave drove the run's first 5 samples backwards
    # (the end at the wave's tempo, handover.tempo_ended, left out: it ends the wave too)
    # (nothing vetoed as an overrun either: overrun.overruns takes these samples too)
    monkeypatch.setattr(Validity, "_overruns", lambda self, k, g, x, progress: False)
    every, states = _wrong_run(*wave_then_run)
    monkeypatch.setattr(spotting, "TEMPO_END_FROM", 9.0)
    on, _ = _wrong_run(*wave_then_run)
    monkeypatch.setattr(handover, "FINISH_FROM", 9.0)
    off, _ = _wrong_run(*wave_then_run)
    assert max(every, on) <= 2 < off, (every, on, off)
    truth, prog = wave_then_run[2], wave_then_run[3]
    got = [p for s, t, p in zip(states, truth, prog) if t == "run_left_wrist" and s.valid
           and s.best == t]
    # recognised as from rest (its first sample held still 30 ticks before it) but a sample:
    # its tempo is read from where its attempt began (tempo.before_attempt), over the attempt's
    # own samples (tempo.span): 0.155, from rest 0.102 (both 0.209 with the demand over the
    # whole window); the sample is the wave's end, read only as the input moved on (the attempt
    # begins at 0.102 there, at 0.050 from rest)
    start = truth.index("run_left_wrist")
    x = wave_then_run[1][start:]
    alone = ActionFollower(wave_then_run[0], units=np.ones(2), invariance="scale")
    rest = [alone.step(x[0]) for _ in range(30)]
    from_rest = [p for s, p in zip([alone.step(s) for s in x], prog[start:])
                 if s.valid and s.best == "run_left_wrist"]
    assert not any(s.valid for s in rest) and got and from_rest, (got[:1], from_rest[:1])
    assert got[0] <= from_rest[0] + 0.06 and got[0] <= 0.17, (got[0], from_rest[0])


def test_a_group_ends_a_finished_action_as_its_followers_alone(wave_then_run):
    templates, x = wave_then_run[0], wave_then_run[1]
    kws = [dict(units=np.ones(2), invariance="scale"),
           dict(units=np.ones(2), invariance="scale", confirm=1)]
    alone = [ActionFollower(templates, **kw) for kw in kws]
    group = FollowerGroup([ActionFollower(templates, **kw) for kw in kws])
    from tests.mop.test_group import _same
    handed = 0
    for s in x:
        a = [f.step(s) for f in alone]
        for u, v in zip(a, group.step([s, s])):
            _same(u, v)
        handed += a[0].best == "run_left_wrist" and a[0].valid
    assert handed > 10


@pytest.fixture(scope="module")
def crawl_stream():
    """A crawl's wrist at 0.81x (bench/motions.py's twenty-template draw, seed 2, its third
    sequence, the crawl and the start of the zigzag after it), the twenty templates loaded: the
    crawl's follower stalls at 0.20 (its size still 1.02) and is refused at 0.31, where the figure
    eight becomes ``best``."""
    everything = {**gesture_templates(), **mocap_templates(joints=MOCAP)}
    rng = np.random.default_rng(2)
    for _ in range(3):
        x, truth, prog, order = back_to_back(rng, everything, 4)
    return everything, x[:60], truth[:60], prog[:60], order


def test_a_new_best_drives_only_after_its_own_confirmation(crawl_stream):
    # the confirmation run belonged to no action: the figure eight took over the crawl's run
    # and drove in the very sample it became best (9 wrong ticks; 8 with its own two)
    everything, x, truth, prog, order = crawl_stream
    f = ActionFollower(everything, units=np.ones(2), invariance="scale")
    states = [f.step(s) for s in x]
    sudden = [t for t in range(1, len(x))
              if states[t].valid and states[t].best != states[t - 1].best]
    assert not sudden, sudden
    assert any(s.valid and s.best == "crawl_right_wrist" for s in states)
    assert wrong_valid(states, truth, prog, order, everything)["longest"] <= 8


def _group_equals_alone(everything: dict, x: np.ndarray, confirms: tuple[int, int]) -> None:
    """A group of two scale-invariant followers (their ``confirm`` given) steps as each alone."""
    kws = [dict(units=np.ones(2), invariance="scale", confirm=c) for c in confirms]
    alone = [ActionFollower(everything, **kw) for kw in kws]
    group = FollowerGroup([ActionFollower(everything, **kw) for kw in kws])
    from tests.mop.test_group import _same
    for s in x:
        for u, v in zip([f.step(s) for f in alone], group.step([s, s])):
            _same(u, v)


def test_a_group_confirms_a_new_best_as_its_followers_alone(crawl_stream):
    _group_equals_alone(crawl_stream[0], crawl_stream[1], (2, 3))


@pytest.fixture(scope="module")
def dance_then_punch():
    """A dance's wrist at 0.80x, then a punch's wrist at once (bench/motions.py's
    twenty-template draw, seed 6, its first sequence, up to the punch's 0.2), the twenty
    templates loaded: the follower lags the dance to 0.93 and creeps on at its end (0.93 ->
    0.94) as the punch begins, never sliding back."""
    everything = {**gesture_templates(), **mocap_templates(joints=MOCAP)}
    x, truth, prog, order = back_to_back(np.random.default_rng(6), everything, 4)
    cut = truth.index(order[3]) + 12
    return everything, x[:cut], truth[:cut], prog[:cut], order


def test_an_action_followed_at_a_crawl_past_its_finish_hands_over(dance_then_punch, monkeypatch):
    # with the rule the dance stops as it crawls past 0.9 (the punch's 2 first samples); without
    # it the dance drove the punch's first 7, until it crawled CRAWL_SAMPLES samples (measured
    # with the last samples' fit, take_rule.TAKE_MISFIT2, lifted: with it neither drives them)
    monkeypatch.setattr(take_rule, "TAKE_MISFIT2", math.inf)
    # (nothing vetoed as an overrun either: overrun.overruns takes these samples too)
    monkeypatch.setattr(Validity, "_overruns", lambda self, k, g, x, progress: False)
    everything, x, truth, prog, order = dance_then_punch
    begin = truth.index(order[2])   # over the dance and the punch (the kick's end is another)

    def longest() -> int:
        _, states = _wrong_run(*dance_then_punch)
        return wrong_valid(states[begin:], truth[begin:], prog[begin:], order,
                           everything)["longest"]
    on = longest()
    monkeypatch.setattr(handover, "FINISH_CRAWLS", False)
    off = longest()
    assert on <= 2 < off, (on, off)


def test_a_group_hands_over_a_crawling_finished_action_as_its_followers_alone(dance_then_punch):
    _group_equals_alone(dance_then_punch[0], dance_then_punch[1], (2, 1))


@pytest.fixture(scope="module")
def kick_then_dance():
    """A kick's ankle, then a dance's wrist at once (bench/follow_widened.py's twenty-template
    draws, seed 1201, its seventh sequence, the first two gestures and the third's first
    samples), the six gestures and the sequence's four clips loaded: the kick eases into its end
    (1-2 mm a sample over its last 20%), the follower crosses it at about a state a sample and is
    at 0.94 when the performer, at 1.5 states a sample, reaches its last point."""
    everything = {**gesture_templates(), **mocap_templates(joints=MOCAP)}
    rng = np.random.default_rng(1201)
    for _ in range(7):
        x, truth, prog, order = back_to_back(rng, everything, 4)
    cut = truth.index(order[2]) + 5
    names = [*gesture_templates(), *map(str, order)]
    return {n: everything[n] for n in names}, x[:cut], truth[:cut], prog[:cut], order


def test_an_action_lagging_on_its_eased_end_ends_at_its_tempo(kick_then_dance, monkeypatch):
    # with the rule the kick ends where its tempo before the eased stretch reaches its end: it
    # drives the dance's first 2 samples (the grace); without it 3, its end reached a sample
    # into the dance
    templates, x, truth, prog, order = kick_then_dance
    on, states = _wrong_run(*kick_then_dance)
    monkeypatch.setattr(spotting, "TEMPO_END_FROM", 9.0)   # (read there, from handover)
    off, _ = _wrong_run(*kick_then_dance)
    assert on <= 2 < off, (on, off)
    kicked = [s.valid and s.best == t for s, t in zip(states, truth) if t == order[0]]
    assert np.mean(kicked[len(kicked) // 3:]) > 0.9   # the kick drives to its last sample
    assert kicked[-1]


def test_a_group_ends_a_lagging_action_at_its_tempo_as_its_followers_alone(kick_then_dance):
    _group_equals_alone(kick_then_dance[0], kick_then_dance[1], (2, 1))
