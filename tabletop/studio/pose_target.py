"""A touch-pose character as a studio target: actions designed by posing it at the table.

The take is the character's posture, sampled every tick while the designer poses it with their
fingers (the character does not start its known actions meanwhile: drags only pose). Stopping
makes it an action (:func:`behaviors.touch_pose.designed.designed_action`, learned in a worker
thread and swapped in between ticks 0.3 s of frame time after the stop, as the other engines'
takes are after 0.15 s), known to the character: the designer tries it by dragging its primary
part along the recorded path (drawn on the table), in their own timing. Kept actions are folders of
the engine's ``library`` (:func:`~behaviors.touch_pose.designed.save_action`), known from the next
start too; renamed in place and deleted into ``<library>/.trash`` so undo restores them.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import TYPE_CHECKING, Callable

import numpy as np

from behaviors.touch_pose import designed
from behaviors.touch_pose.humanoid import PARTS, Humanoid, Pose
from behaviors.touch_pose.samples import relative
from tabletop import library
from tabletop.frames import Frame, InputError
from tabletop.kiosk.watch import Poller, tree_signature
from tabletop.files import keep_under_free_name
from tabletop.studio.folders import named_folder, rename_folder, trash
from behaviors.worker import Worker, close_workers

if TYPE_CHECKING:
    from behaviors.touch_pose.action import ActionModel
    from tabletop.plugins.touch_pose import TouchPoseEngine


def _learn(body: Humanoid, name: str, times: np.ndarray, poses: list[Pose],
           part: str | None) -> tuple[ActionModel, np.ndarray]:
    """(the take's action, its demonstration for the session log: t and its primary part's
    path, character metres); pure, so it may run in the worker."""
    action = designed.designed_action(body, name, times, poses, part)
    k = PARTS.index(action.spec.part)
    path = np.array([body.parts(relative(p, poses[0]))[k] for p in poses])
    return action, np.column_stack([times - times[0], path])


class TouchPoseTarget:
    """The designed actions of one touch-pose engine (:mod:`tabletop.plugins.touch_pose`)."""

    what = "pose action"

    def __init__(self, engine: TouchPoseEngine, background: bool = True) -> None:
        self.engine, self.core = engine, engine.core
        self.worker = Worker(f"{engine.name}-training") if background else None
        self.name = engine.name
        self.lib = Path(engine.library)
        self.base: Path | None = None        # the config's folder (the keep's line)
        self.times: list[float] = []
        self.poses: list[Pose] = []
        self.held: dict[str, int] = {}
        self.pending = None                  # the ActionModel being tried
        self.demo: np.ndarray | None = None  # t and its primary part's path (the session log)
        self.kept: str | None = None
        self._loaded = set(engine.designed)   # the library's actions the character knows
        self._poller = Poller(self.lib, read=getattr(engine, "library_read", None))
        self._problems: list[str] = list(engine.problems)
        self.started_problems = tuple(engine.problems)   # logged by the engine's start

    # --- the take ------------------------------------------------------------------------------

    def close(self, deadline: float | None = None) -> bool:
        """The studio closes: the training worker's thread ends, waited for until
        ``deadline``; says whether it did."""
        return close_workers(self.worker, deadline=deadline)

    def begin(self, frame: Frame) -> None:
        self.times, self.poses, self.demo = [], [], None
        self.held: dict[str, int] = {}        # ticks each part was held
        self.core.recognising = False

    def resume(self, frame: Frame) -> None:
        pass                                  # an action is one part

    def record(self, frame: Frame) -> str:
        if not self.times or frame.t > self.times[-1]:
            self.times.append(frame.t)
            self.poses.append(self.core.target.copy())
        held = [f.part for f in self.core.fingers.values() if f.part is not None]
        for part in held:
            self.held[part] = self.held.get(part, 0) + 1
        return "" if held else "recording: hold a body part and move it"

    def ended(self) -> bool:
        return False

    def cut(self) -> str:
        return ""

    def seconds(self) -> float:
        return self.times[-1] - self.times[0] if self.times else 0.0

    def _free_name(self) -> str:
        """``ENGINE-action`` (then ``-2``, ``-3``..., shortened to leave room for the number
        within the library's 64 characters, as a behaviour's name is), or ``action`` for an
        engine whose name no folder may have ("mein Poser"): its takes were refused as they
        stopped."""
        base = f"{self.name}-action"
        if not library.NAME_RE.match(base):
            base = "action"
        taken = {a.name for a in self.core.m.actions}
        name, i = base, 2
        while name in taken or (self.lib / name).exists():
            name, i = library.numbered(base, i), i + 1
        return name

    def train(self) -> str | None:
        """The take's action is learned (about 50 ms CPU) in the worker (None: the studio swaps
        it in with :meth:`trained`), else at once; then the character knows it."""
        self.core.recognising = True
        if not self.held and self.seconds() >= designed.MIN_SECONDS:   # (a shorter one is
            # too short, said by the learning) nobody posed it: said so, not as "the head hardly
            # moves (0.00 m)", the part that moved most, to a designer whose drag missed the figure
            raise InputError("no body part was held: press on a part and move it while "
                             "recording")
        part = max(self.held, key=self.held.__getitem__) if self.held else None   # else: moved most
        job = (self.core.body, self._free_name(), np.array(self.times), list(self.poses), part)
        if self.worker is None:
            return self._learned(_learn(*job))
        self.worker.start(_learn, *job)
        return None

    def trained(self, wait: bool) -> str | None:
        """Between ticks: the worker's action, once learned (``wait``: waits for it), is known
        from now; InputError when the take cannot be an action."""
        if self.worker is None:
            return None
        if wait:
            self.worker.wait()
        done = self.worker.poll()
        if done is None:
            return None
        if isinstance(done, InputError):
            raise done
        if isinstance(done, Exception):
            raise InputError(f"training failed: {done}")
        return self._learned(done)

    def _learned(self, learned: tuple) -> str:
        action, self.demo = learned
        self.core.add_action(action)
        self.pending = action
        return (f"trained {action.name}: its {action.spec.part.replace('_', ' ')}, "
                f"{action.duration:.1f} s; drag it along that path")

    cue = "get ready: hold a body part, then pose the motion"
    swap_s = 0.3     # learning a take's action takes 50 ms CPU here (60 frames, bench/studio.py)

    def guide(self) -> np.ndarray | None:
        """The path to drag to try the take (table metres), from where its part is now."""
        return None if self.pending is None else self.core.stroke_on_table(self.pending)

    def tried_take(self) -> tuple[str, str] | None:
        """The take being tried as its keep saves it: (".json", the ``action.json`` of
        :func:`behaviors.touch_pose.designed.save_action`); None without one."""
        if self.pending is None or not self.times:
            return self.learning_take()
        a = self.pending
        return ".json", designed.to_json(a.name, a.spec.part, np.array(self.times), self.poses)

    def learning_take(self) -> tuple[str, str] | None:
        """A take still being learned, as :meth:`recorded_take` gives one; None without one."""
        if self.worker is None or not self.times:
            return None
        made = self.recorded_take()
        return made if isinstance(made, tuple) else None

    def recorded_take(self) -> tuple[str, str] | str:
        """The take still recorded (or learned) at quit as an ``action.json``, its name the
        one its keep would take and its part the one held longest; or why none: shorter than
        :data:`~behaviors.touch_pose.designed.MIN_SECONDS`, or no part held."""
        if self.seconds() < designed.MIN_SECONDS:
            return (f"take too short ({self.seconds():.2f} s, needs "
                    f"{designed.MIN_SECONDS:g} s)")
        if not self.held:
            return "no body part was held"
        part = max(self.held, key=self.held.__getitem__)
        return ".json", designed.to_json(self._free_name(), part, np.array(self.times),
                                         self.poses)

    def revert(self) -> None:
        self.core.recognising = True
        if self.worker is not None:
            self.worker.cancel()              # a take still being learned is dropped
        a, self.pending = self.pending, None
        if a is not None:
            self.core.remove_action(a.name)
            if a.name in self._loaded:        # another run kept an action of its name: known
                self._load(a.name)

    @property
    def kept_in(self) -> str:
        """What the keep's line adds: the library folder it was saved in."""
        return f" in {named_folder(self.lib, self.base)}"

    def keep(self) -> str:
        """Save the take's action under its name, or the next free one when another run on the
        library kept an action of its name after it was trained (that one is known from now)."""
        a = self.pending
        if a is None:
            raise InputError("nothing to keep")
        named = a.name
        stale = tree_signature(self.lib) != self._poller.signature
        keep_under_free_name(
            lambda: designed.save_action(self.lib, a.name, a.spec.part, np.array(self.times),
                                         self.poses),
            lambda name: self._rename_action(a, name), self._free_name)
        self.kept, self.pending = a.name, None
        self._loaded.add(a.name)
        if named != a.name:       # refused for its name: the other run's action is there
            self._load(named)
            self._loaded.add(named)
        if not stale:             # else the watcher's next look reloads all of the library
            self._seen()
        return a.name

    def _rename_action(self, action: ActionModel, new: str) -> None:
        """The character knows ``action`` as ``new`` from now."""
        self.core.remove_action(action.name)
        action.spec = dataclasses.replace(action.spec, name=new)
        self.core.add_action(action)

    def _load(self, name: str) -> None:
        """The library's action ``name`` is known from now (a bad one is reported)."""
        try:
            self.core.add_action(designed.load_action(self.lib / name, self.core.body))
        except InputError as exc:
            self._problems = [*self._problems, str(exc)]

    def _seen(self) -> None:
        """The library's changes made here are not reloads."""
        self._poller.signature = tree_signature(self.lib)

    # --- the library -----------------------------------------------------------------------------

    def items(self) -> list[str]:
        return designed.list_actions(self.lib)

    def current(self) -> str | None:
        return self.kept

    def use(self, name: str) -> None:
        self.kept = name      # every kept action is known to the character; this one is selected

    def rename(self, old: str, new: str, undo: bool = False) -> None:
        """Rename a kept action; a name the character already knows (a built-in action such as
        the punch) is refused: the renamed action would replace it, and undo then remove it."""
        if new in {a.name for a in self.core.m.actions}:
            raise InputError(f"an action {new!r} already exists")
        rename_folder(self.lib, old, new, check=not undo)
        action = next((a for a in self.core.m.actions if a.name == old), None)
        if action is not None:
            self._rename_action(action, new)
        self._loaded = (self._loaded - {old}) | {new}
        if self.kept == old:
            self.kept = new
        self._seen()

    def remove(self, name: str) -> Callable[[], None]:
        put_back = trash(self.lib / name)
        self.core.remove_action(name)
        self._loaded.discard(name)
        was_kept = self.kept == name
        if was_kept:
            self.kept = None
        self._seen()

        def restore() -> None:
            put_back()
            self.core.add_action(designed.load_action(self.lib / name, self.core.body))
            self._loaded.add(name)
            if was_kept and self.kept is None:
                self.kept = name               # in play again: F2 said "nothing to rename"
            self._seen()
        return restore

    def poll(self) -> list[str]:
        """Reload the library when its files change: new and fixed actions are known at once,
        removed ones forgotten; a bad file is reported and skipped, the others keep working."""
        if self._poller.changed():
            actions, self._problems = designed.load_library(self.lib, self.core.body)
            self.engine.problems = self._problems      # (a kiosk's behavior_errors)
            names = {a.name for a in actions}
            for gone in self._loaded - names:
                if self.pending is None or gone != self.pending.name:
                    self.core.remove_action(gone)
            for a in actions:   # (another run's keep of the take's name: the take is tried on)
                if self.pending is None or a.name != self.pending.name:
                    self.core.add_action(a)
            self._loaded = names
        return self._problems
