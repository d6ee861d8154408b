"""Can the follower tell a designer's take from the actions its performer already drives?

A take is replayed, sample by sample, through a fresh follower built as the stage builds its
performer's (the same templates, the take's among them, units, floor and window; the live one
is left alone); the replay is the take performed exactly as recorded, the best case it will
ever get. Two figures come out: the share of its samples on which the take is followed validly
as itself, and the mean probability each other template takes meanwhile. A take followed validly
on less than :data:`MIN_OWN` of its own recording, and on at least that once the template that
took most of the probability is left out (a second replay), is *too like* that one: the
follower splits between them and judges no tick valid, so the take does not drive when tried.

Measured with ``bench/take_likeness.py`` (each example gesture re-recorded through the studio,
plainly and at 0.85x with 0.5 mm of noise, beside each as the face's one known action; both
replays take at most 65 ms): a gesture re-recorded beside itself is followed validly on 0.00 of
its recording in 10 of 12 takes (the known one takes 0.13-0.55 of the probability; alone the
take is followed on 0.72-0.76), and those 10 are named; the other two, zigzags, are followed on
0.42 and 0.53 and drive. Beside any other gesture a take is followed on 0.46-0.76 and none of
the 60 is named. A share threshold on the probability alone was rejected: a wave re-recorded
slowly does not drive while its twin takes only 0.18, and a line beside a square takes 0.32
and drives.
"""

from __future__ import annotations

from typing import Callable, Mapping

import numpy as np

#: Below this share of its own recording followed validly as itself, a take does not drive.
MIN_OWN = 0.3


def likeness(make_follower: Callable[..., object], templates: Mapping[str, np.ndarray],
             take_key: str, **build: object) -> tuple[float, dict[str, float]]:
    """Replay ``templates[take_key]`` through ``make_follower(templates, **build)``: (the
    share of its samples followed validly as ``take_key``, the mean probability each other
    template took)."""
    follower = make_follower(dict(templates), **build)
    samples = np.asarray(templates[take_key], dtype=float)
    own, shares = 0, {k: 0.0 for k in templates if k != take_key}
    for x in samples:
        state = follower.step(x)  # type: ignore[attr-defined]
        own += bool(state.valid and state.best == take_key)
        for k in shares:
            shares[k] += float(state.probabilities[k])
    n = max(1, len(samples))
    return own / n, {k: v / n for k, v in shares.items()}


def too_like(make_follower: Callable[..., object], templates: Mapping[str, np.ndarray],
             take_key: str, **build: object) -> str | None:
    """The template ``take_key`` is too like: the take hardly drives on its own replay, and
    does once the template that took most of the probability is left out; else None."""
    own, shares = likeness(make_follower, templates, take_key, **build)
    if own >= MIN_OWN or not shares:
        return None
    like = max(shares, key=lambda k: shares[k])
    rest = {k: v for k, v in templates.items() if k != like}
    return like if likeness(make_follower, rest, take_key, **build)[0] >= MIN_OWN else None
