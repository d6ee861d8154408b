"""``bench/follow_quality.py``'s ``unrelated`` section: motions that are none of the templates.

A diagonal line, a triangle, a spiral, an aimless wander, a still puck and every template
mirrored (:func:`bench.motions.unrelated_motions`), each at 0.7, 1.0 and 1.4x, with 1, 6 and 20
templates loaded, and a straight stroke along each loaded template's own first direction
(:mod:`bench.follow_strokes`). Figures: the share of ticks valid (``unrelated_..._valid_share``),
and of those where the motion so far is no start of the action driving (``told``,
:func:`performs`: a triangle's first stroke *is* a line drawn outward, which the line's
character may follow).
"""

from __future__ import annotations

import functools
from typing import Callable, Mapping

import numpy as np

from behaviors.mop.follower import ActionFollower
from bench.motions import at_phase, mirror_copies, performance, unrelated_motions


#: How far (metres) an unrelated motion so far may stray from a start of the action driving
#: (at any size and tempo) for that action to be a reading of it a performer expects
#: (:func:`performs`): twice the ideal observer's 2 mm (``bench/spotting_reach.py``), as a hand
#: drawing a 15 cm line by eye wanders a few millimetres off it.
PERFORMS_M = 0.004


def performs(path: np.ndarray, p: float, other: np.ndarray, memo: dict, key: tuple) -> bool:
    """Whether ``path`` up to progress ``p`` (noise-free) left its start and is a start of the
    template ``other`` within :data:`PERFORMS_M` at some size and tempo: a partial performance
    of ``other`` (the triangle's first stroke is a line drawn outward; a line out to the left
    and back is an action that goes out to the left and most of the way back), which its
    character may follow. A still puck performs nothing."""
    key = (*key, round(p, 2))
    if key not in memo:
        from bench.spotting_reach import closest_start
        prefix = at_phase(path, np.linspace(0, key[-1] * (len(path) - 1), int(400 * key[-1]) + 2))
        moved = float(np.max(np.linalg.norm(prefix - prefix[0], axis=1))) > PERFORMS_M
        memo[key] = moved and closest_start(prefix, other) <= PERFORMS_M
    return memo[key]


def motion_shares(f: ActionFollower | None, path: np.ndarray, x: np.ndarray, prog: np.ndarray,
                  loaded: Mapping[str, np.ndarray], memo: dict, key: tuple,
                  run: Callable) -> tuple[float, float]:
    """(valid share, told valid share: :func:`unrelated`) of the performance ``x`` (true
    progress ``prog``) of the unrelated ``path`` followed by ``f`` with ``loaded``; ``run`` is
    ``bench.follow_quality.run``."""
    states = run(f, x)
    # before the motion: nothing performed; after it: all of it
    p = np.where(np.isfinite(prog[:, 0]), prog[:, 0],
                 np.arange(len(x)) > np.argmax(np.isfinite(prog[:, 0])))
    told = np.mean([s.valid and not performs(path, float(q), loaded[s.best], memo,
                                             (*key, s.best))
                    for s, q in zip(states, p)]) if f is not None else 0.0
    return float(np.mean([s.valid for s in states])), float(told)


def unrelated(factory: Callable, templates: dict[str, np.ndarray], rng: np.random.Generator,
              strokes_rng: np.random.Generator, run: Callable,
              debug: bool = False) -> dict[str, float]:
    """Valid share on motions that are none of the templates (``unrelated_..._valid_share``),
    and the same counting only ticks where the action driving is one the motion so far does not
    partially perform (``unrelated_..._told_valid_share``, :func:`performs`): a performer drawing
    a stroke that *is* the start of an action expects its character to follow, whatever comes
    after. Then the same of straight strokes along each template's own first direction
    (``unrelated_own_stroke_...``, drawn with ``strokes_rng``: :mod:`bench.follow_strokes`).
    ``run`` is ``bench.follow_quality.run``; ``debug`` prints each motion's shares."""
    from bench.follow_strokes import stroke_shares
    out = {}
    names = list(templates)
    worst_all, told_worst = 0.0, 0.0
    every: list[float] = []
    told_every: list[float] = []
    memo: dict = {}
    own: list[float] = []
    own_told: list[float] = []
    for k in (1, 6, 20):
        loaded = {n: templates[n] for n in names[:k]}
        f = factory(loaded)
        valid, told_valid = stroke_shares(f, loaded, strokes_rng, memo, k,
                                          functools.partial(motion_shares, run=run))
        out[f"unrelated_{k}_templates_own_stroke_valid_share_max"] = max(valid.values())
        out[f"unrelated_{k}_templates_own_stroke_told_valid_share_max"] = max(told_valid.values())
        own += valid.values()
        own_told += told_valid.values()
        shares, told = {}, {}
        copies = mirror_copies(loaded)
        for name, path in unrelated_motions(rng, loaded, copies=True).items():
            vals, told_vals = [], []
            for scale in (0.7, 1.0, 1.4):
                x, prog = performance(rng, path, scale)
                if name in copies:   # another template performed: drawn, not counted
                    continue
                valid, told_valid = motion_shares(f, path, x, prog, loaded, memo, (k, name), run)
                vals.append(valid)
                told_vals.append(told_valid)
            if name in copies:
                continue
            shares[name], told[name] = float(np.mean(vals)), float(np.mean(told_vals))
            if debug:
                print(k, name, [round(float(v), 3) for v in vals],
                      "told", [round(float(v), 3) for v in told_vals])
        mirrored = [v for n, v in shares.items() if n.startswith("mirrored_")]
        # every motion with this many templates loaded (the target holds for any count)
        out[f"unrelated_{k}_templates_valid_share_mean"] = float(np.mean(list(shares.values())))
        for base in ("diagonal", "triangle", "spiral", "wander", "still"):
            out[f"unrelated_{k}_templates_{base}_valid_share"] = shares[base]
        if mirrored:
            out[f"unrelated_{k}_templates_mirrored_valid_share_max"] = float(max(mirrored))
        out[f"unrelated_{k}_templates_told_valid_share_max"] = float(max(told.values()))
        worst_all = max(worst_all, max(shares.values()))
        told_worst = max(told_worst, max(told.values()))
        every += shares.values()
        told_every += told.values()
    out["unrelated_valid_share_max"] = worst_all
    # the mean over every motion and template count: how much of the refusal is won overall
    out["unrelated_valid_share_mean"] = float(np.mean(every))
    # what the target counts: valid where the motion so far is no start of the action
    out["unrelated_told_valid_share_max"] = told_worst
    out["unrelated_told_valid_share_mean"] = float(np.mean(told_every))
    out["unrelated_own_stroke_valid_share_max"] = max(own)
    out["unrelated_own_stroke_valid_share_mean"] = float(np.mean(own))
    out["unrelated_own_stroke_told_valid_share_max"] = max(own_told)
    out["unrelated_own_stroke_told_valid_share_mean"] = float(np.mean(own_told))
    return out
