"""An action paused part way through, resumed when its performer goes on.

A rest (the puck still for the input's ``rest_time``) ends a gesture: its follower starts afresh
and nothing drives the resting puck. A performer who pauses part way through an action and then
goes on with it would lose it (the fresh gesture starts at the pause, half way through the
action: a circle paused 1-3 s at half way drove 0% of its second half). So the action that drove
when the puck stood still is kept, with the gesture's samples up to there and its origin, as a
hypothesis: while the puck stands and rests, a spare follower replays those samples (a few per
sample, so no tick pays for the whole gesture); when the puck moves again it follows the samples
read against the kept origin beside the fresh gesture. Its state drives only while the
follower keeps it valid by its own rules from the first samples after the rest on, once its
progress has moved on past where the follower had it when the puck stopped (:data:`ADVANCE`),
and while it out-weighs the fresh one (a higher log-likelihood when both are valid). It is
dropped as soon as it is invalid, when the fresh gesture out-weighs it, or when the rest lasted
longer than :data:`PAUSE_S`. Replayed only once the rest began, a pause just over the rest time
left most of the gesture to catch up after it (driven 0.27-0.75 of the second half, a wrong
action 0.39 of a figure eight's); replayed all at once, one tick would follow the whole
gesture (a hundred samples and more).

Measured on the example installation (``tests/mop/test_resume.py``): circles, zigzags, figure
eights and lines paused 1-3 s at 30-70% drive 0.70-0.96 of their second half by their action
(0-0.16 without); a different gesture after such a pause is driven by a wrong action 0% of it.
A finger rests when it lifts: the gesture resumes read against the first touch's origin
(:attr:`behaviors.mop.inputs.TouchInput.origin`) when a finger comes down where it lifted and
draws on; the same gestures lifted at 30-70% for 1-3 s drive 0.86-0.97 of their second half
(0-0.24 read from the new touch's origin).
Tried before: keeping the gesture's origin through rests of up to 3 s while an action drives
(85-100% of the second half), not kept: it drove through the rest too (the bird alone in
``tests/mop/test_live.py``: 46 ticks driven by a resting puck, 0 allowed).
"""

from __future__ import annotations

import copy
from collections import deque
from typing import Any

import numpy as np

#: Longest rest (seconds) after which a paused action may still be resumed.
PAUSE_S = 3.0
#: Seconds before the rest began within which the action must have driven to be kept: the
#: input's rest time (0.8 s) of stillness and a little (a follower stops an action that stands
#: still part way through, after 8 samples for a circle stopped at 30%).
SETTLE_S = 1.0
#: Progress (share of the action) the resumed action must have moved on from where it was
#: kept before it drives: a different gesture after the pause holds it where it was until the
#: follower refuses it (8-14 samples), a continuation moves it on at once.
ADVANCE = 0.02
#: Seconds the puck stands still while an action drives before its samples are kept and
#: replayed (a pause may follow), ahead of the rest (the input's rest time, 0.8 s).
STAND_S = 0.2
#: Seconds a copy of the spare follower stands on the last kept sample of a gesture whose rest
#: began while it moved (a finger lifted mid-stroke), as long as a puck stands before its rest:
#: the furthest it takes the action is where the action stopped (:meth:`Resume.keep`).
SETTLE_PROBE_S = 0.8
#: Progress from which an action has finished: a rest there ends it (nothing to resume).
FINISHED = 0.95
#: Longest gesture (seconds) kept for resuming; a longer one keeps its last samples only.
GESTURE_S = 20.0
#: Samples of the kept gesture replayed per sample of the rest.
REPLAY_PER_SAMPLE = 3
#: Replay steps all of an engine's performers share per sample, a step of a follower of more
#: than 20 templates counting one for every 20 (:func:`replay_cost`): a spare follower's step
#: costs 0.13-0.25 ms with 1-80 templates of 6 features, 0.65 ms with 80 of 60 (bench/mop.py),
#: so eight performers pausing at once replayed up to 24 steps a sample, 3-15 ms, where the
#: engine's tick has 1 ms (DESIGN). Shared, a tick's catch-up replays take about 1 ms at most
#: (beside them each performer going on with a kept action follows its live sample, as a second
#: follower); one performer pausing alone replays at full pace, and the turn goes round them.
#: Stepped alone, examples/mop.yaml's spare (5-6 templates, size invariance) took 0.7-1.8 ms
#: of thread CPU a step on a loaded 2-core machine, a replaying tick 4.1-4.9 ms median; in the
#: engine's compiled pass (:class:`GroupSpare`) 0.13 ms, the tick 1.4 ms (0.7-0.8 ms the
#: others). Fewer steps lose short pauses: 1 a sample, a zigzag paused 1 s at 70% drove 0.18
#: of its second half (0.79 at 3), a lifted one 0 (0.91); 2 a sample, the lifted one 0.85.
REPLAY_BUDGET = 6


def replay_cost(templates: int) -> int:
    """What one replay step of a follower of ``templates`` templates counts against
    :data:`REPLAY_BUDGET`."""
    return max(1, -(-templates // 20))


def share_replay(templates: list[int], turn: int) -> list[int]:
    """Replay steps this sample for each waiting performer, whose followers have
    ``templates`` templates: :data:`REPLAY_PER_SAMPLE` each while :data:`REPLAY_BUDGET` lasts,
    served from the ``turn``-th (mod their number) on, so the turn goes round them; the one
    whose turn it is replays at least one step, however large its follower. (A performer
    moving on follows its live sample besides: :meth:`Resume.follow`.)"""
    steps, budget, k = [0] * len(templates), REPLAY_BUDGET, len(templates)
    for j in range(k):
        i = (turn + j) % k
        cost = replay_cost(templates[i])
        steps[i] = min(REPLAY_PER_SAMPLE, max(budget // cost, int(j == 0)))
        budget -= steps[i] * cost
    return steps


class GroupSpare:
    """A spare follower stepped as the only member of a follower group (the engine's compiled
    pass): its states equal the follower's own (80 of 80 samples of examples/mop.yaml's), a
    step 0.15 ms of thread CPU against 1.06 ms stepped alone (ActionFollower.step's rules in
    Python), so a replaying tick's 3 steps fit the engine's 1 ms."""

    def __init__(self, group: Any) -> None:
        self.group = group

    def step(self, x: np.ndarray) -> object:
        """One sample ``x``: the follower's state after it."""
        return self.group.step([x])[0]

    def reset(self) -> None:
        """Start afresh."""
        self.group.reset_member(0)


class Resume:
    """One performer's paused action (see the module docstring). ``rate_hz``: samples per
    second of the engine; ``make_group`` (optional): the engine's follower group maker, to
    step the spare in (:class:`GroupSpare`)."""

    def __init__(self, rate_hz: float, make_group: Any = None) -> None:
        self._make_group = make_group
        self._pause = int(round(PAUSE_S * rate_hz))
        self._most = int(round(GESTURE_S * rate_hz))
        self._settle = int(round(SETTLE_S * rate_hz))
        self._probe_n = int(round(SETTLE_PROBE_S * rate_hz))
        # the settle probe (:meth:`_probe_step`), while it runs: its copy of the spare follower
        # (None until its first step), the last kept sample it stands on, its steps left
        self._probe: tuple[object | None, np.ndarray, int] | None = None
        self.stand_samples = int(round(STAND_S * rate_hz))
        self._drove = 0   # how many of the fresh gesture's samples had been seen when it drove
        self._at: list[tuple[str, float]] = []   # its follower's action and progress at each
        self._stopped = ("", 0.0)   # the kept action's and its progress where the puck stopped
        self.samples: list[np.ndarray] = []   # the fresh gesture's samples since it began
        self._mine: list[np.ndarray] = []     # the resumed one's, read against its origin
        self.follower: object | None = None   # the spare follower
        self._source: object | None = None    # the follower it was copied from
        self.kept: np.ndarray | None = None    # the kept origin, while an action is kept
        self._todo: deque[np.ndarray] = deque()   # samples the spare has not followed yet
        self._left = 0   # of which kept ones (before the rest)
        self._cut = 0   # how many of the fresh gesture's samples were kept
        self.preparing = False   # kept while the puck stands, before the rest began
        self._rested = 0
        self.state: object | None = None      # the resumed follower's state, while followed
        self._from: tuple[str, float] | None = None   # the kept action and its progress

    def drop(self) -> None:
        """Forget the kept action."""
        self.kept, self._todo, self.state, self._mine = None, deque(), None, []
        self.preparing, self._probe = False, None
        self._from = None

    def add(self, x: np.ndarray, resting: bool, state: object) -> None:
        """The gesture's sample ``x`` (read against the fresh origin) and the fresh follower's
        ``state`` after it; ``resting``: the follower was reset at it (the gesture starts again
        here)."""
        if resting:
            self.samples, self._at, self._drove = [], [], 0
        self.samples.append(x)
        self._at.append((state.best, float(state.progress)))  # type: ignore[attr-defined]
        if bool(state.valid) and not resting:  # type: ignore[attr-defined]
            self._drove = len(self.samples)
        if len(self.samples) > self._most:
            del self.samples[0], self._at[0]
            self._drove -= 1

    @property
    def drives(self) -> bool:
        """The fresh gesture drove an action not yet finished at its last sample."""
        return self._drove == len(self.samples) and self.drove_lately

    @property
    def drove_lately(self) -> bool:
        """The fresh gesture drove an action not yet finished (:data:`FINISHED`) within
        :data:`SETTLE_S` of its last sample."""
        return (self._drove > 0 and len(self.samples) - self._drove <= self._settle
                and self._at[self._drove - 1][1] < FINISHED)

    def keep(self, follower: object, origin: np.ndarray, still: int) -> None:
        """The rest began while the fresh gesture (read against ``origin``) drove lately
        (:attr:`drove_lately`): keep it up to the last sample it drove at or the last one
        before the puck stood ``still`` (samples, the rest's included), the earlier: the
        stillness is the pause's, not the action's (kept, a follower refused a line resumed
        after 46 still samples at once). A rest begun as the input moved (``still`` 1: a finger
        lifted mid-stroke) has no standing to tell where the action stopped: a copy of the
        spare stands on the last kept sample instead (:meth:`_probe_step`; the follower's
        progress lags a moving input: without it a circle begun where a line was lifted at
        0.49 took the resumed line on to 0.53, and it drove 15-20% of the circle; kept as
        still samples in the replay, the stillness made a circle or zigzag lifted at 30%
        invalid: 0-5% of their second half driven)."""
        if self._source is not follower:   # a rebuilt follower: a new spare
            spare = copy.deepcopy(follower)
            make = self._make_group
            self._source = follower
            self.follower = spare if make is None else GroupSpare(make([spare]))
        cut = min(self._drove, len(self.samples) - max(0, still - 2))
        self.kept, self._mine = origin.copy(), self.samples[:max(cut, 0)]
        self._cut, self.preparing = cut, False
        self._settle_stop()
        self._requeue(still)

    def _requeue(self, still: int) -> None:
        """The spare follower starts afresh on the kept samples, all of them to replay, then
        the settle probe when the input moved up to the rest (``still`` 1)."""
        self.follower.reset()  # type: ignore[attr-defined]
        self._todo, self._rested, self.state, self._from = deque(self._mine), 0, None, None
        self._left = len(self._mine)
        probe = still <= 1 and bool(self._mine) and self._probe_n > 0
        self._probe = (None, self._mine[-1], self._probe_n) if probe else None

    def _settle_stop(self) -> None:
        """Where the action was when the puck stopped: the furthest the fresh follower took it
        while the puck stood still before the rest (a line's crept from 0.48 to 0.55; measured
        from 0.48, a different gesture after the pause took the resumed line as far, and it
        drove 6-13% of that gesture)."""
        cut = self._cut
        best = self._at[cut - 1][0] if 0 < cut <= len(self._at) else ""
        self._stopped = (best, max((p for b, p in self._at[max(cut - 1, 0):self._drove]
                                    if b == best), default=1.0))

    def prepare(self, follower: object, origin: np.ndarray, still: int) -> None:
        """The puck has stood ``still`` (samples) while the fresh gesture drove: keep it as
        :meth:`keep` does before the rest begins, so its samples are replayed while it stands
        (:meth:`stand`); :meth:`settled` when the rest begins, :meth:`drop` if it moves on."""
        self.keep(follower, origin, still)
        self.preparing = True

    def stand(self, n: int = REPLAY_PER_SAMPLE) -> None:
        """One more still sample before the rest: replay up to ``n`` kept samples."""
        self._replay(n)

    def settled(self) -> None:
        """The rest began after :meth:`prepare`: where the follower had the action when the
        puck stopped is known now (it may creep on while the puck stands)."""
        self.preparing = False
        self._settle_stop()
        self._rested = 0

    def keep_resumed(self, still: int) -> None:
        """The rest began while the resumed action drove: keep it again, as it was before the
        puck stood ``still`` (samples, the rest's included)."""
        s = self.state
        self._stopped = (s.best, float(s.progress))  # type: ignore[attr-defined]
        del self._mine[max(0, len(self._mine) - max(0, still - 2)):]
        self._requeue(still)

    def rest(self, n: int = REPLAY_PER_SAMPLE) -> None:
        """One sample of the rest: replay up to ``n`` kept samples; drop beyond
        :data:`PAUSE_S`."""
        if self.kept is None:
            return
        self._rested += 1
        if self._rested > self._pause:
            self.drop()
            return
        self._replay(n)

    @property
    def replaying(self) -> bool:
        """An action is kept: its spare follower steps (replays while the puck rests or
        stands, follows the live samples when it moves on)."""
        return self.kept is not None

    def _replay(self, n: int) -> bool:
        """Step the spare follower on up to ``n`` queued samples, the kept ones first; False
        when the resumed action was dropped (invalid, or another action, after the rest)."""
        follower = self.follower
        while n > 0 and (self._todo or (self._left == 0 and self._probe is not None)):
            if self._left == 0 and self._probe is not None:   # the kept samples followed
                self._probe_step()
                n -= 1
                continue
            if self._left == 0 and self._from is None:   # where the puck stopped along it
                s: Any = self.state
                same = s is not None and s.best == self._stopped[0]
                self._from = (s.best, max(s.progress, self._stopped[1])) if same else ("", 1.0)
            state: Any = follower.step(self._todo.popleft())  # type: ignore[union-attr]
            self.state = state
            n -= 1
            if self._left > 0:
                self._left -= 1
            elif not bool(state.valid) or state.best != self._from[0]:  # type: ignore[index]
                self.drop()
                return False
        return True

    def _probe_step(self) -> None:
        """One step of the settle probe (:meth:`keep`): a copy of the spare, which has followed
        the kept samples, stands on the last of them; the furthest it takes the kept action
        while valid is where the action stopped."""
        f, last, left = self._probe  # type: ignore[misc]
        f = copy.deepcopy(self.follower) if f is None else f
        s: Any = f.step(last)  # type: ignore[attr-defined]
        if bool(s.valid) and s.best == self._stopped[0]:
            self._stopped = (s.best, max(self._stopped[1], float(s.progress)))
            self._probe = (f, last, left - 1) if left > 1 else None
        else:
            self._probe = None

    def follow(self, x: np.ndarray, origin: np.ndarray,
               n: int = REPLAY_PER_SAMPLE) -> object | None:
        """The moving puck's sample ``x`` read against the fresh ``origin``: the resumed
        follower's state while it drives, else None. The follower steps on at most ``n``
        samples per sample (the kept ones not replayed during the rest first): it drives once
        it has caught up."""
        if self.kept is None:
            return None
        x = x + (origin - self.kept)
        self._mine.append(x)
        if len(self._mine) > self._most:
            del self._mine[0]
        self._todo.append(x)
        if len(self._todo) > self._most:   # it cannot catch up (the replay budget is spent)
            self.drop()
            return None
        if not self._replay(n + 1) or self._todo:   # the live sample, and n of the backlog
            return None
        state = self.state
        if state.progress < self._from[1] + ADVANCE:  # type: ignore[attr-defined,index]
            return None   # followed, not shown: it has not moved on yet
        return state
