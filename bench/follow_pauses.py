"""``bench/follow_quality.py``'s ``pauses`` section: a performer pausing in the middle of a gesture.

A performer stops part way through an action, wherever they like (not where its template
holds), for a moment or two and goes on. They expect the character to hold its pose where they
stopped and to continue with them. Every template loaded in the bench (six gestures, fourteen
DeepMimic joints) is performed :data:`DRAWS` times at 0.7-1.4x, time-warped, with a pause of
:data:`PAUSE_SECONDS` at a progress within :data:`PAUSE_AT` (:func:`bench.motions.paused`),
between still rests; tracking jitter throughout.

Figures, over the performances whose action drove (``valid``, ``best`` the true template) on
the :data:`BEFORE` samples before the pause (``pause_driving_performances`` of them):
- ``pause_valid_share``: the share of the pause's samples it drove on;
- ``pause_wrong_valid_share``: the share a wrong action drove on;
- ``pause_held_through_share``: the share of pauses it drove through (95% of the pause or more);
- ``pause_progress_drift_median`` / ``_p90``: how far its progress moved off where the performer
  paused (the largest over the pause);
- ``pause_valid_after_share``: the share of the rest of the gesture it drove on after the pause.
"""

from __future__ import annotations

from typing import Callable, Mapping

import numpy as np

from bench.motions import paused

#: Performances per template.
DRAWS = 4
#: The samples before the pause its action must drive on for the performance to count.
BEFORE = 3
#: How long the pauses last (seconds) and where in the gesture (progress), drawn uniformly.
PAUSE_SECONDS = (0.3, 2.0)
PAUSE_AT = (0.2, 0.8)


def driven_over(states: list, name: str, pause: tuple[int, int],
                before: int = BEFORE) -> tuple[np.ndarray, np.ndarray] | None:
    """Whether ``name`` drove (valid and best) and whether another action did, at each state from
    the ``pause``'s first sample on; None unless ``name`` drove on the ``before`` samples before
    the pause."""
    right = np.array([s.valid and s.best == name for s in states])
    if not right[pause[0] - before:pause[0]].all():
        return None
    wrong = np.array([s.valid and s.best != name for s in states])
    return right[pause[0]:], wrong[pause[0]:]


def pauses(factory: Callable, templates: Mapping[str, np.ndarray], rng: np.random.Generator,
           run: Callable, draws: int = DRAWS) -> dict[str, float]:
    """The ``pause_`` figures (module docstring) with ``templates`` loaded; ``factory`` makes the
    follower (None: the section left out, its random numbers drawn all the same) and ``run``
    (:func:`bench.follow_quality.run`) steps it over samples."""
    f = factory(templates)
    rows = []
    for name, tpl in templates.items():
        for _ in range(draws):
            scale = float(rng.uniform(0.7, 1.4))
            seconds = float(rng.uniform(*PAUSE_SECONDS))
            x, prog, (a, b) = paused(rng, tpl, scale, seconds, PAUSE_AT)
            if f is None:
                continue
            states = run(f, x)
            driven = driven_over(states, name, (a, b))
            if driven is None:
                continue
            right, wrong = driven                       # from the pause's first sample on
            got = np.array([s.progress_by[name] for s in states[a:b]])
            end = int(np.flatnonzero(np.isfinite(prog[:, 0]))[-1]) + 1
            rows.append((right[:b - a].mean(), wrong[:b - a].mean(),
                         float(np.max(np.abs(got - prog[a, 0]))), right[b - a:end - a].mean()))
    if not rows:
        return {}
    during, wrong, drift, after = (np.array(c) for c in zip(*rows))
    return {"pause_driving_performances": len(rows),
            "pause_valid_share": float(during.mean()),
            "pause_wrong_valid_share": float(wrong.mean()),
            "pause_held_through_share": float(np.mean(during >= 0.95)),
            "pause_progress_drift_median": float(np.median(drift)),
            "pause_progress_drift_p90": float(np.percentile(drift, 90)),
            "pause_valid_after_share": float(after.mean())}
