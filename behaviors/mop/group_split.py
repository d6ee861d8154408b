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
        self._make = make_group
        self.followers = list(followers)
        self._parts: list[list[int]] = []
        self._groups: list[object] = []
        self._partition(list(range(len(self.followers))))

    def _partition(self, members: list[int]) -> None:
        """Group ``members`` (indices) by parameters, each set a new group beside the parts
        kept."""
        parts: list[list[int]] = []
        fs = self.followers
        for i in members:
            part = next((p for p in parts if fs[p[0]].same_parameters(fs[i])), None)
            if part is None:
                parts.append([i])
            else:
                part.append(i)
        self._parts += parts
        self._groups += [self._make([fs[i] for i in p]) for p in parts]
        #: follower i -> (its group, its place in that group)
        self._where = {i: (g, k) for g, p in enumerate(self._parts) for k, i in enumerate(p)}

    def replace(self, new: dict[int, ActionFollower]) -> set[int]:
        """Followers ``new`` (index -> follower) take those places; only the groups they leave
        or join are made again (a group starts its members afresh). Returns the members started
        afresh; the others' groups, and their progress, are kept."""
        for i, f in new.items():
            self.followers[i] = f
        fs = self.followers
        touched = [g for g, p in enumerate(self._parts)
                   if set(p) & set(new) or any(fs[p[0]].same_parameters(f) for f in new.values())]
        again = sorted(i for g in touched for i in self._parts[g])   # every new one among them
        self._parts = [p for g, p in enumerate(self._parts) if g not in touched]
        self._groups = [x for g, x in enumerate(self._groups) if g not in touched]
        self._partition(again)
        return set(again)

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
