"""Following performances nobody scripted (a fixed subset of ``bench/follow_quality.py``): other
sizes, holds of other lengths, still input at any window, unrelated motion, and what a
performer sees before anything is recognised. Gestures back to back: ``test_spotting.py``."""

import math

import numpy as np
import pytest

from bench.follow_quality import puck_follower, true_metrics
from bench.motions import at_phase, performance, phase_of, raise_hold_return, unrelated_motions
from behaviors.mop import bends, shape_lead, take_rule
from behaviors.mop.follower import ActionFollower
from tests.mop.helpers import run, solo, widened_mirrored


def test_gestures_at_other_sizes_stay_valid_and_followed(gestures):
    # measured here: valid 0.817 of the time after 30% (0.7x / 1.4x: circle 0.77 / 1.0, wave
    # 0.72 / 1.0, figure eight 0.58 / 0.91, square 0.80 / 0.75: the 0.7x figure eight is lost to
    # other gestures while its size is still near 1, the square's first side is the line's
    # until 0.37 of it; behaviors.mop.invariance), second lowest 0.72 (bench, all twenty
    # templates: 0.91), RMSE median 0.02
    rng = np.random.default_rng(3)
    f = solo(puck_follower(gestures))
    after30, rmse = [], []
    for name in ("circle", "wave", "figure_eight", "square"):
        for scale in (0.7, 1.4):
            x, prog = performance(rng, gestures[name], scale)
            m = true_metrics(run(f, x), name, prog)
            after30.append(m["valid_after30"])
            rmse.append(m["rmse"])
    assert np.mean(after30) >= 0.8 and sorted(after30)[1] >= 0.7
    assert np.median(rmse) <= 0.05


def test_size_matters_to_the_follower_without_invariance(gestures):
    # the same performances with features as recorded: a 1.4x circle is refused for most of it
    rng = np.random.default_rng(3)
    plain = solo(ActionFollower(gestures, units=np.ones(2)))
    scaled = solo(puck_follower(gestures))
    x, prog = performance(rng, gestures["circle"], 1.4)
    assert (true_metrics(run(scaled, x), "circle", prog)["valid_after30"]
            >= true_metrics(run(plain, x), "circle", prog)["valid_after30"] + 0.3)


def test_a_hold_of_any_length_is_followed_without_sliding_back(gestures):
    rhr, spans = raise_hold_return()
    f = solo(puck_follower({**gestures, **rhr}))
    rng = np.random.default_rng(5)
    for name in ("arc_hold", "lift_hold"):
        for factor in (0.3, 3.0):
            # measured: RMSE 0.023-0.047 with the holds' states dwelling (0.8), 0.023-0.080
            # without (the lift at 0.3x ran through its hold into the return's eased start)
            x, prog = performance(rng, rhr[name], 1.0, hold=spans[name], hold_factor=factor)
            m = true_metrics(run(f, x), name, prog)
            assert m["rmse"] <= 0.06 and m["backward"] <= 0.05 \
                and m["valid_after30"] >= 0.8, (name, factor)


@pytest.mark.parametrize("rules", [True, False])
def test_a_smaller_lift_held_briefly_is_followed_through_its_hold(gestures, rules):
    # a lift at 0.8x: its size was overestimated during the raise, so the stop at the top read
    # as a stop short of it at 1x and the return was followed backwards along the raise.
    # Measured: RMSE 0.068 / 0.043 and 0.03 at 0.9x with the hold rules (behaviors.mop.holding),
    # 0.377 / 0.136 without (0.377 / 0.482 before the size was read less along the path,
    # invariance.ALONG)
    rhr, spans = raise_hold_return()
    f = puck_follower({**gestures, **rhr})
    if not rules:
        f._holds = None
    rng = np.random.default_rng(7)
    worst = []
    for factor in (0.3, 0.6):
        x, prog = performance(rng, rhr["lift_hold"], 0.8, hold=spans["lift_hold"],
                              hold_factor=factor)
        m = true_metrics(run(f, x), "lift_hold", prog)
        worst.append(max(m["rmse"], m["backward"]))
    if rules:
        assert max(worst) <= 0.08, worst
    else:
        assert min(worst) >= 0.12, worst


def test_the_group_reads_resting_as_its_followers_do():
    # holding.resting_with: the buffered samples before this one and this one
    from behaviors.mop.holding import resting_with
    from behaviors.mop.tempo import resting
    rng = np.random.default_rng(4)
    radius = np.array([1.0, 0.5])
    seen = set()
    for keep in (6, 5, 3):   # the member's still_samples (the group's buffer holds the largest)
        for count in list(range(keep + 1)) * 6:
            spread = rng.choice([0.2, 0.6, 1.5])
            buf = rng.normal(0, spread, (2, 6, 2))
            x = rng.normal(0, spread, (2, 2))
            recent = list(buf[1, 6 - count:]) if count else []
            want = resting(recent[1 - keep:] + [x[1]], radius)
            assert resting_with(buf, np.array([0, count], dtype=np.intp), 1, x, radius, keep) \
                == want, (keep, count)
            seen.add(want)
    assert seen == {True, False}


def test_a_still_puck_is_never_valid_whatever_the_window(gestures):
    # the floor is shared by the window's states: a wide window only reaches further.
    # Measured, a still puck of 3 s (seeds 0-5), the installation's puck follower and the
    # ``follow`` command's defaults: valid on no sample at windows 15, 20, 40, 80 and 200; with
    # the whole floor on each state (window_kernel's ``fl = floor``) 0.385 of the time at
    # window 40 in one draw of six (seed 2), the window's far states taking over
    for window in (15, 20, 40, 80):
        for f in (solo(puck_follower(gestures, window=window)),
                  solo(ActionFollower(gestures, window=window))):
            for seed in range(6):
                x, _ = performance(np.random.default_rng(seed), np.zeros((60, 2)), 1.0)
                assert not any(s.valid for s in run(f, x)), (seed, window)


def test_a_mirrored_gesture_is_refused(gestures):
    # measured with one template loaded: circle, figure eight and square mirrored 0% valid
    # (zigzag 33%, wave 34%, line 45%: their mirror images share long stretches with them)
    for name in ("circle", "figure_eight", "square"):
        rng = np.random.default_rng(4)
        f = solo(puck_follower({name: gestures[name]}))
        x, _ = performance(rng,
                           unrelated_motions(rng, {name: gestures[name]})[f"mirrored_{name}"], 1.0)
        assert np.mean([s.valid for s in run(f, x)]) <= 0.1, name


def test_the_threshold_models_mirror_chains_refuse_a_template_drawn_mirrored():
    # threshold.MIRROR_KEEP: among the twenty templates, the dance wrist mirrored at 0.7x (seed
    # 208) was driven by the zigzag 0.239 of the time and the square mirrored at 1.4x (seed
    # 206) by the roll ankle 0.212 without the mirror chains; measured 0.056 and 0 with them.
    # The templates themselves still drive: valid after 30% 0.94-1.0 and 0.73-0.91 (both alike)
    from bench.motions import MOCAP, gesture_templates, mocap_templates
    templates = {**gesture_templates(), **mocap_templates(joints=MOCAP)}
    f = solo(puck_follower(templates))
    for seed, name, scale in ((208, "dance_a_left_wrist", 0.7), (206, "square", 1.4)):
        x = widened_mirrored(seed, name, scale)
        assert np.mean([s.valid for s in run(f, x)]) <= 0.1, name
        rng = np.random.default_rng(1)
        for s in (0.7, 1.0, 1.4):
            x, prog = performance(rng, templates[name], s)
            assert true_metrics(run(f, x), name, prog)["valid_after30"] >= 0.6, (name, s)


def test_the_likeliest_actions_are_known_before_any_is_valid(gestures):
    rng = np.random.default_rng(6)
    f = puck_follower(gestures)
    x, prog = performance(rng, gestures["circle"], 1.0)
    states = run(f, x)
    first_valid = next(i for i, s in enumerate(states) if s.valid and s.best == "circle")
    early = [s for s in states[:first_valid] if s.likely]
    assert early, "nothing was suggested before the action was recognised"
    assert any("circle" in [name for name, _, _ in s.likely] for s in early)
    # while the puck waits before the gesture, nothing is suggested
    assert not any(s.likely for s in states[6:12])


def _unrelated_shares(gestures, **kw):
    """Valid share of the diagonal, spiral, wander and triangle (0.7, 1.0, 1.4x) with the circle
    alone and with the six gestures loaded (seeded), stepped by a group of one
    (:func:`~tests.mop.helpers.solo`)."""
    out = {}
    for key, loaded in (("circle", {"circle": gestures["circle"]}), ("six", gestures)):
        rng = np.random.default_rng(11)
        f = solo(puck_follower(loaded, **kw))
        paths = unrelated_motions(rng, loaded)
        for name in ("diagonal", "spiral", "wander", "triangle"):
            shares = []
            for scale in (0.7, 1.0, 1.4):
                x, _ = performance(rng, paths[name], scale)
                shares.append(np.mean([s.valid for s in run(f, x)]))
            out[f"{key}:{name}"] = float(np.mean(shares))
    return out


def test_unrelated_motion_rarely_drives(gestures, monkeypatch):
    # a template drives once its followed progress covered 8% of its path and while the input
    # keeps to its path; measured: mean valid share 0.103 with them, 0.197 without (the
    # triangle's first stroke is the line's outward half, a diagonal the figure eight's start:
    # they stay valid for those stretches; validity.stalls and tempo.crawls take part of
    # what they would: without crawls 0.121 with them, 0.251 without); all measured with the
    # last samples' fit (take_rule.TAKE_MISFIT2) lifted, which takes most of what they take
    # (bends.STRAYS off: its straight strokes are ones the templates stray from; the rule
    # would hide what this one measures)
    monkeypatch.setattr(bends, "STRAYS", 0.0)   # read at each step
    monkeypatch.setattr(take_rule, "TAKE_MISFIT2", math.inf)   # read at each step
    now = _unrelated_shares(gestures)
    before = _unrelated_shares(gestures, coverage=0.0, shape_distance=99.0, shape_accept=98.0)
    assert np.mean(list(now.values())) <= 0.25, now
    assert np.mean(list(now.values())) <= np.mean(list(before.values())) - 0.07, (now, before)
    # with the circle alone, an aimless wander and a spiral drive it at most a tenth of the time
    # (measured 0.03 and 0; without the rules 0.42 and 0.05)
    assert now["circle:wander"] <= 0.1 and now["circle:spiral"] <= 0.1, now
    # the threshold model (every template's states in any order) takes the probability pieces
    # of the six gestures stitched together need to drive; alone it cannot compete with one
    # template's own order. Measured: six gestures loaded, mean 0.326 with it, 0.352 without
    # (spiral 0.18 vs 0.25, triangle 0.41 vs 0.45); no motion drives more with it. Compared
    # without shape_lead.TAKE_FIT, which now refuses most of the spiral the threshold model took
    # (0.0709 with it, 0.0717 without)
    monkeypatch.setattr(shape_lead, "TAKE_FIT", math.inf)   # (read where the group is built)
    now = _unrelated_shares(gestures)
    plain = _unrelated_shares(gestures, threshold=float("inf"))
    six = [k for k in now if k.startswith("six:")]
    assert np.mean([now[k] for k in six]) <= np.mean([plain[k] for k in six]) - 0.015, (now, plain)
    assert all(now[k] <= plain[k] + 0.01 for k in now), (now, plain)


def _unrelated_target(gestures) -> tuple[dict, dict]:
    """Per loaded set and motion (bench/follow_quality.py's unrelated motions at 0.7, 1.0,
    1.4x; seed 11): the share of ticks valid, and of those where the motion so far is no start
    of the action driving (``told``, :func:`bench.follow_unrelated.performs`)."""
    from bench.follow_unrelated import performs
    valid, told, memo = {}, {}, {}
    for key in ("square", "six"):
        loaded = gestures if key == "six" else {key: gestures[key]}
        rng = np.random.default_rng(11)
        f = solo(puck_follower(loaded))
        for name, path in unrelated_motions(rng, loaded).items():
            v, t = [], []
            for scale in (0.7, 1.0, 1.4):
                x, prog = performance(rng, path, scale)
                states = run(f, x)
                p = np.where(np.isfinite(prog[:, 0]), prog[:, 0],
                             np.arange(len(x)) > np.argmax(np.isfinite(prog[:, 0])))
                v.append(np.mean([s.valid for s in states]))
                t.append(np.mean([s.valid and not performs(path, float(q), loaded[s.best], memo,
                                                           (key, name, s.best))
                                  for s, q in zip(states, p)]))
            valid[f"{key}:{name}"], told[f"{key}:{name}"] = float(np.mean(v)), float(np.mean(t))
    return valid, told


def test_unrelated_motions_drive_a_tenth_of_the_time_at_most(gestures):
    # the target on a fixed subset: a diagonal, a triangle, a spiral, a wander, a still
    # puck and the mirrored gestures, with the square alone or all six loaded. Measured: valid
    # at most 0.093 (the triangle, the square alone), but the diagonal among the six 0.134, the
    # figure eight whose first stroke it is (told 0.042); with the coverage and path-misfit
    # rules off (coverage 0, shape limits 99 sigma): the triangle 0.131 with the square, the
    # wander among the six 0.184
    valid, told = _unrelated_target(gestures)
    assert max(told.values()) <= 0.1, told
    assert max(v for k, v in valid.items() if k != "six:diagonal") <= 0.1, valid
    assert valid["six:diagonal"] <= 0.15, valid


def _tail_and_paused(gestures) -> tuple[int, int, float]:
    """Valid ticks of the diagonal, wander and triangle (0.7, 1.4x; the circle alone and the six
    gestures loaded) while their last half second rests, all their valid ticks, and the six
    gestures' share after 30% valid and within 0.1 of the truth when paused 0.6 s part way
    (0.7, 1.4x, two seeds), stepped by a group of one (:func:`~tests.mop.helpers.solo`). Shared
    starts off (``share_radius`` 0): the rule's own effect (with them on the wrong ticks it
    removes are fewer)."""
    tail = total = 0
    for loaded in ({"circle": gestures["circle"]}, gestures):
        rng = np.random.default_rng(5)
        f = solo(puck_follower(loaded, share_radius=0.0))
        paths = unrelated_motions(rng, loaded)
        for name in ("diagonal", "wander", "triangle"):
            for scale in (0.7, 1.4):
                x, _ = performance(rng, paths[name], scale)
                valid = [s.valid for s in run(f, x)]
                tail += sum(valid[-15:])
                total += sum(valid)
    f = solo(puck_follower(gestures, share_radius=0.0))
    on_track = []
    for seed in (5, 6):
        rng = np.random.default_rng(seed)
        for name, tpl in gestures.items():
            for scale in (0.7, 1.4):
                x, prog = performance(rng, tpl, scale, pause_s=0.6)
                on_track.append(true_metrics(run(f, x), name, prog)["valid_on_track_after30"])
    return tail, total, float(np.mean(on_track))


def test_an_action_moved_on_the_spot_holds_no_resting_performer(gestures, monkeypatch):
    # a wander hovering at the circle's start, a diagonal stopped on the circle's chord: the
    # action taken was moved by the input without carrying it forward, and the performer then
    # rests; it does not hold them there (validity.stalls). The price: a gesture paused within
    # a few samples of its recognition at a slow tempo (a 0.7x figure eight, a 1.4x square:
    # 2 of 24 here). Measured: valid ticks in the resting tail 29 (without 35), in all 153 (162),
    # paused gestures valid on track after 30% 0.676 (0.712; with the path misfit at 1.4 sigma
    # instead of 1.2, refusal.py: 168 (177), 0.693 (0.718)); tempo.crawls and
    # validity.unjudged take part of what it took (before unjudged: 33 (47), 181 (198); without
    # crawls either: 44 (70), 257 (286)); with the take sizes up to 1.4 times the estimate
    # (take_rule.TAKE_SIZES), as here: 6 (12), 75 (84), 0.705 (0.728); up to 1.12, the
    # default, they take part of it too: 6 (9), 73 (76)
    from behaviors.mop import validity

    monkeypatch.setattr(take_rule, "TAKE_SIZES", (0.7, 0.8, 0.9, 1.0, 1.12, 1.25, 1.4))
    now = _tail_and_paused(gestures)   # (both read where the group is built)
    monkeypatch.setattr(validity, "CARRY_FIRST", -1.0)
    plain = _tail_and_paused(gestures)
    assert now[0] <= plain[0] - 5 and now[1] <= plain[1] - 5, (now, plain)
    assert now[2] >= plain[2] - 0.04, (now, plain)


def test_resting_reads_net_motion_not_jitter():
    # the bench's tracking jitter (0.7 mm) around a resting puck against a still radius of 0.9 mm
    # (twenty templates loaded), and a slow stroke (0.1 m in 3 s at 30 Hz)
    from behaviors.mop.tempo import resting
    rng = np.random.default_rng(0)
    radius = np.full(2, 0.0009)
    rest = [resting(list(rng.normal(0, 0.0007, (6, 2))), radius) for _ in range(500)]
    stroke = np.stack([np.linspace(0, 0.1, 90), np.zeros(90)], 1) + rng.normal(0, 0.0007, (90, 2))
    slow = [resting(list(stroke[i:i + 6]), radius) for i in range(84)]
    assert np.mean(rest) >= 0.95 and not any(slow), (np.mean(rest), np.mean(slow))
    assert not resting(list(rng.normal(0, 0.0007, (3, 2))), radius)   # too few samples to tell


def test_a_gesture_larger_than_recorded_is_sized_by_its_reach(gestures, monkeypatch):
    # motion-capture paths whose first stroke is fast and straight (size and progress are one
    # there), drawn 1.4x: measured valid after 30% 0.99 with the reach bound and the sizes
    # judged afresh, 0.84 with the bound alone, 0.78 with the judging alone, 0.64 with neither
    # (crawl and walk never recognised: refused at the stroke's end while the size was ~1)
    from bench.motions import mocap_templates
    from behaviors.mop import invariance
    clips = mocap_templates(joints=(("crawl", "right_wrist"), ("walk", "right_ankle"),
                                    ("cartwheel", "right_ankle"), ("punch", "left_ankle")))
    templates = {**gestures, **clips}
    shares = {}
    for rules in ("on", "off"):
        if rules == "off":
            monkeypatch.setattr(invariance, "REACH_BOUND", 0.0)
            monkeypatch.setattr(invariance, "REJUDGE", 0.0)
        f = solo(puck_follower(templates))   # (the bound and judging read where it is built)
        out = []
        for name in clips:
            for seed in range(3):
                x, prog = performance(np.random.default_rng(seed), templates[name], 1.4)
                out.append(true_metrics(run(f, x), name, prog)["valid_after30"])
        shares[rules] = out
    assert np.mean(shares["on"]) >= 0.95 and min(shares["on"]) >= 0.85, shares
    assert np.mean(shares["on"]) >= np.mean(shares["off"]) + 0.2, shares


def _there_and_back(gestures, name: str, seed: int, reach: float = 0.6) -> np.ndarray:
    """``name`` performed to ``reach`` of it, back along itself to its start, then resting."""
    rng = np.random.default_rng(seed)
    tpl = gestures[name]
    phase = phase_of(rng, len(tpl))[0]
    phase = phase[phase <= reach * (len(tpl) - 1)]
    path = at_phase(tpl, np.concatenate([phase, phase[::-1]]))
    x = np.concatenate([np.zeros((15, 2)), path, np.repeat(path[-1:], 25, axis=0)])
    return x + rng.normal(0, 0.0007, x.shape)


def test_an_action_does_not_hold_a_performer_resting_behind_where_it_began(gestures,
                                                                          monkeypatch):
    # a wave or a zigzag performed to 60%, back to its start and rested: the action stops
    # driving once the performer rests behind where it began driving (validity.rests_behind).
    # Measured: valid ticks in the resting tails 0 (25 without; 50 without it and without
    # the strained rule of invariance.PerformanceFrame._reversal_sizes, which keeps the zigzag
    # strained at its turn from being sized). The zigzag covered sooner than 8% of its path
    # (coverage.told_apart_arc) is refused on its way back by coverage.EARLY_FIT (and LATE_FIT)
    # before it rests (valid to sample 90 of the first draw, 100 without): lifted, so this rule
    # is what stops it
    from behaviors.mop import coverage, validity

    monkeypatch.setattr(coverage, "EARLY_FIT", math.inf)   # all read where the group is built
    monkeypatch.setattr(coverage, "LATE_FIT", math.inf)
    streams = [_there_and_back(gestures, n, s) for n in ("wave", "zigzag") for s in (0, 1)]
    f = solo(puck_follower(gestures))
    now = sum(sum(s.valid for s in run(f, x)[-25:]) for x in streams)
    monkeypatch.setattr(validity, "REST_BEHIND", -1.0)
    f = solo(puck_follower(gestures))
    plain = sum(sum(s.valid for s in run(f, x)[-25:]) for x in streams)
    assert now <= 2 and plain >= 20, (now, plain)


def test_a_gesture_drawn_smaller_is_sized_once_its_stroke_turns(gestures, monkeypatch):
    # on a straight stroke size and progress are one; what tells the size is what does not lie
    # along the template's direction (invariance.ALONG): a 0.85x crawl wrist and a 0.7x square,
    # each paused 0.6 s part way, three seeds. Measured valid after 30%: crawl 0.93 (0.54 with
    # the whole of each sample counted), square 0.32 (0.21); without the sizes at reversals
    # (invariance.REVERSAL_FIT), which lift both (square 0.34 and 0.29)
    from bench.motions import mocap_templates
    from behaviors.mop import invariance
    monkeypatch.setattr(invariance, "REVERSAL_FIT", 0.0)
    templates = {**gestures, **mocap_templates(joints=(("crawl", "right_wrist"),))}
    shares, now, plain = {}, invariance.ALONG, 1.0
    for along in (now, plain):   # (ALONG patched reaches the follower alone)
        monkeypatch.setattr(invariance, "ALONG", along)
        f = solo(puck_follower(templates)) if along == now else puck_follower(templates)
        for name, scale in (("crawl_right_wrist", 0.85), ("square", 0.7)):
            shares[along, name] = np.mean([
                true_metrics(run(f, x), name, prog)["valid_after30"]
                for x, prog in (performance(np.random.default_rng(seed), templates[name], scale,
                                            pause_s=0.6) for seed in range(3))])
    assert shares[now, "crawl_right_wrist"] >= 0.85, shares
    assert shares[now, "crawl_right_wrist"] >= shares[plain, "crawl_right_wrist"] + 0.3, shares
    assert shares[now, "square"] >= shares[plain, "square"] + 0.05, shares
