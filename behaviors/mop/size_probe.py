"""Size probes: two other sizes tried beside each template's estimate as the gesture unfolds.

The size estimate (:meth:`~behaviors.mop.invariance.PerformanceFrame._estimate_size`) is a
least squares against the *followed* state; while the size is wrong the followed state is wrong
too, and on a straight first stroke the two cannot be told apart, so the estimate stayed near 1
until well after the stroke turned: with the true size given to every template
(``--sections=sized`` draws of ``--seed=102``, valid after 30%) 0.7x 0.75 -> 0.95 and 1.4x
0.86 -> 0.96, so most of what is lost at those sizes was the estimate. As GVF keeps particles
of several scales and lets the likelihood choose, each template here also reads the input at
its size times :data:`PROBE_FACTOR` and over it: the distance of the sample (from the anchor,
in units) from the template's path (the segments from :data:`PROBE_REACH` states before the
followed state to as many after, at that size; its progress free, as a particle's), remembered
over :data:`PROBE_MEMORY` samples. On a straight stroke every size fits alike and nothing
changes; once the input turns where a smaller (larger) gesture turns, that size fits and the
current one does not. Where a probe's remembered distance falls below :data:`PROBE_RATIO` of the
current size's, and the current one is off by more than :data:`PROBE_FLOOR` squared still radii
(jitter and a bent redraw), the template takes the probe's size (its sums set to it, as
:func:`~behaviors.mop.reversal.reversal_size` does) and the probes start again around it.

Measured with ``bench/follow_quality.py --sections=sized,unrelated,holds --seed=N --debug`` (valid
after 30% at 0.7-1.4x, tuned / held-out at seeds 101, 102, 103; unrelated worst, tuned / held-out
101 / 102 / 103), before: 0.9121 / 0.9022, 0.8749, 0.9055; 0.058 / 0.099, 0.085, 0.105 (103 was
over 0.10 before too). For every template (ratio 0.3, factor 1.2, memory 8, reach 8 / 25, floor 2):
0.9267 / 0.9199, 0.9144, 0.9109; 0.057 / 0.099, 0.085, 0.105; unrelated mean 0.0110 -> 0.0118
(tuned), 0.0128 -> 0.0135 (101), 0.0129 -> 0.0139 (102); holds unchanged (RMSE max 0.055, backward
0.0013). Per size (tuned, 0.6 / 0.7 / 0.85 / 1.0 / 1.2 / 1.4 / 1.5x): 0.594 / 0.801 / 0.922 / 0.948
/ 0.959 / 0.930 / 0.915 -> 0.702 / 0.831 / 0.927 / 0.951 / 0.960 / 0.964 / 0.945; held-out 101
0.528 / 0.809 / 0.940 / 0.952 / 0.943 / 0.867 / 0.822 -> 0.632 / 0.856 / 0.940 / 0.952 / 0.942 /
0.910 / 0.876 (a 0.6x getup facedown wrist 0.00 -> 1.00, a 1.4x dance ankle 0.60 -> 0.96; no
performance of seed 101 lost 0.1 or more). Not kept: ratio 0.5: 0.9429 / 0.9228, 0.9156, 0.9188
(0.6x 0.757) but unrelated worst 0.113 / 0.184, 0.138, 0.133 (the diagonal among six and twenty: a
size for every slightly bent first stroke); ratio 0.5 with floor 4: 0.9362 / 0.9225, worst 0.113 /
0.192; memory 12: 0.9393 / 0.9225, worst 0.077 / 0.187; factor 1.15: 0.9337 / 0.9171, worst 0.081 /
0.180. What limits it is what a size probe also does: it lets a template fit a stroke that is not
it at some size. The sized subset of ``tests/mop/test_quality.py`` 0.817 -> 0.886 (every template).
Left: a 0.7x figure eight (its straight first stroke) is still lost to other gestures until the
probe has seen the turn for about its memory.

Restricted to the template driving, and not while it is strained (as a reversal's size,
:meth:`~behaviors.mop.invariance.PerformanceFrame._reversal_sizes`): probes for every template let
rivals grow to fit the input (the live example's 1.45x line not recognised, a triangle driving the
square, the circle's chord). With it (:data:`PROBE_DRIVING_ONLY`):
``--sections=sized,unrelated,holds --seed=N``, tuned 0.9239, held-out 101 / 102 / 103 0.9116 /
0.8839 / 0.9065, unrelated worst 0.057 / 0.099 / 0.085 / 0.105, holds unchanged, but held-out
redrawn shapes lower. Gated by the input turning (:data:`PROBE_TURN_COS` 0.7, every template):
0.9144 / 0.908, eight failed.

Kept: only the best template while no action drives (:func:`probe_allowed`), only to a smaller
size, its sums started afresh at each sample it may not be probed (:data:`PROBE_FRESH`) and
settled over :data:`PROBE_SETTLED` 0.8 of the memory (13 samples as the best) before a probe:
``bench/follow_seeds.py --sections=sized`` 101-106 0.9022 / 0.8749 / 0.9055 / 0.8871 / 0.8818 /
0.8744 -> 0.9022 / 0.8749 / 0.9057 / 0.8871 / 0.8860 / 0.8744, 107-112 109 0.8686 -> 0.8691, the
rest the same; ``--sections=unrelated,holds,sequences`` identical; ``bench/follow_quality.py
--sections=shapes,after``: shapes identical, after mean 0.0639 -> 0.0632. Without the fresh start,
settled after 0.6 (7 samples): sized mean 0.8876 -> 0.8891, but held-out aspect 1.1 0.8674 ->
0.8500 and bent 5% 0.7450 -> 0.7215 (a dance ankle shrunk at its take from a size near right,
then refused); not fresh at 0.8, and fresh at 0.6: the same aspect 1.1 loss; fresh and 0.9:
held-out after mean 0.0620 -> 0.0628."""

from __future__ import annotations

import math

import numba
import numpy as np

from behaviors.kernel_cache import compiled

#: The probes' sizes: the estimate divided and multiplied by this.
PROBE_FACTOR = 1.1
#: A probe is taken once its remembered squared distance is below this share of the current
#: size's (0: never).
PROBE_RATIO = 0.3
#: Samples over which the probes' distances are remembered (exponentially forgotten).
PROBE_MEMORY = 8.0
#: States before and after the followed state whose segments the probes measure against.
PROBE_REACH = (8, 25)
#: The current size's remembered squared distance must be over this many squared still radii
#: (summed over the columns, in units) before a probe is taken.
PROBE_FLOOR = 2.0
#: The probe sums' weight (in samples) before a probe may be taken: this share of the memory.
PROBE_SETTLED = 0.8
#: A probe is taken only while the input turns: its motion over the last :data:`PROBE_TURN_LAG`
#: samples against the motion over as many before at a cosine below this (1: at any sample).
PROBE_TURN_COS = 1.0
#: Samples of each of the two motions whose angle tells whether the input turns.
PROBE_TURN_LAG = 3
#: Probes only for the template driving (an action taken), none for its rivals.
PROBE_DRIVING_ONLY = True
#: Probes for the template driving.
PROBE_DRIVING = False
#: While no action drives, the best template (not refused, not strained) is probed too.
PROBE_IDLE = True
#: Probes to a larger size too (else only to a smaller one).
PROBE_GROW = False
#: A template's probe sums start afresh at each sample its probes may not be taken, so a
#: template just become the best is probed only once they have settled again.
PROBE_FRESH = True


@compiled(numba.boolean(numba.boolean, numba.boolean, numba.boolean, numba.boolean,
                        numba.boolean))
def probe_allowed(driving: bool, idle: bool, best: bool, refused: bool, strained: bool) -> bool:
    """Whether a template's probes may be taken: ``driving`` (it is the action driving),
    ``idle`` (no action drives and :data:`PROBE_IDLE`), ``best`` (it is the best), ``refused``
    (the refusal rules refused it), ``strained`` (its recent distance is over the acceptance's)."""
    if strained:
        return False
    if not PROBE_DRIVING_ONLY:
        return True
    if driving:
        return PROBE_DRIVING
    return idle and best and not refused


@compiled(numba.boolean(numba.float64[:, :, ::1], numba.intp[::1], numba.intp,
                        numba.float64[:, ::1], numba.float64[::1], numba.float64))
def input_turns(buf: np.ndarray, count: np.ndarray, i: int, x: np.ndarray, units: np.ndarray,
                move2: float) -> bool:
    """Whether the input turns at this sample ``x[i]``: its motion over the last
    :data:`PROBE_TURN_LAG` samples against the motion over as many before (``buf[i]``'s last
    rows, ``count[i]`` of them valid) at a cosine below :data:`PROBE_TURN_COS`, each longer
    than ``sqrt(move2)`` (units)."""
    lag = PROBE_TURN_LAG
    s = buf.shape[1]
    if PROBE_TURN_COS >= 1.0:
        return True
    if count[i] < 2 * lag or s < 2 * lag:
        return False
    a, b = s - 2 * lag, s - lag
    n1 = 0.0
    n2 = 0.0
    dot = 0.0
    for c in range(x.shape[1]):
        v1 = (buf[i, b, c] - buf[i, a, c]) / units[c]
        v2 = (x[i, c] - buf[i, b, c]) / units[c]
        n1 += v1 * v1
        n2 += v2 * v2
        dot += v1 * v2
    return n1 > move2 and n2 > move2 and dot < PROBE_TURN_COS * math.sqrt(n1 * n2)


@compiled(numba.float64(numba.float64[:, ::1], numba.intp, numba.intp, numba.intp,
                        numba.float64, numba.float64[::1], numba.float64, numba.float64))
def path_gap2(rows: np.ndarray, col: int, first: int, last: int, g: float, r: np.ndarray,
              size: float, factor: float) -> float:
    """The squared distance (units) of ``r`` (d,: the sample from the anchor, in units) from the
    template's path at ``size * factor``: the segments joining its states (``rows[j, col:col +
    d]``: relative to its first, in units; ``first``..``last`` its rows) from
    :data:`PROBE_REACH` states before the followed state ``g`` (a row) to as many after."""
    s = size * factor
    d = r.size
    c0 = int(g)
    a0 = max(c0 - PROBE_REACH[0], first)
    a1 = min(c0 + PROBE_REACH[1], last)
    if a1 <= a0:
        j = min(c0, last)
        e = 0.0
        for c in range(d):
            e += (r[c] - s * rows[j, col + c]) ** 2
        return e
    best = np.inf
    for j in range(a0, a1):
        ab2 = 0.0
        az_ab = 0.0
        for c in range(d):
            ab = rows[j + 1, col + c] - rows[j, col + c]
            az = r[c] / s - rows[j, col + c]
            ab2 += ab * ab
            az_ab += az * ab
        t = min(max(az_ab / max(ab2, 1e-12), 0.0), 1.0)
        e = 0.0
        for c in range(d):
            off = r[c] / s - rows[j, col + c] - t * (rows[j + 1, col + c] - rows[j, col + c])
            e += off * off
        e *= s * s
        if e < best:
            best = e
    return best


@compiled(numba.float64(numba.float64[:, ::1], numba.intp, numba.intp, numba.intp,
                        numba.float64, numba.float64[::1], numba.float64, numba.float64[::1],
                        numba.float64, numba.float64, numba.float64, numba.boolean))
def probe_size(rows: np.ndarray, col: int, first: int, last: int, g: float, r: np.ndarray,
               size: float, probe: np.ndarray, floor2: float, lo: float, hi: float,
               turns: bool) -> float:
    """One sample's probes (see the module docstring) for one template: ``probe`` (4,) holds
    the remembered squared distances at ``size`` / :data:`PROBE_FACTOR`, ``size``, ``size`` x
    :data:`PROBE_FACTOR` and their weight, updated in place (cleared when a probe is taken).
    ``floor2``: :data:`PROBE_FLOOR` squared still radii (units); ``lo``, ``hi``: the size's
    range. The size a probe finds (within ``lo``-``hi``, not ``size`` itself), else 0."""
    keep = 1.0 - 1.0 / PROBE_MEMORY
    probe[0] = probe[0] * keep + path_gap2(rows, col, first, last, g, r, size, 1.0 / PROBE_FACTOR)
    probe[1] = probe[1] * keep + path_gap2(rows, col, first, last, g, r, size, 1.0)
    probe[2] = probe[2] * keep + path_gap2(rows, col, first, last, g, r, size, PROBE_FACTOR)
    probe[3] = probe[3] * keep + 1.0
    if PROBE_RATIO <= 0.0 or not turns or probe[3] < PROBE_SETTLED * PROBE_MEMORY:
        return 0.0
    if probe[1] <= floor2 * probe[3]:
        return 0.0
    p = 0 if probe[0] < probe[2] or not PROBE_GROW else 2
    if not probe[p] < PROBE_RATIO * probe[1]:
        return 0.0
    s = min(max(size * (1.0 / PROBE_FACTOR if p == 0 else PROBE_FACTOR), lo), hi)
    if s == size:
        return 0.0
    for c in range(4):
        probe[c] = 0.0
    return s


@compiled(numba.void(numba.float64[:, ::1], numba.intp, numba.intp, numba.intp, numba.float64,
                     numba.float64[::1], numba.float64[::1], numba.float64, numba.float64,
                     numba.float64, numba.float64[::1], numba.float64[::1], numba.float64[::1],
                     numba.float64[::1], numba.float64, numba.intp, numba.boolean))
def take_probe(rows: np.ndarray, col: int, first: int, last: int, g: float, r: np.ndarray,
               probe: np.ndarray, floor2: float, lo: float, hi: float, num: np.ndarray,
               den: np.ndarray, size: np.ndarray, least: np.ndarray, prior: float,
               k: int, turns: bool) -> None:
    """:func:`probe_size` for template ``k`` after its size estimate: a size found becomes
    the estimate (``num`` set so ``(num + prior) / (den + prior)`` is it; ``size[k]`` that,
    at least ``least[k]``, within ``lo``-``hi``), for the follower and the group alike."""
    if PROBE_FRESH and not turns:
        for c in range(4):
            probe[c] = 0.0
        return
    s = probe_size(rows, col, first, last, g, r, size[k], probe, floor2, lo, hi, turns)
    if s > 0.0:
        num[k] = s * (den[k] + prior) - prior
        size[k] = min(max(max(s, least[k]), lo), hi)
