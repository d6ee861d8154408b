"""Commitment's fit, read at the best timing offset. A template committed to by shape
(:meth:`~behaviors.mop.shape_lead.ShapeLead._committed`) drives however improbable, once its shape
fits within :data:`~behaviors.mop.shape_lead.COMMIT_FIT` still radii (RMS per column and sample
since the gesture began). That sum compares each sample with the template's *followed state*; on a
fast start the follower's state lags the performer along the path, and the sum counts the lag as a
misfit: the zigzag back to back, covered, leading every rival by 16-100 nats and met within
0.02-0.08 sigma of its path, summed 2.0-2.7 still radii, and waited 1-2 samples for the evidence
(:mod:`behaviors.mop.coverage`, the tick-by-tick reading). So the fit is also summed at each
constant offset of the followed state within :data:`COMMIT_LAGS` states either way
(:func:`add_lagged`), and commitment reads the least: a constant lag is timing, not shape; a path
met only by a timing that changes sample by sample is not taken as fitting (below).
``bench/follow_quality.py`` (tuned / held-out, against the same figures before): six gestures back
to back within 20% 0.125 -> 0.156 / 0.125 (or reach the same), the open three 0.235 -> 0.294 /
0.308, the zigzag 0.67 -> 0.83 / 0.80 (median 0.183 -> 0.179); every other figure unchanged (sized
0.912 / 0.902, unrelated worst 0.058 / 0.099, after a gesture 0.072 / 0.083, holds, pauses, wrong
runs 1 / 1 and 2 / 11, the draws for options). On ``bench.motions.back_to_back``'s draws 0-59 with
the zigzag among their four, every gesture that changed is recognised sooner (the zigzag 0.207 /
0.231 -> 0.183 / 0.204, the circle 0.313 / 0.304 -> 0.287 / 0.278, the wave 0.290 / 0.260 -> 0.263
/ 0.234), and no wrong run grew. Its cost: :func:`add_lagged` for 800 templates (DESIGN's 8 x 100),
rows drawn at random, 45 us a tick with 2 features, 105 us with 6 (medians, a machine loaded 12-15
on 2 cores); ``bench/mop.py --design`` on a quiet machine, alternated, the group tick's CPU median
/ p99 0.815-0.822 / 1.28-1.36 ms before (with the projections of :mod:`behaviors.mop.path_kernel`
not yet shared), 0.915-0.926 / 1.46-1.48 ms after: within DESIGN's 1 / 2 ms, with a tenth less
margin.

The fit judged without the timing, measured and not kept (``bench/follow_quality.py``, tuned /
held-out; what it frees, the zigzag, in :mod:`~behaviors.mop.coverage`): committed while its path
misfit is within ``coverage.EARLY_FIT`` (0.25 sigma) instead of ``COMMIT_FIT``, or while its shape
sum is within 0.4 sigma of its own spread at its size: six gestures within 20% 0.125 -> 0.156 /
0.125 (the zigzag 0.67 -> 0.83), held-out twenty's longest wrong run 11 -> 9, sized 0.912 -> 0.919
/ 0.902 -> 0.906 (own spread: 0.920 / 0.902), but unrelated worst 0.058 -> 0.070 (a wander among
six; the told worst unchanged, 0.057), a spiral after a gesture 0.072 -> 0.083 (0.4 sigma: held-out
0.083 -> 0.088) and a pause's wrong valid share 0 -> 0.011; at 0.3 and 0.35 sigma no gesture
sooner.

What holds twenty templates back to back past the observer's reach (``bench/follow_sequences.
full_reach``: every other template and unrelated stroke, 2 mm) + 0.05: 23 of 32 tuned gestures,
66 of 96 held-out (seeds 101-103). Per tick from the reach to recognition (progress summed over
both): the true template not ``best`` on the evidence with commitment closed 4.9 (its fit alone
1.2, 75 ticks; its fit with the lead or coverage 2.7), the confirmation's sample 1.9 (one a
gesture), best but not leading in shape 1.25 (a probable rival within ``LEAD``: the line on the
spin ankle), coverage 1.2, a shared start 0.4, a slow take 0.3. The tuned kick ankle (4 draws,
0.8-1.2x): the walk ankle best by 2-5 nats and ahead in shape by 200-400 still radii squared at
0.21-0.29 of it, its followed state 1-3 states behind a fast start, then 4-7 still radii a sample
off on its fast stretch (several mm a state). Measured and not kept (``bench/follow_quality.py
--sections=sequences``, tuned / held-out, before: by the reach + 0.05 0.281 / 0.406, within 20% or
by it 0.50 / 0.625, mean progress past the reach 0.101 / 0.087): this fit forgotten over 10 samples
(the fast start's lag forgotten): shares unchanged (0.100 / 0.087), tuned unrelated worst 0.058 ->
0.063; no fit limit at all (the ceiling of any fit): 0.281 / 0.375, 0.50 / 0.50 (0.096 / 0.076:
sooner on the mean, wrong commitments); the lead and commitment read at each template's best
constant offset too: held-out 0.438, 0.656 (one gesture; seeds 101-106 only 101), but held-out
sized valid after 30% lower on 102, 104-106 (mean 0.9058 -> 0.9055) and a stroke after a gesture
valid 0.0448 -> 0.0466 of its ticks (tuned mean).

The gates hand the lag on (traced again with the size rules since, twenty templates, gestures
recognised later than the reach + 0.05: 23 of 32 tuned, 66 of 96 held-out 101-103; the check that
held each longest: held-out coverage 20, this fit 16, the lead 14, the confirmation's sample 10;
progress summed past the reach, held-out: the lead 2.1, the fit 1.8, coverage 1.6, the
confirmation 1.3). Measured and not kept (``--sections=sequences``, then ``unrelated,after``; the
same figures before): a lead held instead of the fit, the fit waived for a template that was the
least in shape and led every one not refused by ``LEAD`` on 3 samples in a row, its evidence
within ``LEAD`` nats of the likeliest: held-out twenty by the reach + 0.05 0.406 -> 0.469, past
the reach 0.087 -> 0.079, every within-20% share unchanged (six 0.156 / 0.125, twenty 0.406 /
0.375; or by the reach 0.50 / 0.469, 0.50 / 0.625), but unrelated worst 0.058 -> 0.068 (a wander
among twenty 0 -> 0.068), told worst 0.053 -> 0.068, after a gesture mean 0.045 -> 0.049: the true
takes it frees fit within 1.8-5.9 still radii, 0.2-6.1 nats behind on the evidence, the unrelated
motions' 1.8-10.6 radii, 0.1-4 nats behind. With the fit kept within 2.5 radii: 0.438, 0.085,
unrelated worst 0.060 (a wander among six), a template's own stroke told 0.098 -> 0.100. With no
bound on the evidence (2, 3 or 5 samples): held-out twenty within 20% or by the reach 0.625 ->
0.531 / 0.531 / 0.563 (a getup wrist taking a punch ankle 6-10 nats behind, the line a square).
Traced again, tick by tick from the reach to recognition (twenty, tuned / held-out 101-103 and 107:
23 of 32 / 76 of 128 later than the reach + 0.05; progress past the reach summed 2.6 / 9.2):
several gates at once 1.5 / 5.8, nearly always probability and ``best`` together (where they are
the first, commitment closed by the own fit over ``COMMIT_FIT`` 0.44 / 1.52, half of it within 2.3
still radii, by a rival less in shape 0.35 / 0.44); the likeliest rival there: tuned the walk ankle
on the kick and roll ankles 0.46, the getup wrist on the spinkick and roll ankles 0.34; held-out
the jump ankle on the backflip ankle 1.53, the spin wrist on the circle 0.97, the cartwheel ankle
on the zigzag and the wave 0.75, the punch ankle on the getup wrist 0.27. One gate alone: the
confirmation's sample 0.56 / 1.25, a shared start 0.28 / 0.10, coverage 0.14 / 0.57 (the followed
arc 0.8-0.98 of its need), the take's fit 0.02 / 0.90 (0.6 of it a line on 107 never taken: its
last samples off its path, its shape 6 still radii off), the lead 0.10 / 0.36. The circle among six
(29 circles, 25 past 0.25, recognised at 0.25-0.30): coverage 0.49, the confirmation 0.47, the lead
over the line 0.24, this fit 0.18, the line's shared start 0.18: a sample each, handed on.
``COMMIT_FIT`` 2.0 (``bench/follow_quality.py``, tuned / held-out): by the reach + 0.05 unchanged
(0.281 / 0.531), within 20% or by it 0.50 / 0.688 -> 0.50 / 0.656, unrelated worst 0.058 -> 0.065
(a wander among six), held-out own stroke told 0.008 -> 0.033: not kept.
"""

from __future__ import annotations

import numba
import numpy as np

from behaviors.kernel_cache import compiled

#: Commitment's fit is read at the best constant timing offset of the followed state, within
#: this many states either way (0: at the followed state only, as the shape sums).
COMMIT_LAGS = 3


_F1, _F2 = numba.float64[::1], numba.float64[:, ::1]
_FA2 = numba.float64[:, :]   # a follower's sums, or a group's (columns of its per-template state)


@compiled(numba.void(_FA2, numba.intp, _F1, numba.float64, numba.intp, numba.intp, _F2,
                     numba.intp, numba.intp, numba.intp, numba.float64, _F1, _F1))
def add_lagged(sums: np.ndarray, k: int, dx: np.ndarray, g: float, first: int, last: int,
               states: np.ndarray, off: int, col: int, d: int, size: float, units: np.ndarray,
               radius: np.ndarray) -> None:
    """Add to template ``k``'s column of ``sums`` (one row per timing offset, from as many states
    behind the followed one as ahead: :data:`COMMIT_LAGS` either way) the squared distance in still
    radii ``radius`` between the input ``dx`` (d: from the anchor, raw units) and the template's
    path at its followed state ``g`` plus that offset, kept within its states ``first`` .. ``last``
    (``states``' rows from ``off``, columns ``col`` on: each state from the template's first, in
    ``units`` at ``size``). The follower (:func:`add_lagged_all`) and the group's kernel call it
    alike. A puck's two features written out (the same operations, the divisions side by side)
    gave the same numbers but DESIGN's update_templates 622 -> 617 us median of five
    alternating runs (three faster, two slower): not taken."""
    for j in range(sums.shape[0]):
        at = min(max(g + (j - (sums.shape[0] - 1) // 2), float(first)), float(last))
        jl = min(int(at), last - 1)
        acc = 0.0
        for c in range(d):
            a = states[jl + off, col + c]
            q = a + (at - jl) * (states[jl + 1 + off, col + c] - a)
            e = (dx[c] - size * q * units[c]) / radius[c]
            acc += e * e
        sums[j, k] += acc


@compiled(numba.void(_F2, _F1, _F1, numba.intp[::1], numba.intp[::1], _F2, _F1, _F1, _F1),
          __file__)
def add_lagged_all(sums: np.ndarray, dx: np.ndarray, g: np.ndarray, starts: np.ndarray,
                   lengths: np.ndarray, rel: np.ndarray, size: np.ndarray, units: np.ndarray,
                   radius: np.ndarray) -> None:
    """:func:`add_lagged` for every template of a follower's bank (``g``: followed states, bank
    index; ``rel`` (S, d): each state from its template's first)."""
    for k in range(g.size):
        add_lagged(sums, k, dx, g[k], starts[k], starts[k] + lengths[k] - 1, rel, 0, 0,
                   dx.size, size[k], units, radius)
