"""A best that may not drive: a template taken at a crawl (:func:`~behaviors.mop.validity.
slow_take`) at a size below :data:`BLOCKED_SIZE` keeps the most evidence (its Jacobian earns it
``dim ln(1/size)`` nats a sample) while the true action, sized right, is never ``best``: the
held-out getup facedown wrist at 1.4x under the kick's wrist sized 0.63, its followed state
stuck at 0.22-0.24 for 40-50 samples. Such a best, blocked :data:`BLOCKED_SAMPLES` samples in a
row, is barred from ``best`` while it leads (``best`` is the likeliest of the others, MOP
section 3.2's choice among the templates that may drive), until it began anew or may drive
again (neither sharing its start nor crawling); the validity then reads the probabilities and
the threshold model's share among the others, and a template once barred does not drive until
its performance begins anew.

Measured (``bench/follow_seeds.py --sections=sized,unrelated,sequences``, see the figures in
:mod:`behaviors.mop.recognition`). Not kept: a best sharing its start blocked too (the 0.7x
line under the square: a line's return no longer ends it, the next circle valid 10 samples
later; unrelated worst 107-112 0.1154 -> 0.1484); any size (107 / 112 unrelated 0.0914 /
0.0936 -> 0.1399 / 0.1484); the barred one allowed to drive once freed (its crawl run broken
by the bar: a wave sized 0.55 on a wander among six, valid 0.068 -> 0.162).
"""

from __future__ import annotations

import numpy as np

#: Samples in a row ``best`` may be blocked before it is barred (0: never barred).
BLOCKED_SAMPLES = 4
#: ... and sized below this. Held-out seed 107's worst unrelated motion (0.0914 unbarred): any
#: size 0.1399, below 0.8 0.1206, with the threshold model's share against the others 0.0981,
#: and the barred one kept from driving 0.0914.
BLOCKED_SIZE = 0.8


def blocked_run(run: int, same: bool, blocked: bool) -> int:
    """Samples in a row ``best`` was blocked: ``run`` before, ``same``: the same best as then."""
    return (run + 1 if same else 1) if blocked else 0


def likeliest_other(evidence: np.ndarray, barred: int) -> int:
    """The template of most evidence other than ``barred`` (the first of equals)."""
    best, top = -1, -np.inf
    for k, e in enumerate(evidence.tolist()):
        if k != barred and (best < 0 or e > top):
            best, top = k, e
    return best
