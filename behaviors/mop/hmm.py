"""Template HMMs (MOP section 3.2.1): left-to-right states built from recorded samples.

A template is one recording of an action, ``(n, d)`` samples regularly spaced in time. Each sample
becomes one state whose observation probability is a Gaussian centred on the (standardised)
sample with a shared relative ``sigma`` (equation 1). Each template is standardised by its *own*
spread (each column's spread in the features' units, at least half the template's RMS spread),
so how far a performance may stray from an action depends on that action alone, not on the other
templates loaded beside it. Measured (``tests/mop/test_live.py``, the bird alone on its puck):
one isotropic spread per template (x and y alike) let the bird take 3 of 17 other gestures at
60% of them (the zigzag is a wave that swings wider in y); per column, 0 of 17. The units
are given (a puck's metres) or, when unknown, the pooled per-column spread of the set
(:func:`behaviors.mop.features.fit_scale`), so features of any scale work without tuning. Units
unknown, the column floor compares a template's columns in the set's pooled units, the one
place its scale still depends on the others: beside a line ten times as long (its x spread
0.54 m, y 6 mm) the circle's x scale is floored 4.5 -> 13.7 cm, beside a circle ten times as
large it stays its own (``tests/mop/test_hmm.py``). With units given nothing of the set enters.

Holds: a run of samples that stays within ``hold_tolerance`` (in the template's own spread) of
its first sample is kept as three states (first, middle, last) that map back to the progress
of the whole run, so a performer may hold for any time (the last state loops) and a short hold
is crossed in three steps instead of the recorded run's length. Measured with
``bench/follow_quality.py`` (raise-hold-return at holds 0.3-3x). The states of a hold inside a
template also *dwell* (``Transitions.dwell``, :func:`dwell_states`): each step that share of
their probability stays before the transitions move the rest. Without it the prior's drift of
about a state per step carried the progress through the three states of a hold and on into the
return's eased start (which matches a held input as well) while the performer slowed into the
hold or held it long: 0.3 ahead of a lift slowing into its hold. Progress RMSE over the whole
action, max / median of 15 performances (held-out seed in brackets): dwell 0 0.093 / 0.036
(0.080 / 0.035), 0.5 0.074 / 0.033 (0.091 / 0.032), 0.65 0.063 / 0.032 (0.095 / 0.030), 0.7
0.059 / 0.032 (0.098 / 0.029), 0.8 0.055 / 0.028 (0.102 / 0.028; kept), 0.95 0.075 / 0.040,
0.98 0.089 / 0.054 (too slow to leave the hold); dwelling on the hold's middle and last states
only, 0.8: 0.073 / 0.032 (0.094 / 0.031). The held-out worst was a lift at 0.3x hold whose size
was overestimated during the raise (1.06 for 0.89): the follower stayed short of the hold until
the return began (a straight line's size and progress are one); :mod:`behaviors.mop.holding`
now takes a performer resting just short of a hold as holding it, at the size that puts them
there, and shows where the hold ends (0.102 -> 0.048).

Transitions (:class:`Transitions`) go left to right: self (offset 0), next (+1) and skips
(+2, +3, ...) so a performer may be up to about twice as fast as the recording, a small backward
transition (-1) so they can go back, and a small restart probability (back to the first state)
so a new performance of the action is picked up after the last one ended.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Mapping

import numpy as np

from behaviors.mop.features import fit_scale
from tabletop.frames import InputError


class TemplateError(InputError):
    """A template set cannot be used: too few samples, mismatched columns, non-finite values."""


@dataclass(frozen=True)
class Transitions:
    """Left-to-right transition weights, per step (normalised to sum to 1 when used).

    ``forward[o]`` is the weight of moving ``o`` states ahead (``forward[0]`` self, ``forward[1]``
    next, higher offsets skips); ``backward`` the weight of moving one state back; ``restart`` the
    probability per step of a new performance starting at the first state; ``dwell`` the share
    of a hold state's probability that stays there each step before the rest moves by the
    transitions (:func:`dwell_states`). MOP's own model is
    ``Transitions(forward=(0.5, 0.5), backward=0.0, restart=0.0)``.

    What the extra transitions cost (``bench/mop.py``, 8 templates of 200 samples, progress RMSE
    on the 0..1 scale): run time, nothing measurable, since the transitions are one small matrix
    product whatever their number (20 templates: ~0.35-0.38 ms per step for all three models on
    a loaded 2-core machine). Accuracy: self/next only gives 0.026 on performances warped
    between 0.5x and 2x and 0.080 at a steady 2x (it falls behind); with skips to +3 it gives
    0.010 and 0.018; adding the backward weight 0.1 keeps 0.010 and 0.020 and improves going
    back and forth with a pause from 0.060 to 0.043. Backward weights of 0.02-0.2 trade
    following backwards (better when larger) against fast forward following (worse when larger).

    Measured and not kept: the performer's tempo kept where the observations do not tell the
    states apart. Per template a tempo (states per sample) followed the progress's advance
    (0.3 of the way a sample, weighed by how much the emissions of the states reachable from
    the mean, -1 to +3, differ); where they lay within 1 nat of each other the weights moved
    ahead to that tempo (mixed with themselves shifted one state, so their spread stays; never
    slower than the prior's 0.95). A stroke eased over its last 30% (0.4% of its length, under
    the noise), performed at 1.5 states per sample, was followed at 0.98 instead of 0.91 at its
    last sample, and among twenty templates back to back (seeds 201-210 of
    ``bench.follow_quality.evaluate``) no ended action drove more than two ticks into the next
    gesture (ended runs per seed 2,3,4,4,3,4,2,3,2,2 -> at most 2), once the grace counted from the
    end reached (not from where the input stood still, ``spotting._arrived``, which made the
    gestures now reached on time lose their last ticks: valid after 30% at 0.7-1.4x 0.9147 ->
    0.9089). But the end reached a sample earlier put the next gesture's anchor short of its
    start where the last sample was fast (a dance wrist's, 1 cm), and a walk ankle drove the
    next one's start: longest wrong run per seed -> 2,2,3,4,5,2,4,2,2,4 (anchored at the sample
    nearest the ended template's last point since the end, follower only: 3,3,3,4,2,2,2,2,2,3,
    the rest a roll ankle's late start). ``bench/follow_quality.py`` (tuned): valid after 30%
    0.9147 -> 0.9167, progress RMSE median / p90 0.0190 / 0.0405 -> 0.0186 / 0.0396, holds
    valid 0.958 -> 0.962, unrelated strokes after a gesture 0.0730 -> 0.0668; but holds' RMSE
    median 0.0318 -> 0.0320, gestures at 0.6 and 1.5x recognised by their end 0.975 -> 0.95,
    unrelated motions 0.01544 -> 0.01550, pauses driven through 0.928 -> 0.926 (drift p90 0.0835
    -> 0.0842): a performer who pauses or slows in an eased stretch is carried on at the
    pace they had (a kick ankle at 1.4x slowing from 1.5 to 0.9 states per sample over its end).
    The weights replaced by a step of the tempo's two nearest offsets (share 0.8): RMSE p90
    0.046, valid after 30% 0.9086 (a slow tempo measured before a spin ankle's pause kept the
    window from following it on: lost); that step never slower than the prior: p90 0.050;
    flat within 0.5 nat: the six gestures' ended runs 2 -> 3. Kept only past 0.8 of a
    template, with that anchor and grace (follower only): pauses and unrelated motions as
    before, but twenty templates back to back (seed 13) longest wrong run 2 -> 5, median
    recognition 0.298 -> 0.329. Nothing in a flat stretch tells a performer slowing into an
    eased end from one going on at their pace.
    """

    forward: tuple[float, ...] = (0.3, 0.35, 0.25, 0.1)
    backward: float = 0.1
    restart: float = 1e-4
    dwell: float = 0.0

    def __post_init__(self) -> None:
        w = np.asarray(self.forward, dtype=float)
        if w.ndim != 1 or w.size < 1 or not np.all(np.isfinite(w)) or np.any(w < 0):
            raise TemplateError("transition weights must be non-negative numbers, got "
                                f"{self.forward}")
        if not (np.isfinite(self.backward) and self.backward >= 0):
            raise TemplateError(f"backward transition must be >= 0, got {self.backward}")
        if w.sum() + self.backward <= 0:
            raise TemplateError("transition weights must not all be zero")
        if not (0.0 <= self.restart < 1.0):
            raise TemplateError(f"restart probability must be in [0, 1), got {self.restart}")
        if not (0.0 <= self.dwell < 1.0):
            raise TemplateError(f"hold dwell must be in [0, 1), got {self.dwell}")

    def weights(self) -> tuple[float, np.ndarray]:
        """(backward weight, forward weights) normalised so that all of them sum to 1."""
        w = np.asarray(self.forward, dtype=float)
        total = w.sum() + self.backward
        return self.backward / total, w / total


@dataclass(frozen=True)
class TemplateBank:
    """Every template of a set, standardised and stacked: ``means[starts[k] : starts[k] +
    lengths[k]]`` are the states of template ``names[k]``. ``center`` and ``scale`` (K, d) map a raw
    sample x to ``(x - center[k]) / scale[k]`` for template k; ``first`` (K, d) is each template's
    first sample (raw units); ``source`` (one per state) the progress (0..1) in the recorded
    template of each state (holds are compressed); ``units`` (d,) the columns' units; ``holds`` (one
    per state) True for the states of a compressed hold."""

    names: tuple[str, ...]
    means: np.ndarray
    starts: np.ndarray
    lengths: np.ndarray
    center: np.ndarray
    scale: np.ndarray
    first: np.ndarray | None = None
    source: np.ndarray | None = None
    units: np.ndarray | None = None
    holds: np.ndarray | None = None

    @property
    def dim(self) -> int:
        return int(self.means.shape[1])

    def template(self, k: int) -> np.ndarray:
        """Standardised states of template ``k`` (n_k, d)."""
        s = int(self.starts[k])
        return self.means[s:s + int(self.lengths[k])]


def check_templates(templates: Mapping[str, np.ndarray]) -> dict[str, np.ndarray]:
    """Validate a template set and return it as float arrays ``(n_i, d)``; raises TemplateError."""
    if not templates:
        raise TemplateError("no templates given: at least one action template is needed")
    out: dict[str, np.ndarray] = {}
    dim: int | None = None
    first = ""
    for name, data in templates.items():
        if not isinstance(name, str) or not name:
            raise TemplateError(f"template names must be non-empty strings, got {name!r}")
        try:
            a = np.asarray(data, dtype=float)
        except (TypeError, ValueError) as exc:
            raise TemplateError(f"template {name!r}: not a numeric array ({exc})") from None
        if a.ndim == 1:
            a = a[:, None]
        if a.ndim != 2:
            raise TemplateError(f"template {name!r}: expected samples x features, got shape "
                                f"{a.shape}")
        if a.shape[0] < 2:
            raise TemplateError(
                f"template {name!r}: has {a.shape[0]} sample(s), needs at least 2 to follow "
                "progress")
        if a.shape[1] < 1:
            raise TemplateError(f"template {name!r}: has no feature columns")
        bad = np.argwhere(~np.isfinite(a))
        if bad.size:
            i, j = (int(v) for v in bad[0])
            raise TemplateError(
                f"template {name!r}: sample {i}, feature {j} is {a[i, j]} (every value must be "
                "finite)")
        if dim is None:
            dim, first = a.shape[1], name
        elif a.shape[1] != dim:
            raise TemplateError(
                f"template {name!r}: has {a.shape[1]} feature columns but template {first!r} "
                f"has {dim}; every template of a set must have the same features")
        out[name] = a
    return out


def _vector(value, d: int, what: str, positive: bool = False) -> np.ndarray | None:
    if value is None:
        return None
    v = np.asarray(value, dtype=float)
    if v.shape != (d,) or not np.all(np.isfinite(v)) or np.any(v < 0) \
            or (positive and np.any(v <= 0)):
        kind = "positive" if positive else "non-negative"
        raise TemplateError(f"{what} must be {d} {kind} numbers (one per feature), "
                            f"got {np.asarray(value).tolist()}")
    return v


def compress_holds(states: np.ndarray, tolerance: float) -> tuple[np.ndarray, np.ndarray]:
    """Indices of the samples kept from ``states`` (n, d, standardised), and which of them hold:
    a run of more than three samples within ``tolerance`` (RMS per column) of its first sample
    keeps its first, middle and last samples only."""
    n = states.shape[0]
    keep: dict[int, bool] = {}
    i = 0
    while i < n:
        j = i + 1
        while j < n and np.sqrt(np.mean((states[j] - states[i]) ** 2)) <= tolerance:
            j += 1
        if j - i > 3:
            keep.update({i: True, (i + j - 1) // 2: True, j - 1: True})
        else:
            keep.update({m: keep.get(m, False) for m in range(i, j)})
        i = j
    idx = np.asarray(sorted(keep), dtype=np.intp)
    return idx, np.array([keep[int(m)] for m in idx], dtype=bool)


def build_bank(templates: Mapping[str, np.ndarray], relative_floor: float = 0.05,
               min_scale: np.ndarray | None = None, units: np.ndarray | None = None,
               hold_tolerance: float = 0.02, column_floor: float = 0.5) -> TemplateBank:
    """Validate, standardise (each template by its own spread, see the module docstring) and
    stack a template set, its holds compressed. ``relative_floor`` floors the pooled units when
    they are not given; ``min_scale`` (d,) floors every template's scale (the input's noise);
    ``column_floor`` floors each column's spread at that fraction of the template's RMS spread
    (a line drawn along x still tolerates some y)."""
    checked = check_templates(templates)
    arrays = list(checked.values())
    d = arrays[0].shape[1]
    ms = _vector(min_scale, d, "min_scale")
    given = _vector(units, d, "units", positive=True)
    if given is None:
        given = fit_scale(arrays, relative_floor)[1]
    centers, scales, firsts, means, sources, lengths, holds = [], [], [], [], [], [], []
    for a in arrays:
        center = a.mean(axis=0)
        spread = (a - center).std(axis=0) / given
        rho = math.sqrt(float(np.mean(spread ** 2)))
        scale = given * (np.maximum(spread, column_floor * rho) if rho > 1e-12 else 1.0)
        if ms is not None:
            scale = np.maximum(scale, ms)
        z = (a - center) / scale
        keep, held = (compress_holds(z, hold_tolerance) if hold_tolerance > 0
                      else (np.arange(len(a)), np.zeros(len(a), dtype=bool)))
        if len(keep) < 2:
            keep, held = np.array([0, len(a) - 1]), np.ones(2, dtype=bool)
        centers.append(center)
        scales.append(scale)
        firsts.append(a[0])
        means.append(z[keep])
        sources.append(keep / (len(a) - 1.0))
        lengths.append(len(keep))
        holds.append(held)
    lengths_a = np.array(lengths, dtype=np.intp)
    starts = np.concatenate([[0], np.cumsum(lengths_a)[:-1]]).astype(np.intp)
    return TemplateBank(tuple(checked), np.ascontiguousarray(np.concatenate(means)), starts,
                        lengths_a, np.array(centers), np.array(scales), np.array(firsts),
                        np.concatenate(sources), given, np.concatenate(holds))


#: A hold state's share of probability that stays each step, for followers of spatial inputs
#: (size and offset invariance). With features as recorded a hold performed at another size is
#: never reached, and dwelling in it trapped the progress (the ``follow`` command's defaults,
#: a lift at 0.82x: RMSE 0.12 -> 0.32, 0.17 backward).
HOLD_DWELL = 0.8


def dwell_states(bank: TemplateBank, dwell: float, margin: float = 0.1) -> np.ndarray:
    """Per state of ``bank``, the share of its probability that stays each step (``dwell`` at
    the states of a hold inside a template, 0 elsewhere). A compressed hold is crossed in three
    steps; a performer holding longer, or slowing into the hold, kept the prior's drift of about
    a state per step going past it into the eased start of the return, which matches a held
    input as well. A still start or end (a hold within the first or last ``margin`` of the
    template's progress) is no such hold: the start is where every performance waits, the end
    must be reached for the gesture to end (the circle's eased end is a hold at 91-95%)."""
    out = np.zeros(len(bank.means))
    if dwell <= 0:
        return out
    for a, b in inner_holds(bank, margin):
        out[a:b] = dwell
    return out


def inner_holds(bank: TemplateBank, margin: float = 0.1) -> list[tuple[int, int]]:
    """The compressed holds inside the templates of ``bank``, as (first, past the last) state
    indices: not within the first or last ``margin`` of a template's progress."""
    out: list[tuple[int, int]] = []
    if bank.holds is None or bank.source is None:
        return out
    for s, n in zip(bank.starts, bank.lengths):
        h = bank.holds[s:s + n].astype(int)
        src = bank.source[s:s + n]
        edges = np.flatnonzero(np.diff(np.concatenate([[0], h, [0]])))
        for a, b in zip(edges[::2], edges[1::2]):
            if src[a] >= margin and src[b - 1] <= 1.0 - margin:
                out.append((int(s + a), int(s + b)))
    return out
