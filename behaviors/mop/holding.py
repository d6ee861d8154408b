"""Holds inside an action (raise, hold, return): where a performer resting there is, and at
what size.

A performer holding an action rests where its template holds (a compressed hold, dwelling:
:mod:`behaviors.mop.hmm`). Two rules, for followers whose holds dwell:

- Size: a straight stroke's size and progress are one unknown, so a lift performed at 0.89x
  whose size the follower overestimated during the raise (1.05, lagging a fast rise) was
  followed as a stop short of the top of the rise at 1x, not as the hold at 0.89x; the
  follower stayed at 0.30-0.36 while the performer held (the hold spans 0.38-0.62). When the
  performer rests (:func:`~behaviors.mop.tempo.resting`, over the samples before this one)
  within :data:`HOLD_AHEAD` states before a hold inside the template, and the input lies on
  that hold's place at a smaller size within the size range (every column within
  :data:`SNAP_RADII` still radii), the size becomes that one (:func:`hold_size`): templates
  hold where performers stop. The reach's least size
  (:data:`~behaviors.mop.invariance.REACH_BOUND`) falls to the size so measured: a 0.8x lift
  resting on its hold (``tests/mop/test_quality.py``) was snapped to 0.79 and clamped back to
  0.81 by the reach of one jittered sample at the top (0.097 m against 0.095 resting), so it
  never entered the hold and lagged the return: RMSE 0.088, 0.068 with the bound lowered (as
  without the bound). Lowering the bound by the tolerance everywhere instead did as well there
  but raised the unrelated worst 0.305 -> 0.376 (a mirrored line, no holds). No size is
  taken while the input lies within the tolerance of the anchor (norms), where every size puts
  it on the hold: a 1.4x cartwheel ankle resting at its
  start 2 mm from the anchor, 6 states before a hold, was snapped to 0.64, judged afresh there
  (:data:`~behaviors.mop.invariance.REJUDGE`) and valid 0.62 of the time after 30% instead of
  0.96 (the four 1.4x clips of ``tests/mop/test_quality.py``: mean 0.957 -> 0.989; the lift's
  holds unchanged).
- Progress: once the performer rests in a hold, its states report the progress where the
  hold ends (:func:`hold_maps`) until the followed state leaves the hold (any progress within
  a hold is the same pose, and how long it lasts is unknown): a return begins with an eased
  start that looks held for a few samples, and a follower at the hold's first state was 0.25-0.3
  behind for those samples. Shown only once resting: reported from the hold's first state on,
  the progress ran 0.3 ahead while a performer slowed into the hold. Before the rest, the
  progress shown within a hold is no further than where it begins: a lift performed at 1.15x
  (held-out seed 114, hold 1x) was sized 0.98-1.01 along its raise, so the input easing past
  the 1x top put it in the hold at 0.35-0.55 (sized up to 1.15 by the reach) while the performer
  was at 0.30-0.34, then at the hold's end (0.65) once it rested at 0.37: 0.33 of the
  performance's 0.41 squared error, RMSE 0.067; seed 110's worst (a 1.12x lift, 0.058) the same.

Measured with ``bench/follow_quality.py``'s raise-hold-return section (15 performances, holds
0.3-3x at 0.8-1.2x; progress RMSE max / median, tuned and held-out seeds): before 0.055 /
0.028, 0.102 / 0.028; the progress rule alone 0.052 / 0.032, 0.102 / 0.030; the size rule
alone 0.055 / 0.028, 0.075 / 0.028; both 0.052 / 0.032, 0.048 / 0.030 (kept; longer holds
cost about 0.005 each: the hold's last state lies 0.026 past where the bench's hold ends, in
the return's eased start). The progress shown from the hold's first state on, without the
rest: 0.107 / 0.040, 0.090 / 0.042. No further than the hold's beginning before the rest
(``bench/follow_seeds.py --sections=holds``, seeds 101-118): RMSE max worst .0669 (114) ->
.0522 (114), 110 .0581 -> .0401, 102 .0560 -> .0378, 113 .0546 -> .0372, mean .0469 -> .0406,
backward max unchanged; tuned .0555 -> .0348. Left in 114's .052: the hold's end shown at the
rest's onset over the raise's last two samples (0.37, within 0.3 mm of the hold's pose).
"""

from __future__ import annotations

import numba
import numpy as np

from behaviors.mop import invariance, reversal, tempo
from behaviors.mop.hmm import TemplateBank, inner_holds
from behaviors.mop.reversal import fitted_size
from behaviors.mop.tempo import RESTING_RADII
from behaviors.kernel_cache import compiled

_CALLS_INTO = (invariance, reversal, tempo)   # the files whose constants or kernels they take in

#: States before a hold inside a template from which a resting performer may be holding it.
#: Along a straight stroke to a hold the size stays near 1 (size and progress are one there),
#: so a performer resting on the hold at 0.7x is followed short of it: a 0.7x getup facedown
#: wrist at state 8.6 of a stroke whose hold begins at state 15, where it stalled at size
#: 0.95 while other actions led (``tests/mop/test_holding.py``). Held-out sized 0.7-1.4x valid
#: after 30% (``bench/follow_seeds.py --sections=sized``), seeds 101-106: 6 states .9022 .8749
#: .9057 .8871 .8860 .8744 (mean .8884); 7, 8, 9 or 12 .9022 .8849 .9057 .8968 .8865 .8840
#: (.8933); seeds 107-112: 6 .8653 .8661 .8691 .8877 .8812 .8781 (.8746), 9 .8741 .8761 .8753
#: .8934 .8912 .8797 (.8816). Every other figure of ``follow_seeds`` (101-112) and of
#: ``bench/follow_quality.py`` as before but the held-out 0.6/1.5x edges, .6751 -> .7001 (the
#: tuned templates hold nowhere inside; raise-hold-return unchanged).
HOLD_AHEAD = 9
#: How far (still radii, every column) the input may lie from a hold's place at the size that
#: puts it there.
SNAP_RADII = 3.0


def hold_maps(bank: TemplateBank, ahead: int = HOLD_AHEAD
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """Per state of ``bank``: the progress where its hold ends when it is a state of a hold
    inside a template (:func:`~behaviors.mop.hmm.inner_holds`; NaN elsewhere), the first
    state of such a hold within ``ahead`` states after it (-1 where none) and the progress where
    its hold begins (NaN elsewhere); None without holds."""
    holds = inner_holds(bank)
    if not holds:
        return None
    end = np.full(len(bank.means), np.nan)
    begin = np.full(len(bank.means), np.nan)
    first = np.full(len(bank.means), -1, dtype=np.intp)
    for a, b in holds:
        end[a:b] = bank.source[b - 1]
        begin[a:b] = bank.source[a]
        start = int(bank.starts[np.searchsorted(bank.starts, a, side="right") - 1])
        first[max(a - ahead, start):a] = a
    return end, first, begin


@compiled(numba.float64(numba.float64[::1], numba.float64[::1], numba.float64, numba.float64,
                        numba.float64[::1]), *_CALLS_INTO)
def hold_size(q: np.ndarray, r: np.ndarray, size: float, lo: float, tol: np.ndarray) -> float:
    """The size (least squares) at which the input ``r`` (d,: from the anchor, in units) lies
    on a hold's place ``q`` (d,: from the template's first state, in units), when it is at
    least ``lo``, smaller than ``size`` and puts ``r`` within ``tol`` (d,, units) of it in every
    column; 0 otherwise."""
    s = fitted_size(q, r)
    if s == 0.0 or not (lo <= s < size):
        return 0.0
    rr = 0.0
    tt = 0.0
    for c in range(q.size):
        if abs(r[c] - s * q[c]) > tol[c]:
            return 0.0
        rr += r[c] * r[c]
        tt += tol[c] * tol[c]
    # the input within the tolerance's reach of the anchor lies on the hold at any size
    return s if rr > tt else 0.0


#: A size taken at a hold ahead seats the followed state on the hold (the main window's whole
#: probability there, :meth:`~behaviors.mop.forward.WindowedForward.seat`; follower and group),
#: and an action so seated is not dropped by validity.stalls while its performer rests there.
#: Left where it was, a 0.7x getup wrist sized 0.97 -> 0.72 while followed at 0.10 (its
#: performer at 0.24) crept on a state a sample and its return drove it back down the first
#: stroke (0.16 -> 0.07; held-out seed 105, valid after 30% .06). Sized 0.7-1.4x valid after
#: 30% (bench/follow_seeds.py --sections=sized,unrelated,sequences) 105 .9050 -> .9133 (that
#: getup .06 -> .93), 112 .9038 -> .9123 (its 0.7x getup .16 -> .92), 107 / 109 / 110 / 111 /
#: 101 up a little, none lower, means .9093 -> .9107 / .9074 -> .9095, unrelated and sequences
#: the same; bench/follow_quality.py held-out hold progress RMSE max .046 -> .037. Price, taken:
#: progress RMSE median 101 .0212 -> .0214, hold backward max .00134 -> .00138, aspect 1.2 valid
#: .447 -> .443. Seated without sparing it from validity.stalls: 102 / 108 / 111 lower (their
#: 0.7x getup wrists 1.0 -> .95-.98, two samples near 30% not valid; 108 .9003 -> .8999).
def rested_sizes(ahead: np.ndarray, rel: np.ndarray, r: np.ndarray, size: np.ndarray, lo: float,
                 tol: np.ndarray, num: np.ndarray, den: np.ndarray, prior: np.ndarray,
                 least: np.ndarray, starts: np.ndarray, seat: np.ndarray) -> None:
    """A performer resting within a few states before a hold takes, per template, the size that
    puts the input on it when smaller (:func:`hold_size`), in place on the size estimate's sums
    ``num`` (``den``, ``prior``:
    :meth:`~behaviors.mop.invariance.PerformanceFrame._estimate_size`'s). ``ahead`` (K,): each
    template's hold ahead (-1: none); ``rel``: the states from their first (units); ``r``: the input
    from the anchor (units); ``tol`` (d,): :data:`SNAP_RADII` still radii in units; ``least`` (K,):
    the reach's least size, lowered to a size taken here; ``seat`` (K,): the hold's state from
    its template's first (``starts``) where a size was taken
    (:meth:`~behaviors.mop.forward.WindowedForward.seat`)."""
    for k in np.flatnonzero(ahead >= 0):
        s = hold_size(rel[ahead[k]], r, float(size[k]), lo, tol)
        if s > 0.0:   # the estimate (num + prior) / (den + prior) is then s
            num[k] = s * (den[k] + prior[k]) - prior[k]
            least[k] = min(least[k], s)   # the hold measured it: the reach's jittered max yields
            seat[k] = ahead[k] - starts[k]


def shown_progress(progress: np.ndarray, end: np.ndarray, at_end: np.ndarray,
                   rest: bool, begin: np.ndarray) -> np.ndarray:
    """Each template's progress (K,) as shown: where its hold ends (``end``, NaN outside a hold)
    once the performer rested in it (``rest`` now; ``at_end`` (K,) remembers it, in place, until
    the followed state leaves the hold), no further than where it begins (``begin``) before."""
    inside = ~np.isnan(end)
    if rest:
        at_end |= inside
    at_end &= inside
    return np.where(at_end, np.fmax(progress, end),
                    np.where(inside, np.fmin(progress, begin), progress))


@compiled(numba.boolean(numba.float64[:, :, ::1], numba.intp[::1], numba.intp,
                        numba.float64[:, ::1],
                        numba.float64[::1], numba.intp), *_CALLS_INTO)
def resting_with(buf: np.ndarray, count: np.ndarray, i: int, x: np.ndarray, radius: np.ndarray,
                 keep: int) -> bool:
    """:func:`behaviors.mop.tempo.resting` of a group member ``i``'s buffered samples
    (``buf`` (M, S, D), its last ``count[i]`` rows) before they take this sample ``x[i]``: over
    their last ``keep - 1`` (the member's ``still_samples``; S is the group's largest) and this
    one, as the follower reads its recent samples and this one."""
    s = buf.shape[1]
    c0 = min(count[i], keep - 1)
    total = c0 + 1
    n = total // 2
    if n < 2:
        return False
    for c in range(buf.shape[2]):
        early = 0.0
        late = 0.0
        for r in range(n):
            early += buf[i, s - c0 + r, c] if r < c0 else x[i, c]
            j = total - n + r
            late += buf[i, s - c0 + j, c] if j < c0 else x[i, c]
        if not abs(late / n - early / n) <= RESTING_RADII * radius[c]:
            return False
    return True


def holding_columns(follower) -> np.ndarray:
    """A follower's hold maps as two columns per state (where its hold ends, NaN elsewhere; the
    first state of a hold a few states ahead, -1 where none) for a group's state table."""
    n = len(follower.bank.means)
    if follower._holds is None:
        return np.column_stack([np.full(n, np.nan), np.full(n, -1.0), np.full(n, np.nan)])
    end, first, begin = follower._holds
    return np.column_stack([end, first.astype(float), begin])
