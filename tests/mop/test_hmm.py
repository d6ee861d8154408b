"""Template HMMs and the windowed forward algorithm: equations 2-7 exactly, transitions, scales."""

import math

from bench import synthetic_actions as g
import numpy as np
import pytest

from behaviors.mop.features import fit_scale
from behaviors.mop.forward import WindowedForward, forward_reference
from behaviors.mop.hmm import TemplateError, Transitions, build_bank


@pytest.mark.parametrize("transitions, fastest", [
    (Transitions(restart=0.0), 2.0),
    (Transitions(forward=(0.5, 0.5), backward=0.0, restart=0.0), 1.0),  # MOP's own model
    (Transitions(forward=(0.2, 0.3, 0.3, 0.1, 0.1), backward=0.3, restart=0.0), 2.0)])
@pytest.mark.parametrize("n", [200, 31, 12])
def test_every_template_at_once_equals_the_plain_equations(transitions, fastest, n):
    rng = np.random.default_rng(n)
    target = g.template(rng, n=n, d=4)
    bank = build_bank({"other": g.template(rng, n=90, d=4), "target": target,
                       "long": g.template(rng, n=400, d=4)})
    perf = g.perform(rng, target, g.warped_phase(rng, n, 0.5, fastest), 0.1)
    z = (perf - bank.center[1]) / bank.scale[1]    # in the target's own units
    mean, var, ll, _ = forward_reference(bank.template(1), z, 0.2, 15, transitions)
    fw = WindowedForward(bank, sigma=0.2, half_window=15, transitions=transitions, floor=0.0)
    got = np.array([(fw.step(x)[1], fw.mean[1], fw.var[1]) for x in z])
    assert np.abs(got[:, 0] - ll).max() <= 1e-8
    assert np.abs(got[:, 1] - mean).max() <= 1e-8
    assert np.abs(got[:, 2] - var).max() <= 1e-7
    assert np.all(fw.lo <= bank.lengths - np.minimum(31, bank.lengths))


@pytest.mark.parametrize("transitions, floor", [
    (Transitions(), 1e-8),                                                 # the follower's defaults
    (Transitions(forward=(0.5, 0.5), backward=0.0, restart=1e-3), 1e-8),
    (Transitions(restart=1e-3), 0.0),                                      # the log-domain step
    (Transitions(dwell=0.8), 1e-8),                                        # holds that dwell
    (Transitions(restart=1e-3, dwell=0.5), 0.0)])
def test_the_vectorised_step_equals_the_plain_algorithm_with_restart_floor_and_reentry(
        transitions, floor):
    """Every template of a bank stepped at once, each on its own input (as a group steps them),
    against the algorithm written out state by state for one template at a time: performances,
    input that leaves the template, and new performances from the start (re-entry), also while
    the window still holds the first states."""
    rng = np.random.default_rng(5)
    lengths = [12, 31, 45, 90, 160]           # shorter than, as long as and longer than the window
    tpls = {f"t{n}": g.template(rng, n=n, d=3) for n in lengths}
    if transitions.dwell > 0:   # a hold in the middle of each template long enough to have one
        for tpl in tpls.values():
            if len(tpl) >= 30:
                tpl[len(tpl) // 2:len(tpl) // 2 + 9] = tpl[len(tpl) // 2]
    bank = build_bank(tpls)
    streams = []
    for k, tpl in enumerate(tpls.values()):
        n = len(tpl)
        first = g.perform(rng, tpl, g.warped_phase(rng, n, 0.5, 2.0), 0.1)
        away = g.perform(rng, tpl, np.full(25, n - 1.0), 0.1) + rng.normal(0.0, 2.0, (25, 3))
        again = g.perform(rng, tpl, g.warped_phase(rng, n, 0.6, 1.5), 0.1)
        # a few states in, then starting over while the window still holds the first states
        short = g.perform(rng, tpl, np.arange(0.0, min(10.0, n - 1.0)), 0.1)
        x = np.concatenate([short, first, away, again, first[: n // 2]])[:330]
        x = np.concatenate([x, g.perform(rng, tpl, np.zeros(330 - len(x)), 0.1)])
        streams.append((x - bank.center[k]) / bank.scale[k])
    z = np.stack(streams, axis=1)                                          # (T, K, d)
    fw = WindowedForward(bank, sigma=0.2, half_window=15, transitions=transitions, floor=floor)
    got = []
    for zt in z:
        ll = fw.step(zt)
        got.append((ll, fw.mean.copy(), fw.var.copy(), fw.entries.copy()))
    ll, mean, var, entries = (np.array(c) for c in zip(*got))
    reentered = 0
    for k in range(len(lengths)):
        stay = fw._stay[bank.starts[k]:bank.starts[k] + bank.lengths[k]]
        assert stay.max() == (transitions.dwell if lengths[k] >= 30 else 0.0)
        r_mean, r_var, r_ll, r_entries = forward_reference(bank.template(k), z[:, k], 0.2,
                                                           15, transitions,
                                                           floor, stay)
        assert np.array_equal(entries[:, k], r_entries)
        assert np.abs(ll[:, k] - r_ll).max() <= 1e-9 * max(1.0, np.abs(r_ll).max())
        assert np.abs(mean[:, k] - r_mean).max() <= 1e-9
        assert np.abs(var[:, k] - r_var).max() <= 1e-7
        reentered += int(r_entries[-1] > 0)
    assert reentered >= 2          # the case is exercised: new performances were picked up


def emission_loglik(z: np.ndarray, states: np.ndarray, sigma: float) -> np.ndarray:
    """Log of equation 1 for a standardised sample ``z`` (d,) against states (n, d): the Gaussian
    log-density with standard deviation ``sigma`` (in units of the standardised features)."""
    d = states.shape[1]
    sq = np.sum((states - z) ** 2, axis=1)
    return -0.5 * sq / sigma ** 2 - d * np.log(sigma) - 0.5 * d * np.log(2.0 * np.pi)


def mean_speed(t: Transitions) -> float:
    """The prior's expected advance in states per step."""
    b, w = t.weights()
    return float(np.dot(np.arange(w.size), w) - b)


def test_the_step_loglik_is_the_log_of_equation_one_at_a_certain_state():
    rng = np.random.default_rng(1)
    tpl = g.template(rng, n=50, d=3)
    bank = build_bank({"a": tpl})
    fw = WindowedForward(bank, sigma=0.3, transitions=Transitions(restart=0.0), floor=0.0)
    z = bank.means[0] + 0.1
    # the first step has all its prior on the first state: L_1 = b_1(O_1)
    assert fw.step(z)[0] == pytest.approx(emission_loglik(z, bank.means[:1], 0.3)[0], abs=1e-9)


def test_window_follows_the_mean_and_stays_inside_the_template():
    rng = np.random.default_rng(2)
    tpl = g.template(rng, n=200, d=3)
    bank = build_bank({"a": tpl})
    fw = WindowedForward(bank, half_window=10)
    for i in range(200):
        fw.step(bank.means[i])
        lo = int(fw.lo[0])
        assert 0 <= lo <= 200 - 21
        centre = min(max(int(math.floor(fw.mean[0] + 0.5)) - 10, 0), 179)
        assert lo == centre
    assert fw.progress[0] >= 0.97


def test_probability_stays_normalised_and_finite_on_wild_input():
    rng = np.random.default_rng(3)
    bank = build_bank({f"t{i}": g.template(rng, n=60 + 40 * i, d=5) for i in range(4)})
    fw = WindowedForward(bank)
    for x in rng.normal(0.0, 50.0, (500, 5)):
        ll = fw.step(x)
        assert np.all(np.isfinite(ll))
        sums = fw.alpha[:4].sum(axis=1) + fw.alpha[4:].sum(axis=1)
        # 1 after each step, less only by what left the window when it moved
        # (renormalised next step)
        assert np.all((sums > 0.0) & (sums <= 1.0 + 1e-9)) and np.all(np.isfinite(fw.alpha))
        assert np.all((fw.progress >= 0) & (fw.progress <= 1))


def test_transitions_are_normalised_and_validated():
    b, w = Transitions(forward=(1.0, 1.0), backward=2.0).weights()
    assert b == pytest.approx(0.5) and np.allclose(w, [0.25, 0.25])
    assert mean_speed(Transitions(forward=(0.5, 0.5), backward=0.0)) == pytest.approx(0.5)
    assert 0.9 <= mean_speed(Transitions()) <= 1.1  # about the recording's pace by default
    for bad in (dict(forward=(-1.0, 1.0)), dict(forward=()), dict(backward=-0.1),
                dict(forward=(0.0,), backward=0.0), dict(restart=1.0)):
        with pytest.raises(TemplateError):
            Transitions(**bad)


def test_scale_is_pooled_over_all_templates_with_a_floor_for_still_columns():
    a = np.column_stack([np.linspace(0, 1, 50), np.zeros(50), np.full(50, 3.0)])
    b = np.column_stack([np.linspace(0, 3, 50), np.zeros(50), np.full(50, 3.0)])
    center, scale = fit_scale([a, b], relative_floor=0.05)
    pooled = np.concatenate([a, b])
    assert center == pytest.approx(pooled.mean(axis=0))
    assert scale[0] == pytest.approx(pooled[:, 0].std())
    overall = math.sqrt(np.mean(pooled.std(axis=0) ** 2))
    assert scale[1] == pytest.approx(0.05 * overall) and scale[2] == pytest.approx(0.05 * overall)
    _, floored = fit_scale([a, b], 0.05, min_scale=[0.0, 0.5, 0.0])
    assert floored[1] == 0.5 and floored[0] == scale[0]
    _, flat = fit_scale([np.zeros((5, 2))])
    assert np.all(flat == 1.0)


def test_bank_stacks_standardised_templates():
    rng = np.random.default_rng(4)
    ta, tb = rng.normal(size=(30, 2)), rng.normal(size=(45, 2))
    bank = build_bank({"a": ta, "b": tb})
    assert bank.names == ("a", "b") and list(bank.lengths) == [30, 45] and bank.dim == 2
    assert np.allclose(bank.template(1) * bank.scale[1] + bank.center[1], tb)
    with pytest.raises(TemplateError, match="min_scale"):
        build_bank({"a": ta}, min_scale=[1.0])
    one_column = build_bank({"a": np.arange(5.0)})
    assert one_column.dim == 1


def test_a_templates_tolerance_is_its_own_whatever_is_loaded_beside_it(gestures):
    # the figures: in the pooled feature scale the circle's tolerance was 2.6 cm in x
    # and 1.4 cm in y, and 1.6, 2.6, 4.7 cm as templates were added. Each template's scale
    # (the metres one sigma unit stands for, per column) is now its own spread: measured
    # 4.5 / 5.5 cm for the circle, alone, among the six, beside a line ten times as long
    from bench.follow_quality import paper_follower, puck_follower
    big = {**gestures, "big_line": 10.0 * gestures["line"]}
    alone = puck_follower({"circle": gestures["circle"]}).bank.scale[0]
    assert np.all((alone > 0.04) & (alone < 0.06)), alone
    for loaded in (gestures, big):
        f = puck_follower(loaded)
        assert np.allclose(f.bank.scale[f.names.index("circle")], alone, rtol=1e-12, atol=0)
    # the follow command's defaults (units unknown): the circle's own among the six too
    f = paper_follower(gestures)
    assert np.allclose(f.bank.scale[f.names.index("circle")], alone, rtol=1e-12, atol=0)
    # the pooled units alone (the scale before each template's own spread) tie it to the set
    pooled = [fit_scale(list(s.values()), 0.05)[1] for s in ({"c": gestures["circle"]}, big)]
    assert not np.allclose(*pooled)


def test_the_follow_commands_tolerance_and_refusal_stay_the_templates_own_beside_a_larger_one(
        gestures):
    # the follow command (units unknown) floored every template's scale at a share of the set's
    # pooled spread: beside a circle ten times as large, the circle's became 6.4 / 8.8 cm
    # instead of its own 4.5 / 5.5, and a 0.7x circle was refused on 39 other ticks of 73. The
    # floor is now the still radius's only (tabletop.commands.follow.MIN_SCALE_SHARE)
    from bench.follow_quality import paper_follower
    from bench.motions import performance
    from behaviors.mop.follower import ActionFollower
    x, _ = performance(np.random.default_rng(3), gestures["circle"], 0.7)
    scales, refused = [], []
    for loaded in ({"circle": gestures["circle"]},
                   {"circle": gestures["circle"], "big": 10.0 * gestures["circle"]}):
        f = paper_follower(loaded)
        scales.append(f.bank.scale[0])
        flags = []
        for s in x:
            f.step(s)
            flags.append(bool(f._refused[0]))
        refused.append(flags)
    assert np.allclose(scales[0], scales[1], rtol=1e-12, atol=0), scales
    assert 20 <= sum(refused[0]) <= len(x) - 20 and refused[0] == refused[1]
    with pytest.raises(TemplateError, match="still_scale must be 2 non-negative"):
        ActionFollower(gestures, still_scale=[0.01])



def test_the_window_transitions_add_the_move_back_in_the_order_of_two_passes():
    # window_kernel._transit's one pass: from the fourth state on, each product fused in the
    # order the compiler contracted the sum of the moves forward and then the move back in a
    # second pass (fma(f0, x[t], f1 x[t - 1]), f2, f3, then back): the same numbers to the bit
    # as the two passes (checked against them inside step_windows on DESIGN's states and on
    # windows of 2-45 states); here against that order in exact rational arithmetic
    from fractions import Fraction

    import numba
    from behaviors.mop.window_kernel import _transit

    def fma(a: float, b: float, c: float) -> float:
        return float(Fraction(a) * Fraction(b) + Fraction(c))   # (rounded once, to nearest)

    @numba.njit
    def one_pass(x, y, n, back, f):
        _transit(x, y, n, back, f, False, False)

    rng = np.random.default_rng(11)
    fused = 0
    for n in (4, 5, 17, 31):
        for _ in range(20):
            x = rng.random(32) ** 3
            f = np.array([0.3, 0.35, 0.25, 0.1]) * rng.uniform(0.5, 1.5, 4)
            back = float(rng.uniform(0.0, 0.3))
            got = np.zeros(32)
            one_pass(x, got, n, back, f)
            for t in range(3, n):
                want = fma(f[3], x[t - 3], fma(f[2], x[t - 2], fma(f[0], x[t], f[1] * x[t - 1])))
                if t + 1 < n:
                    want = fma(back, x[t + 1], want)
                assert got[t] == want, (n, t)
                fused += want != ((f[0] * x[t] + f[1] * x[t - 1] + f[2] * x[t - 2]
                                   + f[3] * x[t - 3]) + (back * x[t + 1] if t + 1 < n else 0.0))
    assert fused > 100   # (the order matters: rounded op by op, most rows differ)


def test_a_seat_puts_the_whole_main_window_on_a_state_ahead_only():
    # WindowedForward.seat compiled (window_kernel.seat_windows) as the Python it replaced:
    # only a template whose state lies ahead of its mean is seated (the window on that state,
    # its start within the template, moments of a point), every mark then cleared to -1; the
    # marks as a strided column (the group's record) as well as a row of their own
    rng = np.random.default_rng(5)
    bank = build_bank({f"t{i}": g.template(rng, 40 + 10 * i, 2) for i in range(4)})
    fw = WindowedForward(bank, half_window=5)
    for z in rng.normal(size=(12, 2)):
        fw.step(z)
    record = np.zeros((4, 3))
    record[:, 1] = [-1.0, 30.0, 0.0, 42.0]   # t0 none, t1 and t3 ahead, t2 behind its mean
    states, seated = record[:, 1], np.zeros(4, dtype=bool)
    a, s, lo, mean, mom = fw._a.copy(), fw._s.copy(), fw.lo.copy(), fw.mean.copy(), fw._mom.copy()
    assert mean[2] > 0.0 and mean[1] < 30.0 and mean[3] < 42.0
    fw.seat(states, seated)
    assert seated.tolist() == [False, True, False, True] and (record[:, 1] == -1.0).all()
    for j, h in ((1, 30), (3, 42)):
        low = min(max(h - 5, 0), int(bank.lengths[j]) - 11)
        want = np.zeros(a.shape[1])
        want[h - low] = s[j]
        assert fw.lo[j] == low and (fw._a[j] == want).all() and fw.mean[j] == h
        assert fw._mom[:, j].tolist() == [1.0, h, h * h]
    for j in (0, 2):   # the others as they were
        assert (fw._a[j] == a[j]).all() and fw.lo[j] == lo[j] and fw.mean[j] == mean[j]
        assert (fw._mom[:, j] == mom[:, j]).all()
    a, mean = fw._a.copy(), fw.mean.copy()
    none = np.full(4, -1.0)
    fw.seat(none, seated)   # nothing to seat: nothing touched
    assert (fw._a == a).all() and (fw.mean == mean).all() and (none == -1.0).all()


def test_a_step_clears_the_first_step_marks():
    rng = np.random.default_rng(6)
    bank = build_bank({f"t{i}": g.template(rng, 40, 2) for i in range(3)})
    fw = WindowedForward(bank)
    assert fw._fresh.all()
    fw.step(rng.normal(size=2))
    assert not fw._fresh.any()
    fw.reset_templates(np.array([1]), fresh=True)
    assert fw._fresh.tolist() == [False, True, False]
    fw.step(rng.normal(size=2))
    assert not fw._fresh.any()
