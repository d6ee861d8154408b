"""The compiled loops' tools: the vectorising exponential matches the library's."""

import math

import numba
import numpy as np

from behaviors.mop.compiled import exp_neg, exp_neg32, fma


def _elementwise(fn):
    """A compiled loop applying ``fn`` to every element of ``x`` into ``out``."""
    @numba.njit
    def run(x: np.ndarray, out: np.ndarray) -> None:
        for i in range(x.size):
            out[i] = fn(x[i])
    return run


def test_the_forward_exponential_is_within_two_ulp_of_the_library_over_its_range():
    rng = np.random.default_rng(5)
    x = np.concatenate([-np.linspace(0.0, 200.0, 400_001), -708.0 * rng.random(400_000),
                        [-0.0, -1e-300, -math.log(2.0) / 2, -708.0]])
    got = np.empty_like(x)
    _elementwise(exp_neg)(x, got)
    want = np.array([math.exp(v) for v in x])
    rel = np.abs(got - want) / want
    assert rel.max() <= 4.5e-16, x[np.argmax(rel)]     # 2 ulp
    assert got[-4] == 1.0 and np.all(np.diff(got[:400_001]) <= 0)   # exact at 0, monotone


def test_fma_rounds_once_in_either_width():
    # (1 + e)^2 - (1 + 2e) = e^2 exactly, lost to the product's own rounding when it is rounded
    @numba.njit
    def fused(a, b, c):
        return fma(a, b, c)

    for width, e in ((np.float64, 2.0 ** -30), (np.float32, 2.0 ** -12)):
        a, c = width(1.0 + e), width(-(1.0 + 2.0 * e))
        got = fused(a, a, c)
        assert got == e * e
        assert a * a + c == 0.0   # (rounded twice)


def test_the_single_precision_exponential_is_within_two_ulp_over_its_range():
    # the threshold model's (float32 arguments from -87, its least with a normal result, to 0;
    # the model's own floor is -40): measured 1.2 ulp of the exact value at most
    rng = np.random.default_rng(5)
    x = np.concatenate([-np.linspace(0.0, 87.0, 400_001), -87.0 * rng.random(400_000),
                        [-0.0, -1e-30, -math.log(2.0) / 2, -87.0]]).astype(np.float32)
    got = np.empty_like(x)
    _elementwise(exp_neg32)(x, got)
    assert got.dtype == np.float32
    want = np.exp(x.astype(np.float64))
    ulp = np.spacing(want.astype(np.float32)).astype(np.float64)
    err = np.abs(got - want) / ulp
    assert err.max() <= 2.0, x[np.argmax(err)]
    assert got[-4] == 1.0 and np.all(np.diff(got[:400_001]) <= 0)   # exact at 0, monotone


def test_the_members_unbegun_rule_decides_as_the_followers_own():
    # member_validity.unbegun (every member at once, compiled) against validity.unbegun member
    # by member:
    # random ways and comings, straight back, just either side of the cosine's limit, zeros (at
    # the limit itself the products' last bit decides: numpy's dot may round them otherwise)
    from behaviors.mop import member_validity, validity
    rng = np.random.default_rng(11)
    m = 4000
    came = rng.normal(size=(m, 2))
    way = rng.normal(size=(m, 2))
    way[:500] = -came[:500] * rng.uniform(0.1, 3.0, (500, 1))          # straight back
    for lo, hi, off in ((500, 750, 1e-6), (750, 1000, -1e-6)):         # either side of the limit
        turn = math.acos(-validity.REVERSED) + off
        c, s = math.cos(turn), math.sin(turn)
        way[lo:hi] = np.c_[c * came[lo:hi, 0] - s * came[lo:hi, 1],
                           s * came[lo:hi, 0] + c * came[lo:hi, 1]]
    way[1000:1100] = 0.0
    anchor = rng.normal(size=(m, 2))
    x = anchor + way
    abandoned = rng.random(m) < 0.8
    present = rng.random(m) < 0.9
    leads = np.ones(m, dtype=bool)
    member_validity.unbegun(abandoned, present, x, anchor, came, leads)
    want = np.array([not (a and p and validity.unbegun(True, xi - ai, ci))
                     for a, p, xi, ai, ci in zip(abandoned, present, x, anchor, came)])
    assert np.array_equal(leads, want)
    on = abandoned & present
    assert not leads[:750][on[:750]].any()   # back the way it came: no new action leads
    assert leads[750:1100].all()


def test_still_unbegun_of_every_member_equals_the_followers_rule(monkeypatch):
    # member_validity.still_unbegun (every present member, in place) against
    # validity.still_unbegun member by member, over every combination of abandoned, rested
    # since, resting and present; an absent member keeps its state; with the ban lifted at the
    # rest (validity.RESTED_LIFTS, a member scalar) too
    import itertools
    from behaviors.mop import group_layout, member_validity, validity
    rows = np.array(list(itertools.product((False, True), repeat=4)), dtype=bool)
    abandoned, rested, rests, present = (np.ascontiguousarray(c) for c in rows.T)
    for lifts in (True, False):
        monkeypatch.setattr(validity, "RESTED_LIFTS", lifts)
        mc = np.zeros((len(rows), group_layout.MC_ROWS))
        mc[:, group_layout.MEMBER_SCALARS.index("rested_lifts")] = lifts
        got_a, got_r = abandoned.copy(), rested.copy()
        member_validity.still_unbegun(got_a, got_r, rests, present, mc)
        for i, (a, r, s, p) in enumerate(rows.tolist()):
            want = validity.still_unbegun(a, r, s) if p else (a, r)
            assert (bool(got_a[i]), bool(got_r[i])) == want, (lifts, a, r, s, p)
