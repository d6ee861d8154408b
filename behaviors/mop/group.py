"""Several followers stepped as one (one per performer), in one vectorised forward pass."""

from __future__ import annotations

from typing import Sequence

import numpy as np

from behaviors.mop.follower import ActionFollower, FollowState, SampleError
from behaviors.mop.forward import WindowedForward
from behaviors.mop.hmm import TemplateBank, TemplateError


class FollowerGroup:
    """Several followers (one per performer or character, each with its own templates and
    input) stepped together in one vectorised forward pass: one tick of many characters costs
    about as much as one follower over all their templates. The followers must share their
    parameters; their feature counts may differ. Each keeps its own state (``step`` of the
    group and of a member must not be mixed).
    """

    def __init__(self, followers: Sequence[ActionFollower]) -> None:
        self.followers = list(followers)
        if not self.followers:
            raise TemplateError("a follower group needs at least one follower")
        first = self.followers[0]
        for i, f in enumerate(self.followers[1:], 1):
            if not first.same_parameters(f):
                raise TemplateError(f"follower {i} of the group has other parameters than follower 0; "
                                    "a group's followers must share sigma, window, transitions and limits")
        width = max(f._zdim for f in self.followers)
        means, starts, lengths, dims, names, owner = [], [], [], [], [], []
        offset = 0
        for i, f in enumerate(self.followers):
            b = f._fbank
            padded = np.zeros((b.means.shape[0], width))
            padded[:, :b.dim] = b.means
            means.append(padded)
            starts.append(b.starts + offset)
            offset += b.means.shape[0]
            lengths.append(b.lengths)
            dims += [f._zdim] * len(b.names)
            names += [f"{i}:{n}" for n in b.names]
            owner += [i] * len(b.names)
        bank = TemplateBank(tuple(names), np.concatenate(means), np.concatenate(starts),
                            np.concatenate(lengths), np.zeros(width), np.ones(width))
        p = first._params
        self.forward = WindowedForward(bank, sigma=p["sigma"], half_window=p["window"],
                                       transitions=first.forward.transitions, floor=p["floor"],
                                       dims=np.array(dims))
        self._owner = np.array(owner, dtype=np.intp)
        bounds = np.concatenate([[0], np.cumsum([len(f.names) for f in self.followers])])
        self._slices = [slice(int(a), int(b)) for a, b in zip(bounds[:-1], bounds[1:])]
        self._z = np.zeros((len(owner), width))
        self.reset()

    def reset(self) -> None:
        """Forget every performance."""
        self.forward.reset()
        for f in self.followers:
            f.reset()

    def reset_member(self, i: int) -> None:
        """Forget the performance followed by member ``i`` only (its next performance starts
        afresh: every template at its first state, no evidence); the others go on."""
        sl = self._slices[i]
        self.forward.reset_templates(np.arange(sl.start, sl.stop))
        f = self.followers[i]
        entries = self.forward.entries[sl].copy()
        f.reset()
        f._entries[:] = entries

    def step(self, samples: Sequence[np.ndarray]) -> list[FollowState]:
        """One sample per follower, in order; returns each follower's state."""
        if len(samples) != len(self.followers):
            raise SampleError(f"{len(samples)} samples for a group of {len(self.followers)} followers")
        lost = []
        samples_ok: dict[int, np.ndarray] = {}
        for i, (f, x) in enumerate(zip(self.followers, samples)):
            x = f._sample(x)
            if x is None:
                lost.append(i)
            else:
                sl = self._slices[i]
                self._z[sl, :f._zdim] = f._inputs(x)
                samples_ok[i] = x
        fw = self.forward
        saved = None
        if lost:
            saved = fw.snapshot(np.flatnonzero(np.isin(self._owner, lost)))
        step_ll = fw.step(self._z)
        if saved is not None:
            fw.restore(saved)
        out = []
        for i, (f, sl) in enumerate(zip(self.followers, self._slices)):
            if i in lost:
                out.append(f._held())
            else:
                out.append(f._finish(step_ll[sl], fw, sl.start, fw.entries[sl], samples_ok[i]))
        return out
