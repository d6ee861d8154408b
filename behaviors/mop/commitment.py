"""Commitment's fit, read at the best timing offset. A template committed to by shape
(:meth:`~behaviors.mop.shape_lead.ShapeLead._committed`) drives however improbable, once its shape
fits within :data:`~behaviors.mop.shape_lead.COMMIT_FIT` still radii (RMS per column and sample
since the gesture began). That sum compares each sample with the template's *followed state*; on a
fast start the follower's state lags the performer along the path, and the sum counts the lag as a
misfit: the zigzag back to back, covered, leading every rival by 16-100 nats and met within
0.02-0.08 sigma of its path, summed 2.0-2.7 still radii, and waited 1-2 samples for the evidence
(:mod:`behaviors.mop.coverage`, the tick-by-tick reading). So the fit is also summed at each
constant offset of the followed state within :data:`COMMIT_LAGS` states either way
(:func:`lagged_fits`), and commitment reads the least: a constant lag is timing, not shape; a path
met only by a timing that changes sample by sample is not taken as fitting (below).
``bench/follow_quality.py`` (tuned / held-out, against the same figures before): six gestures back
to back within 20% 0.125 -> 0.156 / 0.125 (or reach the same), the open three 0.235 -> 0.294 /
0.308, the zigzag 0.67 -> 0.83 / 0.80 (median 0.183 -> 0.179); every other figure unchanged (sized
0.912 / 0.902, unrelated worst 0.058 / 0.099, after a gesture 0.072 / 0.083, holds, pauses, wrong
runs 1 / 1 and 2 / 11, the draws for options). On ``bench.motions.back_to_back``'s draws 0-59 with
the zigzag among their four, every gesture that changed is recognised sooner (the zigzag 0.207 /
0.231 -> 0.183 / 0.204, the circle 0.313 / 0.304 -> 0.287 / 0.278, the wave 0.290 / 0.260 -> 0.263
/ 0.234), and no wrong run grew.

The fit judged without the timing, measured and not kept (``bench/follow_quality.py``, tuned /
held-out; what it frees, the zigzag, in :mod:`~behaviors.mop.coverage`): committed while its path
misfit is within ``coverage.EARLY_FIT`` (0.25 sigma) instead of ``COMMIT_FIT``, or while its shape
sum is within 0.4 sigma of its own spread at its size: six gestures within 20% 0.125 -> 0.156 /
0.125 (the zigzag 0.67 -> 0.83), held-out twenty's longest wrong run 11 -> 9, sized 0.912 -> 0.919
/ 0.902 -> 0.906 (own spread: 0.920 / 0.902), but unrelated worst 0.058 -> 0.070 (a wander among
six; the told worst unchanged, 0.057), a spiral after a gesture 0.072 -> 0.083 (0.4 sigma: held-out
0.083 -> 0.088) and a pause's wrong valid share 0 -> 0.011; at 0.3 and 0.35 sigma no gesture
sooner.
"""

from __future__ import annotations

import numpy as np

#: Commitment's fit is read at the best constant timing offset of the followed state, within
#: this many states either way (0: at the followed state only, as the shape sums).
COMMIT_LAGS = 3


def lagged_fits(dx: np.ndarray, g: np.ndarray, starts: np.ndarray, lengths: np.ndarray,
                rel: np.ndarray, size: np.ndarray, units: np.ndarray,
                radius: np.ndarray) -> np.ndarray:
    """Per template (K,) and timing offset (-:data:`COMMIT_LAGS` .. +:data:`COMMIT_LAGS` states),
    the squared distance in still radii ``radius`` between the input ``dx`` (from the anchor, raw
    units) and the template's path at its followed state ``g`` (bank index) plus that offset,
    within the template (``rel``: each state from its template's first, at ``size``)."""
    lags = np.arange(-COMMIT_LAGS, COMMIT_LAGS + 1, dtype=float)
    first = starts.astype(float)[:, None]
    end = (starts + lengths - 1)[:, None]
    at = np.clip(g[:, None] + lags[None, :], first, end.astype(float))
    il = np.minimum(at.astype(np.intp), end - 1)
    q = rel[il] + (at - il)[..., None] * (rel[il + 1] - rel[il])
    e = (dx[None, None, :] - size[:, None, None] * q * units) / radius
    return np.einsum("kld,kld->kl", e, e)
