"""Templates a follower cannot tell apart: two paths within the path misfit's acceptance of
each other (:mod:`behaviors.mop.refusal`), however each is performed.

Template A performed exactly as recorded is measured against template B as the follower
measures an input: mapped into B's own spread (its centre and scale in the bank), each sample
against B's path at the progress it is followed to, as an RMS per column in ``sigma`` units.
The follower's progress is stood for by the monotone alignment of A's samples onto B's (each A
sample moves B's on by 0, 1 or 2 samples, from start to end) that makes that RMS least: a
path drawn backwards, or another shape along the same strokes, stays far. Two templates each
within ``shape_accept`` of the other (1.2 sigma as recorded) are alike: whichever is performed,
neither is refused on its path, and the follower splits between them.

Measured on the example gestures (``examples/mop/gestures``, sigma 0.2, features as recorded):
each one redrawn at 0.7-1.4x its tempo with 0.5-3 mm of noise is within 0.05-0.95 sigma of it
both ways along the alignment; two different gestures are 2.91 sigma apart at the least (the
wave and the zigzag), a circle, square or figure eight drawn backwards 5.1-5.7. The nearest-point
distance alone (the cheap lower bound) puts the wave within 0.82 of the zigzag and a backwards
circle within 0.04 of the circle: the alignment is what tells them apart.
"""

from __future__ import annotations

import itertools

import numpy as np

#: Samples of B an A sample may move the alignment on by (0: B waits, 2: B runs twice as fast).
MAX_STEP = 2
#: Samples of A measured at once (memory: CHUNK x len(B) x columns floats).
CHUNK = 64
#: Samples of a template measured at most (a longer one is taken every k-th sample): the
#: measure is O(len(A) x len(B)); two 8,000-sample templates took 14 s each way on a loaded
#: machine. The example gestures have 47-74.
MAX_SAMPLES = 400


def _misfit(a: np.ndarray, b: np.ndarray, center: np.ndarray, scale: np.ndarray,
            sigma: float, aligned: bool) -> float:
    """RMS per column, in ``sigma`` units of b's spread (``center``, ``scale``), of a's samples
    from b's: each from its nearest (``aligned`` False, a lower bound) or along the best
    monotone alignment."""
    za, zb = (a - center) / scale, (b - center) / scale

    def cost(rows: slice) -> np.ndarray:   # (rows, len(b)): a few rows at a time, so two
        # long templates (10,000 samples each) never hold their whole table at once
        return np.sum((za[rows, None, :] - zb[None, :, :]) ** 2, axis=2) / za.shape[1]
    if not aligned:
        near = np.concatenate([cost(slice(i, i + CHUNK)).min(axis=1)
                               for i in range(0, len(za), CHUNK)])
        return float(np.sqrt(np.mean(near))) / sigma
    total = np.full(len(zb), np.inf)
    for i in range(0, len(za), CHUNK):
        for k, row in enumerate(cost(slice(i, i + CHUNK))):
            if i + k == 0:
                total[0] = row[0]
                continue
            best = total.copy()
            for step in range(1, MAX_STEP + 1):
                np.minimum(best[step:], total[:-step], out=best[step:])
            total = best + row
    return float(np.sqrt(total[-1] / len(za))) / sigma


def _carried(a: np.ndarray, b: np.ndarray, invariance: str) -> np.ndarray:
    """``a`` as a follower of ``invariance`` sees it performed against ``b``: from b's first
    sample ("offset", "scale") and at b's size (its RMS spread; "scale")."""
    if invariance not in ("offset", "scale"):
        return a
    size = 1.0
    if invariance == "scale":
        spread_a = float(np.sqrt(np.mean((a - a.mean(axis=0)) ** 2)))
        spread_b = float(np.sqrt(np.mean((b - b.mean(axis=0)) ** 2)))
        size = spread_b / spread_a if spread_a > 0 else 1.0
    return (a - a[0]) * size + b[0]


def alike(templates: dict[str, np.ndarray], bank, sigma: float, limit: float,
          invariance: str = "none") -> list[tuple[str, str, float, float]]:
    """Pairs (a, b, a's misfit from b, b's from a; sigma) of ``templates`` (raw samples) each
    within ``limit`` of the other, in ``bank`` (the follower's
    :class:`~behaviors.mop.hmm.TemplateBank`, in the same order), as a follower of
    ``invariance`` sees them."""
    names = list(templates)
    out = []
    thin = {k: v[::-(-len(v) // MAX_SAMPLES)] for k, v in templates.items()}
    for i, j in itertools.combinations(range(len(names)), 2):
        a, b = thin[names[i]], thin[names[j]]
        a_on_b, b_on_a = _carried(a, b, invariance), _carried(b, a, invariance)
        near = []
        for aligned in (False, True):   # the cheap bound first: most pairs end there
            near = [_misfit(a_on_b, b, bank.center[j], bank.scale[j], sigma, aligned),
                    _misfit(b_on_a, a, bank.center[i], bank.scale[i], sigma, aligned)]
            if max(near) > limit:
                break
        if max(near) <= limit:
            out.append((names[i], names[j], near[0], near[1]))
    return out
