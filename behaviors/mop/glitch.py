"""Glitches: a live sample held as lost because one frame of the tracker or the mocap misread it.

Two rules, either makes a finite sample a glitch, and only one sample in a row (a second in a
row is a real departure and is followed: :meth:`~behaviors.mop.follower.ActionFollower._glitch`,
the group's :meth:`~behaviors.mop.group.FollowerGroup._glitched`, alike). A glitch is held as a
lost sample is: nothing changes, the state is returned invalid.

A jump (:func:`glitch_limits`): farther from the last sample followed, in any column, than
:data:`GLITCH_STEPS` times the templates' largest per-sample step in that column at the largest
size (``scale_range``'s top), plus :data:`GLITCH_SIGMAS` sigmas of noise: 19 cm in x and y with
the example gestures. One sample of dx = 5 m at row 11 of the example circle (61 rows, the six
example gestures loaded) made the follower end on the zigzag (features as recorded) or the line
("scale"), valid on no row, where the clean circle ends on it at p 1.0 (valid on 45 / 43 rows):
its log-likelihood, thousands of nats below every state, outweighed the whole performance in
the evidence and the refusal's memory. Tried without the noise term (10-12 cm here): noisy
streams (``tests/mop/test_follower.py``'s performances with noise of a tenth of the spread)
had samples held and lost accuracy.

Off every path (:func:`path_distance`): a misread of 5-18 cm is under that limit and cost as
much. The sample lies farther than :data:`OFF_PATH` sigmas (RMS per feature, in each template's
own units and estimated size) from every state that a likely template (not refused, its
evidence within :data:`OFF_PATH_NATS` of the likeliest's) can reach from its progress in one
step (:data:`REACH_BACK` states back to :data:`REACH_AHEAD` ahead of the state at its mean),
while the last sample followed lay within :data:`ON_PATH` sigmas of one, and no likely template has
its last state in reach (a gesture at its end: the next may begin anywhere). Its log-likelihood,
four to nine sigmas (RMS) below the followed template's, let whichever template lay nearest the
misread point (another gesture's stretch, 0.8 sigma from it at row 40 of the circle) take tens of
nats of evidence at once and the refusal's recent likelihood refuse the circle; in the forward
window all probability went to the state nearest the glitch. Held, none of that happens.
Measured on the example circle in ``tabletop follow`` (the six example gestures
loaded; one misread sample, dx or dy off by +-5, 8, 10, 13, 16 or 18 cm at row 6, 11, 20, 30, 40
or 50: 144 runs per invariance): valid rows, min / median over the runs, and the runs that
lost more than two rows against the clean circle (45 "none", 43 "scale" and "offset"):

===================================================  ============  ============  ============
rule                                                 "none"        "scale"       "offset"
===================================================  ============  ============  ============
the jump alone (before)                              4 / 36.5, 87  0 / 25, 103   0 / 32.5, 98
off the followed template's reach (``best`` alone)   43 / 43, 0    33 / 41, 1
off every template's reach (not refused)             25 / 44, 3    4 / 42, 11
off every likely template's reach (kept)             44 / 44, 0    34 / 42, 1    41 / 42, 0
===================================================  ============  ============  ============

``best`` alone was too narrow: the line (2 mm of spread in y) leads the first samples of the
circle, the zigzag and the square and they leave it as they turn (a clean sample held in each).
Every template not refused was too wide: a misread point in an unlikely template's reach let it
take the evidence anyway. The one run left (scale, 5 cm at row 11) lies within 3 sigmas.
Without the last-sample condition the rule held every other sample of a departure that
persists, and of a wrong template's stretch the input leaves as fast as a performer goes:
with the last sample within 3 sigmas, 32 samples held in 216 clean example gestures at
0.6-1.4x as recorded and twice as fast (within 1 or 0.5: 8, all with "offset" or at the
square's corner), and ``bench/follow_quality.py --sections=sized,holds,sequences,unrelated,after``
valid after 30% at 0.6x and 1.5x 0.758 -> 0.745 (a 0.6x circle 0.36 -> 0). Within 1 sigma:
valid after 30% at 0.7-1.4x 0.9124 -> 0.9143, unrelated motions worst 0.0742 -> 0.0681 but
mean 0.0163 -> 0.0169 (mirrored mocap paths among twenty templates); within 0.5 (kept) the
misreads are held as at 1 and no figure gets worse (below). Without the end rule, a wave
handed over to a run's wrist stroke at once (``tests/mop/test_sequences.py``) had three
samples held and the run was not recognised within 20%; a reach as wide as the forward
window instead (15 states either way) held none there but let 10 of the 144 misreads by:
the misread point lies near the circle's own path farther on. Within 1 and off beyond 4
sigmas instead of 3: the same sized and unrelated figures as kept.

``bench/follow_quality.py --sections=sized,holds,sequences,unrelated,after``, before -> after
(kept): unrelated motions worst 0.0742 -> 0.0681, mean 0.0163 -> 0.0161 (a mirrored mocap
path among twenty templates); every other figure unchanged to the last digit.
"""

from __future__ import annotations

from typing import Mapping

import numba
import numpy as np

import behaviors.mop.compiled
from behaviors.kernel_cache import compiled
from behaviors.mop.compiled import CONTRACT

_CALLS_INTO = (behaviors.mop.compiled,)

#: A sample farther from the last one followed than this many of the templates' largest
#: per-sample steps at the largest size (plus :data:`GLITCH_SIGMAS` of noise), in any column,
#: is a glitch: the forward's longest skip (3 states a sample; performers go up to twice the
#: recorded speed).
GLITCH_STEPS = 3.0
#: ... plus this many ``sigma`` of the templates' widest spread in that column: two samples
#: each 3 sigma off, in opposite directions.
GLITCH_SIGMAS = 6.0
#: Sigmas (RMS per feature) from every state a likely template may reach beyond which a sample
#: is a glitch (:func:`path_distance`) ...
OFF_PATH = 3.0
#: ... when the last sample followed lay within this many of one (on a path).
ON_PATH = 0.5
#: Nats of evidence below the likeliest template's within which a template is likely.
OFF_PATH_NATS = 4.6
#: The states a template may reach in one step: from this many before the state at its mean ...
REACH_BACK = 1
#: ... to this many after it (the state after the mean, the forward's skips of up to three
#: from it, and one of slack).
REACH_AHEAD = 5


def glitch_limits(templates: Mapping[str, np.ndarray], largest_size: float, sigma: float,
                  scale: np.ndarray) -> np.ndarray:
    """Per column (d,), in the features' units, the step from the last sample followed beyond
    which a sample is a glitch: :data:`GLITCH_STEPS` times the largest step of any template
    in that column at ``largest_size``, plus :data:`GLITCH_SIGMAS` times ``sigma`` of the
    widest of the templates' ``scale`` (K, d) there (the noise every template accepts)."""
    top = np.max([np.abs(np.diff(np.asarray(a, dtype=float), axis=0)).max(axis=0)
                  for a in templates.values()], axis=0)
    return GLITCH_STEPS * largest_size * top + GLITCH_SIGMAS * sigma * scale.max(axis=0)


_F1, _F2 = numba.float64[::1], numba.float64[:, ::1]
_I1, _B1 = numba.intp[::1], numba.boolean[::1]
# columns of a group's per-template state (group_layout.FLOATS)
_FA1, _BA1 = numba.float64[:], numba.boolean[:]


@compiled(numba.float64(_F2, _F2, _I1, _I1, _F1, _FA1, _BA1, numba.intp, numba.intp, numba.intp,
                        numba.intp, numba.intp),
          *_CALLS_INTO, fastmath=CONTRACT)
def path_distance(z, means, starts, lengths, mean, evidence, refused, a0, a1, d, back,
                  ahead) -> float:
    """The squared distance (summed over the ``d`` columns, standardised units) of the sample,
    ``z[k, :d]`` in template k's units (K, width), from the nearest state of ``means``
    (states, width) that a likely template among ``a0:a1`` can reach from its progress
    ``mean[k]`` (states): one not ``refused``, its ``evidence`` within :data:`OFF_PATH_NATS`
    of the likeliest not refused; infinite when every one is refused (on no path)."""
    top = -np.inf
    for k in range(a0, a1):
        if not refused[k] and evidence[k] > top:
            top = evidence[k]
    near = np.inf
    for k in range(a0, a1):
        if refused[k] or evidence[k] < top - OFF_PATH_NATS:
            continue
        at = int(mean[k])
        lo = max(at - back, 0)
        hi = min(at + ahead, lengths[k] - 1)
        if hi == lengths[k] - 1:   # its end in reach: a new gesture may begin anywhere
            return 0.0
        for j in range(starts[k] + lo, starts[k] + hi + 1):
            s = 0.0
            for c in range(d):
                diff = z[k, c] - means[j, c]
                s += diff * diff
            near = min(near, s)
    return near


@compiled(numba.boolean(_F2, _F2, _I1, _I1, _F1, _FA1, _BA1, _I1, _I1, _I1, _I1, _F1, numba.intp,
                        numba.intp, _F1, _B1, _B1, _B1),
          *_CALLS_INTO, fastmath=CONTRACT)
def path_distances(z, means, starts, lengths, mean, evidence, refused, bounds, counts, dims, best,
                   out, back, ahead, limit2, off, held, strayed) -> bool:
    """:func:`path_distance` of every member of a group into ``out`` (M,): member i's templates
    are ``bounds[i]`` on, ``counts[i]`` of them, its features ``dims[i]``; 0 while it has no
    ``best`` yet (-1). Beyond ``limit2`` (M,) into ``off``; returns whether any member off
    its paths is a glitch by it (neither ``held`` the tick before nor ``strayed``): the numpy
    calls the group made of these after it (four), here. With :meth:`WindowedForward.seat`'s
    early return and the bend's mask applied in :func:`behaviors.mop.members.conclude`, a
    one-member group of 6 templates (a paused gesture's replay, :mod:`behaviors.mop.resume`)
    stepped 121.3 -> 104.0 and 111.7 -> 94.0 us median thread time (two runs of 3000 steps
    interleaved in one process, load 8-9, every output the same); DESIGN's 8 x 100 tick 1744.1
    -> 1756.7 us (within the noise of +-40 us).
    """
    glitch = False
    for i in range(bounds.size):
        a0 = bounds[i]
        out[i] = 0.0 if best[i] < 0 else path_distance(z, means, starts, lengths, mean, evidence,
                                                      refused, a0, a0 + counts[i], dims[i],
                                                      back, ahead)
        off[i] = out[i] > limit2[i]
        glitch = glitch or (off[i] and not held[i] and not strayed[i])
    return glitch
