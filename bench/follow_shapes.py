"""``bench/follow_quality.py``'s ``shapes`` section: a performer's own drawing of an action's shape.

Nobody redraws a shape exactly: a performer's circle bulges where the recording did not and is
a little wider than tall. The other sections perform each template's own path (sized,
time-warped, held, with tracking jitter); here every template (six gestures, fourteen DeepMimic
joints) is performed :data:`DRAWS` times at 0.85-1.2x, time-warped, with its shape changed:
- ``shapes_bent_5pct`` / ``_10pct``: a smooth deformation (three low harmonics per axis, zero
  at the start) whose largest excursion is 5% / 10% of the template's extent (7.5 / 15 mm on
  the 15 cm DeepMimic paths);
- ``shapes_aspect_1.1`` / ``_1.2``: x divided and y multiplied by 1.1 / 1.2 (a circle 1.21 /
  1.44 times as tall as wide).

Figures per kind, as the sized section's (:func:`bench.follow_quality.true_metrics`):
``..._valid_after30_share`` (the true action valid and best after 30% of its progress) and
``..._progress_rmse_median``. Measured (``--sections=shapes``): valid after 30% 0.874 bent 5%,
0.632 bent 10%, 0.895 at aspect 1.1, 0.397 at 1.2 (held out 0.748, 0.476, 0.870, 0.435),
against 0.916 for the templates' own shapes at 0.7-1.4x (``sized``); progress RMSE median
0.016-0.030 (held out 0.024-0.041). A per-column aspect estimated as the gesture unfolds, measured
here and not kept: :mod:`behaviors.mop.invariance`.
"""

from __future__ import annotations

from typing import Callable, Mapping

import numpy as np

from bench.motions import performance

#: Performances per template and kind.
DRAWS = 2
#: (figure name, largest excursion as a share of the template's extent, aspect factor).
KINDS = (("bent_5pct", 0.05, 1.0), ("bent_10pct", 0.10, 1.0), ("aspect_1.1", 0.0, 1.1),
         ("aspect_1.2", 0.0, 1.2))


def reshaped(rng: np.random.Generator, tpl: np.ndarray, bend: float,
             aspect: float) -> np.ndarray:
    """``tpl`` (n, 2) with x / ``aspect``, y * ``aspect`` and a smooth deformation whose largest
    excursion is ``bend`` times the template's extent (0 at its first sample)."""
    u = np.linspace(0.0, 1.0, len(tpl))
    d = np.zeros_like(tpl, dtype=float)
    for j in range(tpl.shape[1]):
        for k in (1, 2, 3):
            d[:, j] += rng.normal() / k * np.sin(np.pi * k * u + rng.uniform(0.0, 2.0 * np.pi))
    d -= d[0]
    extent = float(np.ptp(tpl, axis=0).max())
    d *= bend * extent / max(1e-12, float(np.abs(d).max()))
    return tpl * np.array([1.0 / aspect, aspect]) + d


def shapes(factory: Callable, templates: Mapping[str, np.ndarray], rng: np.random.Generator,
           run: Callable, true_metrics: Callable, draws: int = DRAWS) -> dict[str, float]:
    """The ``shapes_`` figures (module docstring) with ``templates`` loaded; ``factory`` makes
    the follower (None: the section left out, its random numbers drawn all the same)."""
    f = factory(templates)
    out: dict[str, float] = {}
    for key, bend, aspect in KINDS:
        after30, rmse = [], []
        for name, tpl in templates.items():
            for _ in range(draws):
                scale = float(rng.uniform(0.85, 1.2))
                x, prog = performance(rng, reshaped(rng, tpl, bend, aspect), scale)
                if f is None:
                    continue
                m = true_metrics(run(f, x), name, prog)
                after30.append(m["valid_after30"])
                rmse.append(m["rmse"])
        if after30:
            out[f"shapes_{key}_valid_after30_share"] = float(np.mean(after30))
            out[f"shapes_{key}_progress_rmse_median"] = float(np.median(rmse))
    return out
