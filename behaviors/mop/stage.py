"""The MOP engine: performers' features -> action followers -> characters, and designer takes.

Every tick, on the engine's own sampling grid
(``rate_hz``, resampled from frame times, at most ``max_catch_up`` samples per tick), every
performer's features are read once and fed to its follower: one
:class:`~behaviors.mop.follower.ActionFollower` per performer over the actions of every character
it performs (a template shared by several characters is followed once). Each character
(:class:`Puppet`) then plays the most probable valid action among its followers.

Rest: while a performer rests (:attr:`Performer.resting`: its puck has stayed where it settled
for ``rest_time``, its finger is lifted or
has stood still as long) its follower is reset at every sample and drives
nothing, unless its action is valid and held where its template holds (``FollowState.holding``:
a raise, hold, return whose hold outlasts the rest time): a puck at rest sits at the first sample of
every template (gestures start where the puck rested), and a gesture that ended where it began stays
matched at progress 1 for as long as the puck stays. Each gesture after a rest is thus followed from
a clean start, so what the puck did before (the slide back home, an unknown motion) cannot linger in
the evidence.

Why one follower per performer and not one per character: a character only knows its own
actions, so with a follower per character a gesture meant for another character (or any gesture,
for a character with a single action, like a bird that only waves) can only be refused by the
likelihood, and the probabilities compare the gesture only with that character's few actions.

Measured on ``examples/mop.yaml`` with its scripted performers (``tests/mop/test_live.py``, 120 s,
seed 0: 51 gestures, 40 s of rest beyond the first second of each rest, 20 slides home):

- followers per character, previous validity rule, no rest: 37 of 51 gestures recognised by 60%
  of them (the slide home and the 0.8 s before the rest moved the origin left log-likelihoods
  around -170 in the evidence, which took 1.5 s to forget, so the next gesture was invalid);
- followers per character with the refusing validity of :mod:`behaviors.mop.follower`, no rest:
  51 of 51, but characters driven during 1011 of the 2388 ticks of rest, and a character without
  the gesture performed driven 25% of the time;
- the same with the rest: rest 0 ticks, other characters driven 9.8% of the time;
- one follower per performer, with the rest (this engine): 51 of 51, progress RMSE 0.012 median
  (0.032 worst gesture), rest 0 ticks, slides home 0%, other characters driven 0.8% of the time
  (the first edge of a square is a line until it turns).

Designer takes (MOP 4.1.1): :class:`~behaviors.mop.takes.DesignerTakes`; the designer's keys and
control markers reach them through the studio's one state machine (:mod:`tabletop.studio`).
While a take records, its character is driven by none of its actions (from the take's first
tick it names none and eases to its rest pose, and its label says it records): the gesture being
recorded is the new action, and a known action playing along would show the designer a match
that the take is not. Other characters bound to the same performer still play their actions: the
take is one character's, and they show what the gesture already means to them.
"""

from __future__ import annotations

import logging
import math
from typing import Callable, Iterable, Mapping, Sequence

import numpy as np

from behaviors.motion.clips import Clip
from behaviors.mop.hints import HintGates, gate_onsets
from behaviors.mop.inputs import Performer
from behaviors.mop.puppetry import Action, Puppet, Vote
from behaviors.mop.resume import Resume, share_replay
from behaviors.mop.stage_parts import PartStates
from behaviors.mop.take import Take
from behaviors.mop.takes import DesignerTakes, SaveFn
from tabletop.frames import CharacterState, Frame
from behaviors.worker import Worker

#: (templates, the performer's feature units, their smallest spread worth telling apart) ->
#: a follower; units and min_scale None where unknown (a stream's columns)
FollowerFactory = Callable[[Mapping[str, np.ndarray], "np.ndarray | None", "np.ndarray | None"],
                           object]
log = logging.getLogger("tabletop")


class MopStage(DesignerTakes, PartStates):
    """Engine ``step(frame) -> characters``; see the module docstring.

    ``templates``: character -> action -> (performer name, samples (n x d) at ``rate_hz``);
    ``motions``: character -> motion names the designer may assign; ``load_motion(character,
    motion) -> Clip``; ``save(character, action, samples, feature names, motion) -> message``;
    ``taken(character)``: the names ``save`` holds already (a new take is named none of them);
    ``make_group(followers)`` (optional) steps all followers together, e.g.
    :class:`~behaviors.mop.group.FollowerGroup`; ``windows``: character -> the follower's window
    set in the studio (:meth:`set_window`); ``default_window``: the followers' window (states)
    where none is set (the config's ``follower.window``).
    """

    def __init__(self, name: str, rate_hz: float, performers: Mapping[str, Performer],
                 puppets: Sequence[Puppet],
                 templates: Mapping[str, Mapping[str, tuple[str, np.ndarray]]],
                 make_follower: FollowerFactory, motions: Mapping[str, Sequence[str]],
                 load_motion: Callable[[str, str], Clip], save: SaveFn | None = None,
                 character_performer: Mapping[str, str] | None = None,
                 max_catch_up: int = 4,
                 make_group: Callable[[list], object] | None = None,
                 taken: Callable[[str], Iterable[str]] | None = None,
                 windows: Mapping[str, int] | None = None, *, default_window: int) -> None:
        self.name = name
        self.rate_hz = float(rate_hz)
        self.performers = dict(performers)
        self.puppets = {p.name: p for p in puppets}
        self.order = [p.name for p in puppets]
        self.templates = {c: dict(templates.get(c, {})) for c in self.order}
        self.make_follower = make_follower
        self.motions = {c: tuple(motions.get(c, ())) for c in self.order}
        self.load_motion = load_motion
        self.save = save
        self.character_performer = dict(character_performer or {})
        self.max_catch_up = int(max_catch_up)
        self.make_group = make_group
        self.taken = taken or (lambda character: ())   # names ``save`` holds for a character
        self._group: object | None = None
        self._keys: list[str] = []
        self._followers: dict[str, object] = {}
        self._routes: dict[str, list[tuple[str, str, str]]] = {}
        self._states: dict[str, object] = {}
        self._resting: dict[str, bool] = {}
        self._hints = HintGates(self.performers)   # when each performer's hints show
        self._shown: dict[str, object] = {}    # the state that drives: fresh or resumed
        self._resume: dict[str, Resume] = {}   # each performer's paused action
        self._replay_turn = 0   # whose turn it is first to replay (_replay_steps)
        self._told: set[str] = set()        # input problems logged (once each)
        self.worker: Worker | None = None   # set: followers rebuilt off the hot path
        self.building = False               # a rebuild runs in the worker
        #: character -> the window the studio set (its performer's follower reaches it)
        self.windows: dict[str, int] = dict(windows or {})
        self.default_window = int(default_window)
        self._retrain()
        self._next_t: float | None = None
        self.take: Take | None = None       # the designer's take (recording or pending)
        self.take_action: str | None = None  # its action's name once stopped
        self.build_error: str | None = None  # why the last rebuild in the worker failed
        self._counter = 0

    # --- training -------------------------------------------------------------------------------

    def _retrain(self, background: bool = False) -> None:
        """Rebuild every performer's follower from the characters' current templates (after a
        character's actions changed; rebuilding restarts every follower). With
        ``background`` and a :attr:`worker` (a take's stop) the followers (15-70 ms for
        examples/mop.yaml) are built in its thread and installed between ticks by whoever set
        the worker (:meth:`install_built`); the old ones play until then."""
        plan = self._plan()
        if self.worker is None or not background:
            if self.worker is not None:
                self.worker.cancel()         # a rebuild still running is out of date
            self.building = False
            self._install(self._build(plan))
        else:
            self.building = True
            self.worker.start(self._build, plan)

    def install_built(self, wait: bool = False) -> bool:
        """Install followers the worker has built (``wait``: blocks until it has); True when
        they were installed (or the build failed)."""
        if not self.building or self.worker is None:
            return False
        if wait:
            self.worker.wait()
        done = self.worker.poll()
        if done is None:
            return False
        self.building = False
        if isinstance(done, Exception):
            self.build_error = f"cannot train: {done}"
        else:
            self.build_error = None
            self._install(done)
        return True

    def _install(self, built: tuple) -> None:
        self._routes, self._followers, self._keys, self._group = built
        self._states, self._shown = {}, {}
        for r in self._resume.values():
            r.drop()

    def _plan(self) -> tuple[dict, dict]:
        """Routes (performer -> (character, action, template key)) and templates by performer."""
        all_routes: dict[str, list[tuple[str, str, str]]] = {}
        by_performer: dict[str, dict[str, np.ndarray]] = {}
        for c in self.order:
            for action, (performer, samples) in self.templates[c].items():
                templates = by_performer.setdefault(performer, {})
                routes = all_routes.setdefault(performer, [])
                key = next((k for k, s in templates.items()
                            if s.shape == samples.shape and np.array_equal(s, samples)), None)
                if key is None:
                    key, n = action, 1
                    while key in templates:
                        n += 1
                        key = f"{action}~{n}"
                    templates[key] = samples
                routes.append((c, action, key))
        return all_routes, by_performer

    def _build(self, plan: tuple[dict, dict]) -> tuple:
        """The followers of a :meth:`_plan` (pure: may run in the worker)."""
        routes, by_performer = plan
        followers = {p: self._follower(p, templates, routes)
                     for p, templates in by_performer.items()}
        # every follower stepped in one vectorised pass
        keys = list(followers)
        group = (self.make_group([followers[k] for k in keys])
                 if self.make_group is not None and keys else None)
        return routes, followers, keys, group

    def _follower(self, performer: str, templates: dict[str, np.ndarray], routes: dict) -> object:
        """``performer``'s follower over ``templates``, with the window :meth:`window_of` gives."""
        f = self.make_follower(templates, **self._follower_args(performer, routes))
        gate_onsets({performer: f}, self.performers)   # hinted from the rest's end (mop.hints)
        return f

    def _follower_args(self, performer: str, routes: dict) -> dict:
        """:attr:`make_follower`'s arguments besides the templates for ``performer``."""
        p, window = self.performers[performer], self.window_of(performer, routes)
        more = {} if window is None else {"window": window}
        return dict(units=p.units, min_scale=p.min_scale, **more)

    def follower_plan(self, performer: str) -> tuple[dict[str, np.ndarray], list, dict]:
        """``performer``'s follower as the stage builds it from the current templates: its
        templates by key, its routes (character, action, key) and :attr:`make_follower`'s other
        arguments (a fresh follower of the same set, e.g. to replay a take through)."""
        routes, by_performer = self._plan()
        return (by_performer.get(performer, {}), routes.get(performer, []),
                self._follower_args(performer, routes))

    def _rebuild(self, performers: list[str]) -> None:
        """Rebuild the followers of ``performers`` only (their window changed; the templates
        did not). The group is made again around them where it can part its members
        (:meth:`GroupsByParameters.replace`: the other parameter sets keep their groups), else
        whole; the performers whose followers start afresh lose their states and paused
        actions, the others go on."""
        if self.building:                 # a rebuild under way would install the old windows
            self._retrain()
            return
        by_performer = self._plan()[1]
        new = {p: self._follower(p, by_performer[p], self._routes) for p in performers}
        self._followers.update(new)
        afresh = set(new)
        if self._group is not None and hasattr(self._group, "replace"):
            afresh |= {self._keys[i] for i in self._group.replace(  # type: ignore[attr-defined]
                {self._keys.index(p): f for p, f in new.items()})}
        elif self._group is not None:
            self._group = self.make_group(  # type: ignore[misc]
                [self._followers[k] for k in self._keys])
            afresh = set(self._keys)
        for p in afresh:
            self._states.pop(p, None)
            self._shown.pop(p, None)
            if p in self._resume:
                self._resume[p].drop()

    def window_of(self, performer: str, routes: dict | None = None) -> int | None:
        """The window (p, states) ``performer``'s follower reaches: the largest the studio set
        for a character it drives (:attr:`windows`), None for the config's."""
        routes = self._routes if routes is None else routes
        set_ = [self.windows[c] for c, _, _ in routes.get(performer, ()) if c in self.windows]
        return max(set_) if set_ else None

    def window(self, character: str) -> int:
        """The window (p, states) ``character``'s performer's follower runs with now: the
        largest the studio set for a character it drives (:meth:`window_of`), else the
        follower's own (:attr:`default_window` while it has none)."""
        performer = self.performer_of(character)
        set_ = self.window_of(performer)
        if set_ is not None:
            return set_
        f = self._followers.get(performer)
        if f is None:
            return self.default_window
        return int(f.forward.half_window)  # type: ignore[attr-defined]

    def sharing(self, character: str) -> list[str]:
        """The other characters whose actions ``character``'s performer's follower follows, or
        that it performs: they share its window."""
        performer = self.performer_of(character)
        routed = {c for c, _, _ in self._routes.get(performer, ())}
        return [c for c in self.order if c != character
                and (c in routed or self.performer_of(c) == performer)]

    def set_window(self, character: str, window: int | None) -> None:
        """``character`` follows with ``window`` (None: the config's): the followers of the
        performers of its actions are rebuilt at once, and only those whose window
        (:meth:`window_of`, the largest of their characters') changes; a follower rebuilt starts
        afresh, so the others keep their progress (rebuilding all of examples/mop.yaml's followers
        takes 15-70 ms)."""
        mine = [p for p, routes in self._routes.items()
                if any(c == character for c, _, _ in routes)]
        before = {p: self.window_of(p) for p in mine}
        if window is None:
            self.windows.pop(character, None)
        else:
            self.windows[character] = int(window)
        changed = [p for p in mine if self.window_of(p) != before[p]]
        if changed:
            self._rebuild(changed)

    # --- the actions (a designer take puts its own: behaviors.mop.takes) ----------------------

    def put_action(self, character: str, action: Action, performer: str, samples: np.ndarray,
                   background: bool = False) -> None:
        """Give ``character`` the action (or replace the one of its name): followed at once
        (with ``background``, once the :attr:`worker` has rebuilt the followers)."""
        self.put_actions([(character, action, performer, samples)], background)

    def put_actions(self, actions: Sequence[tuple[str, Action, str, np.ndarray]],
                    background: bool = False) -> None:
        """:meth:`put_action` for each (character, action, performer, samples), the followers
        rebuilt once for them all (a rebuild of examples/mop.yaml's takes 15-70 ms)."""
        for character, action, performer, samples in actions:
            self.templates[character][action.name] = (performer, samples)
            self.puppets[character].add_action(action)
        self._retrain(background)

    def remove_action(self, character: str, name: str) -> None:
        """``character`` no longer has the action ``name``."""
        if self.templates[character].pop(name, None) is not None:
            self.puppets[character].remove_action(name)
            self._retrain()

    # --- running --------------------------------------------------------------------------------

    def _sample(self, frame: Frame, ts: float) -> None:
        xs, kept = {}, {}
        for pname, performer in self.performers.items():
            kept[pname] = performer.origin   # before the read: a rest beginning moves it
            xs[pname] = x = performer.read(frame, ts)
            # read against the take's origin: a rest moves the path features' origin to where
            # the puck settled (a raise, a hold longer than the rest time, then the return
            # recorded from 0, 0); the stills before and after the gesture are trimmed at its end
            if self.take is not None and self.take.recording and self.take.performer == pname:
                self.take.add(x, performer.origin)
        resumed = {}
        steps = self._replay_steps()
        for i, key in enumerate(self._keys):
            shown = self._shown.get(key)
            holding = (shown is not None and bool(shown.valid)  # type: ignore[attr-defined]
                       and bool(shown.holding))  # type: ignore[attr-defined]
            # a rest ends a gesture, unless an action is held where it holds (a raise, hold,
            # return held longer than the rest time); resting elsewhere ends it. An action
            # that drove when the rest began is kept, to be resumed if the performer goes on
            # with it (behaviors.mop.resume)
            performer, r = self.performers[key], self._resume.get(key)
            if r is None:
                self._resume[key] = r = Resume(self.rate_hz, self.make_group)
            resting = performer.resting and not holding
            n = steps.get(key, 0)   # replay steps of its paused action this sample
            if resting and not self._resting.get(key, False):   # the rest begins
                if shown is not None and shown is r.state:
                    r.keep_resumed(performer.still)
                elif r.preparing:
                    r.settled()
                elif r.drove_lately:
                    r.keep(self._followers[key], kept[key], performer.still)
                else:
                    r.drop()
            elif resting:
                r.rest(n)
            elif r.preparing and performer.still <= 1:   # it moves on: no pause
                r.drop()
            elif r.preparing:
                r.stand(n)
            elif r.kept is None and performer.still > r.stand_samples and r.drives:
                r.prepare(self._followers[key], kept[key], performer.still)
            self._resting[key] = resting
            self._hints.update(key, resting, performer.still, xs[key])
            if resting:   # the gesture ended: wait for the next one from a clean start
                if self._group is not None:
                    self._group.reset_member(i)  # type: ignore[attr-defined]
                else:
                    self._followers[key].reset()  # type: ignore[attr-defined]
            elif not r.preparing:
                resumed[key] = r.follow(xs[key], performer.origin, n)
        if self._group is not None:
            states = self._group.step([xs[k] for k in self._keys])  # type: ignore[attr-defined]
            self._states.update(zip(self._keys, states))
        else:
            for key in self._keys:
                self._states[key] = self._followers[key].step(xs[key])  # type: ignore[attr-defined]
        for key in self._keys:   # the resumed action drives while it out-weighs the fresh one
            fresh, mine = self._states[key], resumed.get(key)
            self._resume[key].add(xs[key], self._resting[key], fresh)
            if mine is not None and bool(fresh.valid) and (  # type: ignore[attr-defined]
                    fresh.loglik > mine.loglik):  # type: ignore[attr-defined]
                self._resume[key].drop()
                mine = None
            self._shown[key] = fresh if mine is None else mine

    def _replay_steps(self) -> dict[str, int]:
        """This sample's replay steps for each performer whose paused action is kept
        (behaviors.mop.resume.share_replay; a function of the samples, so a replay is exact)."""
        waiting = [k for k in self._keys if k in self._resume and self._resume[k].replaying]
        self._replay_turn += 1
        sizes = [len(self._followers[k].names) for k in waiting]  # type: ignore[attr-defined]
        return dict(zip(waiting, share_replay(sizes, self._replay_turn)))

    def _votes(self, character: str) -> list[Vote]:
        """Votes on ``character``'s actions from the followers of the performers that perform
        them; a resting performer's votes are all invalid."""
        votes: list[Vote] = []
        for performer, routes in self._routes.items():
            state = self._shown.get(performer)
            if state is None:
                continue
            mine = [(action, key) for c, action, key in routes   # (not one dropped since)
                    if c == character and action in self.puppets[c].actions]
            if not mine:
                continue
            probs, prog = state.probabilities, state.progress_by  # type: ignore[attr-defined]
            ok = bool(state.valid)  # type: ignore[attr-defined]
            ok = ok and not self._resting.get(performer, False)
            best = state.best  # type: ignore[attr-defined]
            hints = self._hints.likely(performer, state)
            for action, key in mine:
                loglik = float(state.loglik) if key == best else 0.0  # type: ignore[attr-defined]
                votes.append(Vote(action, float(probs[key]), float(prog[key]), ok and key == best,
                                  loglik, key in hints))
        return votes

    def step(self, frame: Frame) -> tuple[CharacterState, ...]:
        t = frame.t
        period = 1.0 / self.rate_hz
        if self._next_t is None or not math.isfinite(self._next_t) or abs(t - self._next_t) > 1.0:
            self._next_t = t
        n = 0
        while self._next_t <= t + 1e-9 and n < self.max_catch_up:
            self._sample(frame, self._next_t)
            self._next_t += period
            n += 1
        if self._next_t <= t:
            self._next_t = t + period
        take = self.take
        recording = take.character if take is not None and take.recording else None
        out = []
        for c in self.order:
            problem = self.performers[self.performer_of(c)].problem
            if problem and problem not in self._told:
                self._told.add(problem)
                log.error("MOP performer %r: %s", self.performer_of(c), problem)
            if c == recording:
                out.append(self.puppets[c].update(t, (), problem or
                                                  f"recording {take.performer}'s new action",
                                                  hold=False))
            else:
                out.append(self.puppets[c].update(t, self._votes(c), problem or ""))
        return tuple(out)
