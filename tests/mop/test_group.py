"""FollowerGroup's batched per-member rules: equal to each follower stepped alone, through gesture
ends, rests, abandoned attempts, lost samples and members of different settings."""

import dataclasses
import math

from bench import synthetic_actions as g
import numpy as np
import pytest

from behaviors.mop import group_steps, member_spotting, members
from behaviors.mop.follower import ActionFollower
from behaviors.mop.group import FollowerGroup, _new_state
from behaviors.mop.state import FollowState


class Counting(ActionFollower):
    """A follower that records why each new attempt started (as its spotting decided)."""

    def reset(self) -> None:
        super().reset()
        self.why = getattr(self, "why", [])

    def _restart_here(self, x, forward, offset, still=False):
        self.why.append("waiting" if still else "ended" if self._end_x is not None
                        else "abandoned" if self._lost >= self.lost_samples else "resting")
        super()._restart_here(x, forward, offset, still)


def _close(a: float, b: float) -> bool:
    return abs(a - b) <= 1e-12 * max(1.0, abs(a), abs(b))


def _same(a, b) -> None:
    assert (a.best, a.valid, a.restarted, a.holding) == (b.best, b.valid, b.restarted, b.holding)
    assert [n for n, *_ in a.likely] == [n for n, *_ in b.likely]
    assert all(_close(u, v) for (_, *x), (_, *y) in zip(a.likely, b.likely)
               for u, v in zip(x, y))   # each one's probability and progress
    for k in ("progress", "variance", "loglik", "distance"):
        assert _close(getattr(a, k), getattr(b, k)), k
    for k in ("probabilities", "progress_by", "loglik_by", "scale_by"):
        x, y = getattr(a, k), getattr(b, k)
        assert list(x) == list(y) and all(_close(x[n], y[n]) for n in x), k


def _step_both(alone, group, streams) -> int:
    """Step the followers alone and the group on the same samples, checking every state the
    same; returns how many states were valid."""
    valid = 0
    for i in range(min(len(s) for s in streams)):
        xs = [s[i] for s in streams]
        for a, b in zip([f.step(x) for f, x in zip(alone, xs)], group.step(xs)):
            _same(a, b)
            valid += a.valid
    return valid


def _puck_members(rng: np.random.Generator, count: int, templates: int, n: int,
                  performed: int) -> tuple[list, FollowerGroup, list]:
    """``count`` members following puck paths (metres, scale invariance), each with
    ``templates`` of ``n`` samples: the followers alone, the same as a group, and each
    member's stream performing ``performed`` of its templates."""
    sets = [{f"p{c}t{i}": 0.1 * g.template(rng, n=n, d=2) for i in range(templates)}
            for c in range(count)]
    kw = dict(units=np.ones(2), invariance="scale")
    alone = [ActionFollower(s, **kw) for s in sets]
    group = FollowerGroup([ActionFollower(s, **kw) for s in sets])
    streams = [np.concatenate([g.perform(rng, s[f"p{c}t{i}"], g.warped_phase(rng, n))
                               for i in rng.integers(0, templates, performed)])
               for c, s in enumerate(sets)]
    return alone, group, streams


KINDS = [dict(invariance="scale"), dict(invariance="none"), dict(invariance="offset", end=0.9),
         dict(invariance="scale", tangent=0.3),
         dict(invariance="scale", still_samples=3, confirm=1),
         dict(invariance="offset", lost_samples=3, switch_margin=0.5, min_probability=0.4)]


@pytest.mark.parametrize("turn", [math.inf, 1.3])   # with the turning gate too (2-D members)
def test_a_group_spots_gesture_after_gesture_exactly_as_its_followers_alone(turn):
    # a draw whose run goes through every way an attempt starts afresh, a rest included (seed
    # 1; many draws give no rest, as the sizes are judged afresh, the size is read less along
    # the path and nothing is judged at rest, a new action is taken only while the gesture's
    # last samples fit its path, and the actions a performer rests in past 90% reach their end
    # at their tempo first, handover.tempo_ended)
    rng = np.random.default_rng(1)
    sets, streams = [], []
    for c in range(len(KINDS)):
        d = 2 + c % 3
        sets.append({f"m{c}t{i}": g.template(rng, n=int(rng.integers(10, 90)), d=d)
                     for i in range(int(rng.integers(1, 6)))})
        for t in sets[-1].values():   # a hold inside the longer templates (its states dwell)
            if len(t) >= 40:
                t[len(t) // 2:len(t) // 2 + 10] = t[len(t) // 2]
        parts = []
        # back to back or stopped short of the end, a rest, an unrelated stretch
        for j in range(4):
            t = list(sets[-1].values())[int(rng.integers(len(sets[-1])))]
            phase = g.warped_phase(rng, len(t))
            phase = phase[phase <= (len(t) - 1) * (0.93 if j % 2 else 1.0)]
            parts.append(rng.uniform(0.7, 1.4) * g.perform(rng, t, phase))
            parts.append(np.repeat(parts[-1][-1:], int(rng.integers(0, 14)), axis=0))
            parts.append(g.template(rng, n=int(rng.integers(10, 40)), d=d))
        s = np.concatenate(parts)
        s[rng.random(len(s)) < 0.04] = np.nan   # lost samples
        streams.append(s)
    alone = [Counting(s, turn_limit=turn, **kw) for s, kw in zip(sets, KINDS)]
    group = FollowerGroup([ActionFollower(s, turn_limit=turn, **kw) for s, kw in zip(sets, KINDS)])
    valid = _step_both(alone, group, streams)
    why = [w for f in alone for w in f.why]
    # the run went through every way an attempt starts afresh, and was followed in between
    assert {"waiting", "ended", "abandoned", "resting"} <= set(why), why
    assert valid > 150


def test_the_member_rules_equal_the_followers_own_operations():
    rng = np.random.default_rng(8)
    counts = np.array([1, 4, 7, 3])
    bounds = np.concatenate([[0], np.cumsum(counts)[:-1]])
    p = rng.choice([0.0, 0.1, 0.25, 0.5], size=counts.sum())   # many ties
    three = np.zeros(3, dtype=np.intp)
    for a, n in zip(bounds, counts):
        assert group_steps.first_max(p, a, a + n) == a + np.argmax(p[a:a + n])
        group_steps.top_three(p, a, a + n, three)
        want = a + np.argsort(-p[a:a + n], kind="stable")[:3]
        assert three[:len(want)].tolist() == want.tolist() and (three[len(want):] == -1).all()
    buf = rng.normal(size=(3, 5, 2))
    count = np.array([5, 2, 0])
    x = rng.normal(size=(3, 2))
    got = members.recent_mean(buf, count, 3, x)
    for m in range(3):
        rows = list(buf[m, 5 - min(count[m], 3):])
        assert np.array_equal(got[m], np.mean(rows + [x[m]], axis=0))
    # stillness: the last samples within twice the radius per column, after enough samples
    f = ActionFollower({"a": g.template(rng, n=30, d=2)}, still_samples=4)
    r = f._still_radius
    buf, count = np.zeros((1, 6, 2)), np.zeros(1, dtype=np.intp)
    for k, step in enumerate([0.0, 0.5, 0.9, -0.9, 0.2, 2.5, 0.0, 0.0, 0.0, 0.0]):
        x = (np.array([1.0, -2.0]) + step * r)[None, :]
        members.push(buf, count, x, 0, 4)
        assert members.still(buf, count, 0, 4, r) == f._still(x[0]), k


def test_gesture_end_rules_over_members_equal_the_followers_own():
    # where an ended gesture's input moved on or departed: inputs scattered around both limits
    rng = np.random.default_rng(12)
    f = ActionFollower({"a": g.template(rng, n=40, d=2), "b": g.template(rng, n=25, d=2)},
                       invariance="scale")
    group = FollowerGroup([f])
    f._anchor, f._size[:] = rng.normal(size=2), [1.3, 0.8]
    moved = gone = 0
    for k in range(2):
        f._end_x = f._rel[f.bank.starts[k] + f.bank.lengths[k] - 1] * f._units * f._size[k] \
            + f._anchor \
            + rng.normal(size=2) * f._still_radius
        last = group._rel[group._last_state[k]] * group._m_units[0] * f._size[k] + f._anchor
        f._end_last = f._last_point(k)   # frozen where the end was reached (spotting._spot)
        spread = group._scale[k] * f._size[k]
        for _ in range(300):
            x = f._end_x + rng.normal(size=2) * rng.choice([1.0, 3.0, 10.0]) * f._still_radius
            want = f._moved_on(x, k)
            assert member_spotting.moved_on(x, f._end_x, last, f._still_radius) == want
            d = math.sqrt(np.mean(((x - f._end_x) / spread) ** 2)) / f.sigma \
                * rng.uniform(0.8, 1.25)
            assert member_spotting.departed(x, f._end_x, spread, 2.0, (d * f.sigma) ** 2) \
                == f._departed(x, k, d)
            moved += want
            gone += f._departed(x, k, f.accept_distance)
    assert 100 < moved < 500 and 50 < gone < 550   # both sides of each limit were tried


class Returning(ActionFollower):
    """A follower that counts the gestures it ended by the input's return to their last point."""

    returned = 0

    def _returned(self, x, k, progress):
        back = super()._returned(x, k, progress)
        self.returned += back and self._end_x is None
        return back


def test_a_return_followed_backwards_ends_in_the_group_as_alone():
    from bench.motions import at_phase, gesture_templates, phase_of
    gestures = gesture_templates()
    rng = np.random.default_rng(3)
    kws = [dict(units=np.ones(2), invariance="scale"),
           dict(units=np.ones(2), invariance="scale", confirm=1)]
    streams = []
    for _ in kws:
        parts, at = [np.zeros((15, 2))], np.zeros(2)
        for name, size in (("line", 0.7), ("wave", 1.0), ("line", 0.75), ("circle", 1.0)):
            phase = phase_of(rng, len(gestures[name]))[0]
            parts.append(size * at_phase(gestures[name], phase) + at)
            at = parts[-1][-1].copy()
        streams.append(np.concatenate(parts) + rng.normal(0, 0.0007, (sum(map(len, parts)), 2)))
    alone = [Returning(gestures, **kw) for kw in kws]
    group = FollowerGroup([ActionFollower(gestures, **kw) for kw in kws])
    assert _step_both(alone, group, streams) > 100
    assert all(f.returned >= 1 for f in alone), [f.returned for f in alone]


def test_a_group_of_many_puck_templates_equals_its_followers_alone():
    # DESIGN's case in small: puck paths (metres), scale invariance, many rivals per member
    alone, group, streams = _puck_members(np.random.default_rng(3), 3, 30, 60, 4)
    streams[1][50:53] = np.nan   # one performer lost for a moment (the members' samples alike)
    valid = _step_both(alone, group, streams)
    assert valid > 90   # ticks where both drove: 99 (105 with take_rule.TAKE_SIZES up to 1.4)


def test_the_group_threshold_models_keep_the_followers_own_weights():
    # each state's weight equals the follower's own threshold model (zeros where it is 0),
    # with the sample's map and log-density terms taken from the per-template pass: to the
    # single precision's rounding of the log-densities (threshold.PRECISION: a log-density of
    # ~100 nats rounded to ~1e-5, the weight by as much; here at most 1.1e-5 apart)
    alone, group, streams = _puck_members(np.random.default_rng(8), 2, 25, 70, 3)
    # (the group keeps every member's ergodic weights, then every member's mirror chains')
    offsets = np.cumsum([0] + [len(f._threshold_alpha) // 2 for f in alone])
    chains = len(group._thr_alpha) // 2
    for i in range(min(len(s) for s in streams)):
        xs = [s[i] for s in streams]
        for a, b in zip([f.step(x) for f, x in zip(alone, xs)], group.step(xs)):
            _same(a, b)
        for f, lo, total in zip(alone, offsets, group._thr_total):
            n = len(f._threshold_alpha) // 2
            mine = np.concatenate([group._thr_alpha[lo:lo + n],
                                   group._thr_alpha[chains + lo:chains + lo + n]]) / total
            assert np.array_equal(mine == 0.0, f._threshold_alpha == 0.0)
            assert np.allclose(mine, f._threshold_alpha, rtol=1e-4, atol=0.0)
    assert 0.0 < np.mean(group._thr_alpha == 0.0) < 1.0


def test_a_group_with_shared_starts_equals_its_followers_alone():
    # spotting's shared starts (share_radius) batched: members with and without them (a stream
    # member has none), the six gestures performed back to back
    from bench.motions import at_phase, gesture_templates, phase_of
    gestures = gesture_templates()
    rng = np.random.default_rng(4)
    kws = [dict(units=np.ones(2), invariance="scale", share_radius=3.0),
           dict(units=np.ones(2), invariance="scale", share_radius=3.0, confirm=1),
           dict(units=np.ones(2), invariance="none", share_radius=3.0)]
    streams = []
    for _ in kws:
        parts, at = [np.zeros((15, 2))], np.zeros(2)
        for name in rng.permutation(list(gestures)):
            size = rng.uniform(0.7, 1.4)
            phase = phase_of(rng, len(gestures[name]))[0]
            parts.append(size * at_phase(gestures[name], phase) + at)
            at = parts[-1][-1].copy()
        streams.append(np.concatenate(parts) + rng.normal(0, 0.0007, (sum(map(len, parts)), 2)))
    alone = [ActionFollower(gestures, **kw) for kw in kws]
    group = FollowerGroup([ActionFollower(gestures, **kw) for kw in kws])
    assert group._sh_off.tolist()[2] == -1 and min(group._sh_off.tolist()[:2]) >= 0
    shares = [0, 0]
    for f, kw in zip(alone[:2], kws):   # the rule holds actions back in these streams
        rule = f._shares
        def counting(k, g, progress, rule=rule, i=kws.index(kw)):
            held = rule(k, g, progress)
            shares[i] += held
            return held
        f._shares = counting
    assert _step_both(alone, group, streams) > 100
    assert min(shares) >= 1, shares


def test_a_group_state_is_the_followers_state_of_the_same_values():
    # the group builds its states without the dataclass's __init__: every field, in order
    values = [f"value {i}" for i in range(len(dataclasses.fields(FollowState)))]
    assert _new_state(*values) == FollowState(*values)


def test_every_kernel_template_state_is_kept_by_the_group_and_reset_on_a_new_attempt():
    """Each per-template float and flag the compiled kernel updates is an array of the group
    (shared with the followers or the group's own spotting state, so a lost sample keeps it) and
    is set afresh when a new attempt starts."""
    from behaviors.mop.group_layout import FLAGS, FLOATS
    from behaviors.mop.group_rules import RESTART_ONE, RESTART_ZERO
    kept = set(FollowerGroup._PER_TEMPLATE + FollowerGroup._GROUP_TEMPLATE)
    reset = set(RESTART_ZERO + RESTART_ONE)
    assert set(RESTART_ONE) <= set(FLOATS)
    assert not set(RESTART_ZERO) & set(RESTART_ONE)
    for name in FLOATS + FLAGS:
        assert name in kept, f"{name} is not kept by the group"
        assert name in reset, f"{name} is not reset on a new attempt"


def test_one_templates_kernel_state_is_one_record_shared_with_its_follower():
    """The per-template state the compiled pass updates lies template by template (one record of
    25 floats, one of 8 flags: group_layout.FLOATS; as rows, ~40 streams cost DESIGN's pass
    56-162 us cold), each name a view of its column, a follower's of its share of it."""
    from behaviors.mop.group_layout import FLAGS, FLOATS
    _, group, _ = _puck_members(np.random.default_rng(5), 2, 4, 20, 2)
    k = len(group._owner)
    for whole, names in ((group._floats, FLOATS), (group._flags, FLAGS)):
        assert whole.shape == (k, len(names)) and whole.flags.c_contiguous
        for j, name in enumerate(names):
            view = getattr(group, name)
            assert view.base is whole and view.strides == (whole.strides[0],)
            view[1] = 1 - view[1] if view.dtype == bool else view[1] + j + 1.0
            assert whole[1, j] == view[1]
            for f, sl in zip(group.followers, group._slices):
                if name in group._PER_TEMPLATE:
                    assert np.shares_memory(getattr(f, name), whole[sl, j])


def test_a_restarted_member_forgets_its_end_at_the_tempo_as_a_follower_does():
    # ActionFollower._forget and GroupRules._forget_members both forget the driving action's
    # last progress values and whether its end was reached at its tempo (handover.tempo_ended)
    rng = np.random.default_rng(3)
    templates = {f"t{i}": g.template(rng, n=30, d=2) for i in range(3)}
    alone, group = ActionFollower(templates), FollowerGroup([ActionFollower(templates)])
    alone._end_history, alone._lagged = [0.95] * 5, True
    group._end_history_n[0], group._lagged[0] = 5, True
    alone._forget()
    group._forget_members(0)
    assert group._end_history_n[0] == len(alone._end_history) == 0
    assert not group._lagged[0] and not alone._lagged


@pytest.mark.parametrize("kw", [dict(window=4), dict(window=15), dict(window=80),
                                dict(coverage=0.0, shape_distance=99.0, shape_accept=98.0)])
def test_a_group_of_one_with_the_options_the_tests_run_equals_its_follower_alone(kw):
    # the options of the MOP tests' runs stepped by a group of one (tests/mop/helpers.solo):
    # other windows (test_quality's still puck, test_window's 4-60) and the coverage and
    # path-misfit rules off (test_quality's unrelated motions); four gestures back to back,
    # every tick equal
    from bench.follow_quality import puck_follower
    from bench.motions import gesture_templates
    from tests.mop.helpers import chain, group_beside_alone
    gestures = gesture_templates()
    rng = np.random.default_rng(5)
    x, _, _ = chain(rng, gestures, ["circle", "zigzag", "square", "wave"],
                    lambda: float(rng.uniform(0.7, 1.4)))
    valid = group_beside_alone(lambda: puck_follower(gestures, **kw), [x])
    assert valid[0] >= 120, valid   # followed: measured 143, 143 and 144 valid ticks
