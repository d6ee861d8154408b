"""Followers of different parameters stepped as groups: one
:class:`~behaviors.mop.group.FollowerGroup` per parameter set (a character whose window the
designer changed in the studio follows with its own; the group needs its followers to share
them)."""

from __future__ import annotations

from typing import Callable, Sequence

import numpy as np

from behaviors.mop.follower import ActionFollower, FollowState


class GroupsByParameters:
    """``step`` and ``reset_member`` of one group over ``followers`` (in their order), each
    parameter set stepped by its own ``make_group``."""

    def __init__(self, followers: Sequence[ActionFollower],
                 make_group: Callable[[list], object]) -> None:
        parts: list[list[int]] = []
        for i, f in enumerate(followers):
            part = next((p for p in parts if followers[p[0]].same_parameters(f)), None)
            if part is None:
                parts.append([i])
            else:
                part.append(i)
        self._parts = parts
        self._groups = [make_group([followers[i] for i in p]) for p in parts]
        #: follower i -> (its group, its place in that group)
        self._where = {i: (g, k) for g, p in enumerate(parts) for k, i in enumerate(p)}

    def reset_member(self, i: int) -> None:
        g, k = self._where[i]
        self._groups[g].reset_member(k)  # type: ignore[attr-defined]

    def step(self, samples: Sequence[np.ndarray]) -> list[FollowState]:
        out: list[FollowState | None] = [None] * len(samples)
        for part, group in zip(self._parts, self._groups):
            states = group.step([samples[i] for i in part])  # type: ignore[attr-defined]
            for i, state in zip(part, states):
                out[i] = state
        return out  # type: ignore[return-value]


def grouped(make_group: Callable[[list], object]) -> Callable[[list], object]:
    """``make_group`` itself when the followers share their parameters, else one per set."""
    def make(followers: list) -> object:
        if all(followers[0].same_parameters(f) for f in followers[1:]):
            return make_group(followers)
        return GroupsByParameters(followers, make_group)
    return make
