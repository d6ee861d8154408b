"""A circling character's darts into its main (the playful friend): where a dart the match has
entered is kept whole (step.GenerationStep._best_match), and how far in its inward relative
step goes (step.GenerationStep._trajectory). Units: metres, training sample indices.

Its demonstrated designer circles its main and darts in every 2-4 s for 0.6 s; the match
entered a dart's run-up and left it after 3.6-3.8 steps (the demonstration runs on 6.5-7.8
more), 56-62% of the time by a jump, and the linear smooth averaged the dart's inward steps
with the next moment's: beside a main looping clockwise (against its circling) its inward
steps (moments closing over 1.5 mm a step) closed 0.162 m/s raw and 0.108 m/s after the
smooth (counter-clockwise 0.238 / 0.181, the live main walking into it at 0.083 m/s), its
contact 0.0064 against its designer's 0.050 (counter-clockwise 0.051 / 0.041; seeds 0-5,
40-51, 128-139 loops paths, Python step), the contact share following the loops' sense
(correlation -0.60 with the share of clockwise less counter-clockwise steps; its designer's
0.0): the loops paths' misses were the counter-clockwise ones over, the clockwise under.

Kept whole (dart_ends) while the friend is farther out than its moment, the inward step held
(less_inward), and ended once the live main came nearer it over the last DART_SPAN_S than the
moment's main did + DART_MARGIN (dart_goes_on). The friend's misses on its contact, its
designer meeting the band (bench/fidelity.py's engine's alone; the friend generated alone,
relative_motion x 1, 1 +- 0.001 / 0.002 / 0.003, summed over the seven runs), on seeds 0-5 /
40-51 / 128-139: 11 / 25 / 26 -> 6 / 14 / 23 (a run 0-3 / 2-5 / 1-5 -> 0-2 / 1-4 / 2-6);
held-out 300-311 over nine runs (also 1 +- 0.004) 20 -> 20 (0-4 both). bench/fidelity.py
(the engine's misses, the friend's): 0-5 7 -> 5, 2 -> 0; 40-51 --perturb 2 30 / 28 / 31 ->
29 / 28 / 30, 10 -> 8; 128-139 21 / 20 / 22 -> 19 / 19 / 20, 12 -> 7; 300-311 23 / 29 / 27 ->
24 / 29 / 29, 4 -> 7 (0 / 3 / 1 the base's low draw, below). With the margin at
0.2 m/s 7 / 11 / 17 and 21, but fast mains drove it into theirs (seed 0's fast path: contact
0.081 against the band's top 0.061; 0.051 at 0.1 m/s, 0.048 at 0 m/s, 0.039 never kept).
Kept whole to the bottom with no end 7 / 12 / 19, 300-311 24; the main's approach read over
one step (demonstrated.main_approach) swung 300-311 from 0 / 3 / 1 to 2-8 a run in three,
the base's low draw. At 0 m/s, 300-311 over five runs 19 (base 6, 13 with no end), 0 m/s
and the span's turn within 0.5 rad of the moment main's 16, 0.1 m/s and 0.3 rad 14.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from behaviors.puppet_master.character import TOUCH_M

DART_DEPTH = 0.03   # m: the least fall from a run-up sample to its dart's bottom
DART_SPAN_S = 0.25   # s: the main's approach read over this span
DART_MARGIN = 0.1    # m/s: how much faster than the moment's main the live main may close


def dart_ends(distance: np.ndarray, touch: float, depth: float = DART_DEPTH) -> list[int]:
    """Per training sample the index of its dart's bottom (the next local minimum of
    ``distance`` (n,) metres, nearer than ``touch``) where the sample is in that dart's
    run-up (the distance falling there and at least ``depth`` above the bottom), else -1."""
    d = np.asarray(distance, dtype=float)
    n = d.shape[0]
    out = [-1] * n
    bottom = -1
    for i in range(n - 2, 0, -1):
        if d[i] <= d[i - 1] and d[i] <= d[i + 1]:
            bottom = i
        if d[i + 1] < d[i] and bottom > i and d[bottom] < touch and d[i] - d[bottom] > depth:
            out[i] = bottom
    return out


def span_steps(rate_hz: float) -> int:
    """Samples in the main's span read (DART_SPAN_S) at ``rate_hz`` (Hz), at least 2."""
    return max(2, int(round(DART_SPAN_S * rate_hz)))


def span_approach(nx: float, ny: float, ox: float, oy: float, bx: float, by: float) -> float:
    """How far the main came towards its reactor at (bx, by) from the main's last position
    (metres; negative away) from the span's oldest position (ox, oy) to its newest (nx, ny)."""
    rho = math.hypot(bx, by)
    return ((nx - ox) * bx + (ny - oy) * by) / rho if rho > 1e-9 else 0.0


def dart_goes_on(recent: Sequence[tuple[float, float]], n: int, moment: float, dt: float,
                 mx: float, my: float, bx: float, by: float) -> bool:
    """Whether a dart kept whole goes on: the live main at (mx, my) (table metres; its
    reactor at (bx, by) from its last position) came no nearer its reactor over its last
    ``n`` steps of ``dt`` seconds (from the oldest but n - 1 of ``recent``, its positions
    before this one) than the moment's main did (``moment`` metres, span_approaches) +
    DART_MARGIN; so while fewer are known."""
    if len(recent) < n:
        return True
    ox, oy = recent[-n]
    return span_approach(mx, my, ox, oy, bx, by) <= moment + DART_MARGIN * n * dt


def span_approaches(main: np.ndarray, react: np.ndarray, n: int) -> list[float]:
    """Per training sample i the demonstrated main's span_approach from sample i - n to i,
    towards the reactor at i - 1 (0 for the first n). ``main``, ``react``: (m, 2) metres."""
    out = [0.0] * main.shape[0]
    for i in range(n, main.shape[0]):
        out[i] = span_approach(main[i, 0], main[i, 1], main[i - n, 0], main[i - n, 1],
                               react[i - 1, 0] - main[i - 1, 0], react[i - 1, 1] - main[i - 1, 1])
    return out


def less_inward(sx: float, sy: float, qx: float, qy: float, bx: float, by: float, dist: float,
                disc: float) -> tuple[float, float]:
    """The step (sx, sy) (metres) at a place in the main's frame less the part of its
    demonstrated relative step (qx, qy) that goes inward beyond the moment: while the reactor
    at (bx, by) from its main's last position is nearer than TOUCH_M at a moment ``dist``
    metres out that is not, that inward part is scaled by the live room to the main's disc
    (``disc`` metres) over the moment's.

    Kept whole, a dart ends on the main's disc more often: a dart's inward relative step
    copied from a moment farther out pressed the friend onto the disc beside a main hardly
    closing (0.05 m/s; 58% of the steps on the disc in contacts over 0.35 s)."""
    rho = math.hypot(bx, by)
    if not 1e-9 < rho < TOUCH_M <= dist:
        return sx, sy
    a = (qx * bx + qy * by) / rho
    if a >= 0.0:
        return sx, sy
    f = 1.0 - max(0.0, min(1.0, (rho - disc) / (dist - disc)))
    return sx - f * a * bx / rho, sy - f * a * by / rho
