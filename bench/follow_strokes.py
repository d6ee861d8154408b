"""``bench/follow_quality.py``'s ``unrelated`` section, its own strokes: a straight stroke along
each loaded template's own first direction.

The section's strokes (a diagonal at 45 degrees, the triangle's base at 0) miss most templates'
first directions; a straight stroke along a gesture's own first direction is its start until
its path leaves that line (every one of the six gestures stays within 2 mm of a straight stroke
until 0.20-0.37 of its progress), then none of it. Each template loaded (1, 6 and 20 of them, as
the section loads them) gives one path: :data:`STROKE_M` metres straight along the chord from its
start to :data:`FIRST` of its progress, drawn at 0.7, 1.0 and 1.4x as the section draws its
motions (time-warped, still before and after, tracking jitter; a seed of its own, so the other
sections draw what they drew before).

Figures (``unrelated_own_stroke_...``, :func:`bench.follow_unrelated.unrelated`): the share of
ticks valid, the largest over the strokes (each averaged over its three sizes) and the mean,
and the same counting only ticks where the stroke so far is no start of the action driving
(``told``, :func:`bench.follow_unrelated.performs`): while the stroke is still a template's
start, its character may follow it. Measured (``bench/follow_quality.py``): valid share max
0.247, told 0.098 (held out 0.517, told 0.116: a stroke along the punch ankle's own 15 cm first
stroke drives it 0.51-0.58 of its ticks on seed 104); ``bench/follow_seeds.py --sections=unrelated``
on seeds 101-112: told worst 0.219 (104), mean 0.149.
"""

from __future__ import annotations

from typing import Callable, Mapping

import numpy as np

from bench.motions import at_phase, performance

#: A stroke's length (metres; the section's diagonal runs 0.12 m along each axis).
STROKE_M = 0.12
#: A template's first direction: the chord from its start to this share of its progress.
FIRST = 0.2
#: The sizes each stroke is drawn at (as the ``unrelated`` section's motions).
SCALES = (0.7, 1.0, 1.4)


def own_strokes(templates: Mapping[str, np.ndarray]) -> dict[str, np.ndarray]:
    """``stroke_NAME``: a straight path (60 samples, metres from 0) :data:`STROKE_M` long along
    template NAME's first direction (:data:`FIRST`), for each template whose chord is not 0."""
    u = np.linspace(0.0, 1.0, 60)[:, None]
    out = {}
    for name, tpl in templates.items():
        ends = at_phase(tpl, np.array([0.0, FIRST * (len(tpl) - 1)]))
        chord = ends[1] - ends[0]
        length = float(np.linalg.norm(chord))
        if length > 0:
            out[f"stroke_{name}"] = STROKE_M * u * (chord / length)[None, :]
    return out


def stroke_shares(f, loaded: Mapping[str, np.ndarray], rng: np.random.Generator, memo: dict,
                  k: int, shares: Callable) -> tuple[dict[str, float], dict[str, float]]:
    """Each own stroke of the ``loaded`` templates (``k`` of them) followed by ``f`` at
    :data:`SCALES`: ({stroke: valid share}, {stroke: told valid share}), each the mean over
    the sizes; ``shares(f, path, x, prog, loaded, memo, key)`` is
    ``bench.follow_unrelated.motion_shares`` (its ``run`` given)."""
    valid, told = {}, {}
    for name, path in own_strokes(loaded).items():
        both = [shares(f, path, *performance(rng, path, scale), loaded, memo, (k, name))
                for scale in SCALES]
        valid[name] = float(np.mean([v for v, _ in both]))
        told[name] = float(np.mean([t for _, t in both]))
    return valid, told
