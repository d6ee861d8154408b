"""Carried by its own driving: which rests an action may hold once its progress went forward
without it driving (follower and group alike).

:func:`~behaviors.mop.validity.stalls` lets an action hold a resting performer once its progress
passed where it began driving by :data:`~behaviors.mop.validity.CARRY_FIRST`, however that
progress came. It may come while the action did not drive: refused at an input's reversal, the
template is sized afresh there and its followed state leaps ahead, then taken again. The
held-out wander (seed 104, six templates, 1.0x): the zigzag taken at 0.169, driven to 0.207 (the
:data:`earned` carry 0.038), refused as the input reversed, sized 1.0 -> 0.56, leapt to 0.304,
taken again at 0.315 as the performer stopped, and held through the final rest (15 of its 23
valid ticks). Such an action holds a rest only where its template itself rests or slows
(:func:`slow_states`): a performer pausing mid-stroke of an action they performed carried it
forward by driving it; one stopping where the template slows (a turn, its end) may be where it
goes, however its progress came.
"""

from __future__ import annotations

import numpy as np

from behaviors.mop.validity import CARRY_FIRST

#: A template slows at a state whose step (the mean of its two, in units) is under this share of
#: the template's median step; a compressed hold rests.
SLOWS = 0.5


def slow_states(rel: np.ndarray, starts: np.ndarray, lengths: np.ndarray,
                holds: np.ndarray | None) -> np.ndarray:
    """Per state (``rel``: states from their template's first, units; ``holds``: compressed
    holds or None), 1.0 where its template rests or slows (:data:`SLOWS`), else 0.0."""
    out = np.zeros(len(rel))
    for s, n in zip(starts.tolist(), lengths.tolist()):
        if n < 2:
            out[s:s + n] = 1.0
            continue
        step = np.sqrt(np.sum(np.diff(rel[s:s + n], axis=0) ** 2, axis=1))
        around = np.concatenate([step[:1], 0.5 * (step[:-1] + step[1:]), step[-1:]])
        out[s:s + n] = around < SLOWS * float(np.median(step))
    if holds is not None:
        out[np.asarray(holds, dtype=bool)] = 1.0
    return out


def earned(carry: float, drove: bool, peak: float, progress: float) -> float:
    """The progress an action gained while it drove, after this sample: ``carry`` so far, plus
    how far ``progress`` passes its highest since it began driving, ``peak`` (before this
    sample), when it ``drove`` at the last sample as well."""
    return carry + max(0.0, progress - peak) if drove else carry


def unearned_rest(began: float, peak: float, carry: float, moved: bool, still: bool,
                  slows: bool) -> bool:
    """Whether a driving action holds a performer who stopped (``still``, having ``moved`` while
    it drove) on progress it did not gain by driving: its highest, ``peak``, passed ``began`` by
    :data:`~behaviors.mop.validity.CARRY_FIRST` but its :func:`earned` ``carry`` did not, and its
    template neither rests nor slows where it is followed (``slows``, :func:`slow_states`)."""
    return (still and moved and peak - began >= CARRY_FIRST and carry < CARRY_FIRST
            and not slows)
