"""The fast BestMatch path reproduces the plain formulation to the last bit.

The searches of behaviors/puppet_master/similarity.py (compiled in search_kernel.py: in-place
distances with a moving offset, the leaving E recomputed, the coherence proposals from their
bases) and fit_target's bearing table are speed-ups only: every choice, every cost and so every
generated pose must equal the reference formulation's (tests/puppet_master/pm_reference.py) bit for
bit.
"""

import math

import numpy as np
import pytest

from behaviors.puppet_master.engine import Behavior, Reactor
from behaviors.puppet_master.table_boundary import clamp_to_table, fit_target
from behaviors.puppet_master.similarity import CoherenceSearch, SituationSearch
from tests.puppet_master import demos
from tests.puppet_master.pm_reference import ReferenceCoherenceSearch, ReferenceSituationSearch

TABLE = (0.0, 0.0, 1.6, 1.0)


def _bits(rows) -> np.ndarray:
    return np.asarray(rows, dtype=float).view(np.uint64)


def _run(behavior: Behavior, main: np.ndarray, reference: bool, obstacles: bool):
    r = Reactor(behavior, TABLE)
    if reference:
        p = behavior.params
        r.situation = ReferenceSituationSearch(behavior.situation_vectors, p.window,
                                               behavior.valid, behavior.situation_aug,
                                               p.half_life)
        r.coherence = ReferenceCoherenceSearch(behavior.coherence_vectors, p.window,
                                               behavior.valid)
    rows, choices = [], set()
    for k, sample in enumerate(main):
        if k % 97 in (5, 6, 7):          # input gaps: several steps from one sample
            continue
        if obstacles:
            r.obstacles = [(0.8 + 0.3 * math.sin(k / 50), 0.5, 0.08)]
        rows.extend(r.advance(*sample))
        choices.add(r.last_choice)
    return rows, choices


@pytest.mark.parametrize("kind,samples,half_life,rate,obstacles", [
    ("follow", 300, 0.0, 40.0, False),
    ("circling", 420, 10.0, 30.0, True),
    ("keep_away", 500, 0.0, 55.0, True),
])
def test_generated_poses_equal_the_reference_searches_bit_for_bit(kind, samples, half_life,
                                                                  rate, obstacles):
    duration = (samples - 1) / 40.0
    if kind == "keep_away":
        demo = demos.keep_away(3, duration, rate_hz=40.0)
    else:
        m = demos.main_path(3, duration, rate_hz=40.0, reversals=kind == "circling")
        demo = demos.circling(m) if kind == "circling" else demos.follow_behind(m)
    b = Behavior.train(demo, half_life=half_life)
    # 80 s of steps: many times the training length, so the distance buffer wraps
    main = demos.main_path(11, 80.0, rate_hz=rate, reversals=True)
    fast, fast_choices = _run(b, main, False, obstacles)
    ref, _ = _run(b, main, True, obstacles)
    assert len(fast) == len(ref) > 2500
    assert np.array_equal(_bits(fast), _bits(ref))
    assert fast_choices == {"situation", "coherence"}     # both searches decided steps


def _training(seed: int, N: int, n: int, d: int):
    """Random training vectors and the allowed window ends n-1 .. N-2."""
    rng = np.random.default_rng(seed)
    valid = np.zeros(N, bool)
    valid[n - 1:N - 1] = True
    return rng, rng.normal(size=(N, d)), valid


@pytest.mark.parametrize("half_life,d", [(0.0, 6), (7.0, 6), (0.0, 8), (7.0, 8), (0.0, 5)])
def test_situation_search_equals_reference_at_every_step(half_life, d):
    N, n = 180, 20
    rng, train, valid = _training(4, N, n, d)
    # 8 columns: the room's two gated by the live vector (features.room_gate's kind: 0 far,
    # rising near); 5: the generic ungated loop
    gate = (6, lambda x: max(0.0, 1.0 - 0.7 * math.hypot(x[2], x[3]))) if d == 8 else None
    fast = SituationSearch(train, n, valid, half_life=half_life, gate=gate)
    ref = ReferenceSituationSearch(train, n, valid, half_life=half_life, gate=gate)
    start = rng.normal(size=(n, d))
    fast.reset(start)
    ref.reset(start)
    for step in range(3 * N + 7):                  # past three moves of the buffer
        x = train[rng.integers(N)] + rng.normal(size=d) * (0.01 if step % 3 else 1.0)
        fast.push(x)
        ref.push(x)
        assert fast.best() == ref.best()
    assert np.array_equal(_bits(fast.distances()), _bits(ref.distances()))


@pytest.mark.parametrize("contiguous", [True, False])
def test_coherence_search_equals_reference_at_every_step(contiguous):
    N, n, d = 400, 16, 8
    rng, train, valid = _training(5, N, n, d)
    if not contiguous:
        valid[100:130] = False
    fast, ref = CoherenceSearch(train, n, valid), ReferenceCoherenceSearch(train, n, valid)
    start = rng.normal(size=(n, d))
    fast.reset(start)
    ref.reset(start)
    source, found = -1, 0
    for _ in range(600):
        j, cost = fast.best()
        assert (j, cost) == ref.best()
        found += j >= 0
        # mostly runs of consecutive sources, sometimes a jump (as the balancer makes them)
        source = int(rng.integers(N - 1)) if source < 0 or rng.random() < 0.1 else source + 1
        source = source if source < N - 1 else -1
        x = train[max(source, 0)] + rng.normal(size=d) * 0.05
        fast.push(x, source)
        ref.push(x, source)
        assert fast.candidates().tolist() == sorted(set(
            s + age for s, age in zip(ref.src, range(n - 1, -1, -1))
            if s >= 0 and s + age < N and valid[s + age]))
    assert found > 500


def _fit_target_reference(mx, my, tx, ty, rx, ry, table, step_deg=5.0):
    x0, y0, x1, y1 = table
    if x0 <= tx <= x1 and y0 <= ty <= y1:
        return tx, ty
    rho = math.hypot(tx - mx, ty - my)
    best = None
    if rho > 1e-9:
        count = int(round(360.0 / step_deg))
        for k in range(count):
            a = math.tau * k / count
            px, py = mx + rho * math.cos(a), my + rho * math.sin(a)
            if x0 <= px <= x1 and y0 <= py <= y1:
                dd = (px - rx) ** 2 + (py - ry) ** 2
                if best is None or dd < best[0]:
                    best = (dd, px, py)
    if best is not None:
        return best[1], best[2]
    return clamp_to_table(tx, ty, table)


def test_fit_target_equals_the_per_call_bearings():
    rng = np.random.default_rng(6)
    moved = 0
    for _ in range(3000):
        mx, my = rng.uniform(-0.1, 1.7), rng.uniform(-0.1, 1.1)
        tx, ty = mx + rng.normal() * 0.5, my + rng.normal() * 0.5
        rx, ry = rng.uniform(0, 1.6), rng.uniform(0, 1.0)
        step = float(rng.choice([5.0, 7.5, 20.0]))
        got = fit_target(mx, my, tx, ty, rx, ry, TABLE, step)
        assert got == _fit_target_reference(mx, my, tx, ty, rx, ry, TABLE, step)
        moved += got != (tx, ty)
    assert moved > 500
