"""The fit of a gesture's last samples to a template's path near its followed state, read at several
sizes (:meth:`behaviors.mop.take_rule.TakeRule._fits_take`: a new action is taken only while they
fit; the rules, their thresholds and their figures are in :mod:`behaviors.mop.take_rule`, but for
the traced mirrored paths below). Samples are raw (n, d: from the gesture's anchor, in the input's
units); a template's path is its states (in its units: ``scale``, ``first``); misfits are mean
square distances to the segments joining the states, forgotten with ``decay`` per sample (the last
weighing most) and divided by ``norm`` (sigma squared per column times the columns). Compiled: the
follower and the group call the same functions.

Mirrored paths among twenty templates, traced on the tuned joints with seeds 201-210: every wrong
take passed :meth:`~behaviors.mop.take_rule.TakeRule._fits_take`; of their valid ticks 49% were
taken at a misfit of 0.1-0.2 at the estimate, 31% within 0.1, 18% only at 1.12 times it (true takes
at 0.7-1.4x, seeds 201-204: 85%, 5.5%, 6.5% of their valid ticks). What drove on after the take (a
dance wrist on the mirrored figure eight at 0.7x, 0.24 -> 0.59 of itself) strayed 0.4-1.0 sigma^2
for 10 samples before the threshold model refused it. Measured and not kept
(``--sections=sized,unrelated``, tuned seed 13; unrelated mean over seeds 201-206):
:data:`~behaviors.mop.take_rule.TAKE_MISFIT2` 0.1: valid after 30% 0.9147 -> 0.9139, 0.6 / 1.5x
0.7581 -> 0.7498 (recognised by their end 0.975 -> 0.925), mean 0.0232 -> 0.0176; 0.08: 0.9134,
0.7302, mean 0.0155, but the ``follow`` command's circle with scale invariance
(``tests/mop/test_follow_cli.py``) is then valid on no tick (over half at 0.09); the take's fit
asked again of the action's first 10 / 15 samples while it drives (stopped beyond 0.5 / 0.4):
0.9147 / 0.9123, mean 0.0232 -> 0.0222 / 0.0216.

What it held back to back: a held-out jump ankle (seed 103, twenty templates, 0.96x) best from
0.31 of it, 50-70 nats ahead from 0.6, was never taken: the follower reached the dance ankle's end
before it 2.8 mm short of where the performer ended it, and the jump, anchored there, read
0.2-0.5 sigma^2 off its path at every one of :data:`~behaviors.mop.take_rule.TAKE_SIZES` on each
of its 51 ticks (0.02-0.09 read from where it began). So after an end a take refused is read
again from where the input came nearest the ended template's last point (until it first went
away from it), and taken within :data:`~behaviors.mop.take_rule.TAKE_FROM_NEAREST`: the jump at
0.37 of it, a punch ankle 0.45 -> 0.38. ``bench/follow_seeds.py
--sections=sized,unrelated,sequences`` (101-106): twenty within 20% or by the reach + 0.05 worst
0.375 -> 0.406 (105), mean 0.500 -> 0.505, all else unchanged; ``bench/follow_quality.py``: every
figure unchanged. Measured and not kept: within
:data:`~behaviors.mop.take_rule.TAKE_MISFIT2` itself (0.2), a spin wrist drove 0.39 of a circle
for a tick (0.205 from the anchor, 0.155 from there; held-out longest other wrong run median 0 ->
0.5); the end itself following the input nearer its last point (the next gesture anchored there,
and moved on from there; ``bench/follow_quality.py``): held-out twenty within 20% or by the reach
+ 0.05 0.625 -> 0.656, but tuned 0.50 -> 0.469, within 20% 0.406 -> 0.375, longest wrong run
2 -> 5; only the anchor there (but where the input still comes closer): a run wrist's next gesture
(``tests/mop/test_spotting.py``, fast ends) recognised 0.31 -> 0.59.
Measured and not kept: the take's fit waived for an action 20 nats ahead of every other
(``bench/follow_quality.py --sections=sequences``): only the six gestures' mean past the reach
moves (0.085 / 0.094 -> 0.079 / 0.088, tuned / held-out); no within-20% share.

What it holds back to back now (the true template's take asked at each tick from 0.2 of a
gesture to its recognition, gestures recognised after 20%; tuned and held-out 101-103, six and
twenty templates): refused on 21 of 1353 ticks, never on the tick before recognition. So neither
a limit that grows for few samples nor a take after an onset read from where the input began
moving (as :data:`~behaviors.mop.take_rule.TAKE_FROM_NEAREST` after an end) has a gesture to
free there: the lead, the commitment's fit, coverage and the confirmation hold them.

Measured with :func:`~behaviors.mop.validity.unbegun` as it is, none kept (tuned joints, seeds
201-210 and 300-309, unrelated motions through the follower; true ones: the sized gestures of seeds
201-202, 201-203 while driving). Read mirrored: at every take the last samples' least misfit over
:data:`~behaviors.mop.take_rule.TAKE_SIZES` as performed and read mirrored (x -> -x from the
anchor), over the path near the followed state or from its start: no take read better mirrored,
true (2956 checks) or on a mirrored path among twenty (327 runs, 2008 valid ticks; and 5 runs taken
by the mirrored template itself, read mirrored 3-34 sigma^2 off: anchored where its path does not
begin). Strayed while it drives: the last samples read as
:meth:`~behaviors.mop.take_rule.TakeRule._fits_take` reads them, per valid tick, lie within 0.009
/ 0.045 / 0.32 sigma^2 (median, 90%, 99%) on true performances at 0.7-1.4x and 0.16 / 0.29 / 0.53
(median, 75%, 90%) on mirrored paths among twenty. An action stopped once beyond 0.5 five samples
in a row (replayed, no retake): 11 true valid ticks of 14005 lost, 72 of 2067 on the mirrored paths
(their mean share 0.0189 -> 0.0182; beyond 0.3: 57 true ticks, 0.0169). Read from 30 states behind
to 3 ahead it stops a performer going back along the path (a wave and a zigzag to 60% and back: 122
-> 101 valid ticks); from 30 behind to 30 ahead (``bench/follow_quality.py
--sections=sized,holds,sequences,unrelated,after,pauses``): valid after 30% at 0.7-1.4x 0.9147 ->
0.9138, unrelated mean 0.01544 -> 0.01537, mirrored worst 0.0681 unchanged, the rest identical; on
the seeds above the mirrored worst unchanged (201-206); ahead to the furthest state it drove at:
one seed's mirrored worst of six 0.081 -> 0.068, the going back 122 -> 116, at a take fit per
driving member and tick. The size's edge: of the mirrored valid ticks 7% (72 of 1041) were driven
at a size of 1.45 or more, 68% within 10% of 1.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from behaviors.kernel_cache import compiled

# numba's ``njit(cache=True, nogil=True)`` in the shared cache (see tabletop.drawing.dirty.KERNEL)
KERNEL = compiled(None, error_model="python")

#: ... from this many states behind its followed state to this many ahead ...
TAKE_REACH = (30, 3)


@functools.lru_cache(maxsize=8)
def outwards(sizes: tuple[float, ...]) -> np.ndarray:
    """``sizes`` (factors of the size estimate) ordered from the estimate outwards, so a take
    that fits stops at the first size that does (:func:`take_fits`)."""
    return np.array(sorted(sizes, key=lambda f: abs(math.log(f))))


@KERNEL
def _nearest2(z: np.ndarray, path: np.ndarray) -> float:
    """The squared distance from point ``z`` (d,) to the nearest of the segments joining the
    states ``path`` (m, d)."""
    d = z.size
    nearest = math.inf
    for a in range(path.shape[0] - 1):
        za, ab2 = 0.0, 0.0
        for c in range(d):
            ab = path[a + 1, c] - path[a, c]
            za += (z[c] - path[a, c]) * ab
            ab2 += ab * ab
        t = min(max(za / max(ab2, 1e-12), 0.0), 1.0)
        dd = 0.0
        for c in range(d):
            e = z[c] - path[a, c] - t * (path[a + 1, c] - path[a, c])
            dd += e * e
        nearest = min(nearest, dd)
    return nearest


@KERNEL
def _read_near2(x: np.ndarray, scale: np.ndarray, first: np.ndarray, size: float,
                path: np.ndarray, z: np.ndarray) -> float:
    """:func:`_nearest2` of sample ``x`` (d,: raw, from the anchor) read at ``size`` in a
    template's units (``scale``, ``first``) into ``z``."""
    for c in range(x.size):
        z[c] = x[c] / scale[c] / size + first[c]
    return _nearest2(z, path)


@KERNEL
def _forgotten_weight(n: int, decay: float) -> float:
    """The sum of the weights of ``n`` samples forgotten with ``decay`` per sample (1 for the
    last), summed as the misfit's terms are."""
    weight, w = 0.0, 1.0
    for _ in range(n):
        weight += w
        w *= decay
    return weight


@KERNEL
def take_size(samples: np.ndarray, path: np.ndarray, scale: np.ndarray, first: np.ndarray,
              size: float, least: float, decay: float, norm: float, sizes: np.ndarray,
              limit: float) -> float:
    """The size below ``size`` (``sizes`` below 1 times it, none below ``least``) at which the
    mean square distance of :func:`take_fits` between ``samples`` and the segments joining
    ``path`` is least, when within ``limit``; 0 when none is. Compiled: the follower and the
    group call it alike."""
    n = samples.shape[0]
    z = np.empty(samples.shape[1])
    weight = _forgotten_weight(n, decay)
    best, best_size = limit, 0.0
    for f in sizes:
        s = size * f
        if f >= 1.0 or s < least:
            continue
        total, w = 0.0, 1.0
        for j in range(n - 1, -1, -1):
            total += w * _read_near2(samples[j], scale, first, s, path, z)
            w *= decay
        if total / weight / norm <= best:
            best, best_size = total / weight / norm, s
    return best_size


@KERNEL
def take_fits(samples: np.ndarray, path: np.ndarray, scale: np.ndarray, first: np.ndarray,
              size: float, lo: float, hi: float, decay: float, norm: float,
              sizes: np.ndarray, limit: float) -> bool:
    """Whether at any of ``sizes`` (``take_rule.TAKE_SIZES``, times ``size``, within
    ``lo``..``hi``) the mean square distance (forgotten with ``decay`` per sample, the last
    weighing most; divided by ``norm``) between ``samples`` (n, d: raw, from the anchor) read at
    that size in a template's units (``scale``, ``first``: its spread and first state) and the
    segments joining the states ``path`` (m, d) is within ``limit``. Stops at the first size
    that fits, and leaves a size once its samples so far exceed ``limit`` even were the rest to
    lie on the path (the same answer as the least over every size, at a seventh of the work for
    a true take). Compiled: the follower and the group call it alike."""
    n = samples.shape[0]
    z = np.empty(samples.shape[1])
    weight = _forgotten_weight(n, decay)
    for f in sizes:
        s = min(max(size * f, lo), hi)
        total, w = 0.0, 1.0
        for j in range(n - 1, -1, -1):
            total += w * _read_near2(samples[j], scale, first, s, path, z)
            w *= decay
            if total / weight / norm > limit:
                break
        else:
            if total / weight / norm <= limit:
                return True
    return False


@KERNEL
def take_fits_at(samples: np.ndarray, means: np.ndarray, off: int, start: int, length: int,
                 g: float, scale: np.ndarray, first: np.ndarray, size: float, lo: float,
                 hi: float, decay: float, norm: float, sizes: np.ndarray,
                 limit: float) -> bool:
    """:func:`take_fits` at ``sizes`` (``take_rule.TAKE_SIZES`` from the estimate outwards)
    within ``limit`` of a template followed at state ``g`` (its bank's index; ``start``,
    ``length``: its first state and its states), over its path from :data:`TAKE_REACH` states
    behind ``g`` to ahead of it: rows of ``means``
    (bank index plus ``off``), their first ``d`` columns (``samples`` (n, d); ``scale``,
    ``first``: as :func:`take_fits`, at least ``d`` long). True where that path is one state.
    The follower and the group (:func:`behaviors.mop.member_validity.takes`) call it."""
    a = max(start, int(g) - TAKE_REACH[0])
    b = min(int(g) + TAKE_REACH[1], start + length - 1)
    if b <= a:
        return True
    d = samples.shape[1]
    return take_fits(samples, means[a + off:b + off + 1, :d], scale[:d], first[:d], size, lo, hi,
                     decay, norm, sizes, limit)


@KERNEL
def size_of_refused(samples: np.ndarray, means: np.ndarray, arc: np.ndarray, off: int,
                    start: int, length: int, g: float, scale: np.ndarray, first: np.ndarray,
                    size: float, least: float, decay: float, norm: float, sizes: np.ndarray,
                    limit: float) -> float:
    """For a take :func:`take_fits_at` refused (same arguments; ``arc`` the rows' path lengths,
    ``least`` the smallest size the template may take): the samples may be those of a smaller
    performance the followed state lags along the path by the size's ratio, so they are read
    on the path on to where it would be at the least of ``sizes``: :func:`take_size` there (0:
    none within ``limit``). The follower and the group call it alike."""
    a = max(start, int(g) - TAKE_REACH[0])
    last = start + length - 1
    want = arc[int(g) + off] / sizes.min()
    ahead = start   # the first state as far along as ``want`` (numpy's searchsorted, left)
    while ahead <= last and arc[ahead + off] < want:
        ahead += 1
    b = min(ahead + TAKE_REACH[1], last)
    d = samples.shape[1]
    return take_size(samples, means[a + off:b + off + 1, :d], scale[:d], first[:d], size, least,
                     decay, norm, sizes, limit)
