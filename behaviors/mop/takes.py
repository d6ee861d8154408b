"""Designer takes (MOP 4.1.1, in seconds): :meth:`DesignerTakes.begin_take` records a
character's performer; :meth:`DesignerTakes.stop_take` makes the take an action at once
(trained: the followers are rebuilt), playing the motion chosen with
:meth:`DesignerTakes.assign_motion` (which cycles the character's motions, also for a pending
take). Perform to try it; :meth:`DesignerTakes.keep_take` keeps it (``save`` is called, e.g. to
write it to the library), :meth:`DesignerTakes.drop_take` drops it. :class:`DesignerTakes` is
the take half of :class:`behaviors.mop.stage.MopStage`, which holds the followers and the
worker. The designer's keys and control markers reach these through the studio's one state
machine (:mod:`tabletop.studio`), which draws the countdown, the recording and the status line.
"""

from __future__ import annotations

from typing import Callable, Sequence

import numpy as np

from behaviors.mop.inputs import Performer
from behaviors.mop.puppetry import Action, Puppet
from behaviors.mop.take import Take, free_take_number
from tabletop.files import keep_under_free_name
from tabletop.frames import Frame, InputError

SaveFn = Callable[[str, str, np.ndarray, Sequence[str], str], str]

MIN_TAKE_SAMPLES = 8
#: Seconds of a take kept before its gesture's first move and after its last beyond the inputs'
#: jitter (:func:`behaviors.mop.take.moving_part`): an eased start and end move within the
#: jitter about as long. A square recorded with 0.5 mm of jitter kept 61 of its 73 samples with
#: none, and its action was invalid by the time a performer ended it (85% of its second half
#: valid); 67 and still not at 0.1 s; 69 and valid to the end (100%, progress 0.98) at 0.15 s.
TRIM_MARGIN_S = 0.15


class DesignerTakes:
    """The take half of :class:`behaviors.mop.stage.MopStage`: one designer take at a time
    (:attr:`take`, recording or pending), its action named :attr:`take_action` once stopped."""

    rate_hz: float
    performers: dict[str, Performer]
    puppets: dict[str, Puppet]
    templates: dict[str, dict[str, tuple[str, np.ndarray]]]
    motions: dict[str, tuple[str, ...]]
    character_performer: dict[str, str]
    load_motion: Callable
    save: SaveFn | None
    taken: Callable
    take: Take | None
    take_action: str | None
    _counter: int

    def put_action(self, character: str, action: Action, performer: str, samples: np.ndarray,
                   background: bool = False) -> None:
        raise NotImplementedError

    def remove_action(self, character: str, name: str) -> None:
        raise NotImplementedError

    def performer_of(self, character: str) -> str:
        return self.character_performer.get(character) or next(iter(self.performers))

    def motion_of(self, character: str, index: int) -> str:
        """The ``index``-th (cyclic) motion the designer may assign to ``character``."""
        motions = self.motions[character]
        return motions[index % len(motions)]

    def drop_take(self) -> None:
        """Forget the take (recording or pending); its action leaves the character."""
        if self.take is not None and self.take_action is not None:
            self.remove_action(self.take.character, self.take_action)
        self.take, self.take_action = None, None

    def begin_take(self, character: str, frame: Frame) -> None:
        """Start recording ``character``'s performer at ``frame`` (a pending take is dropped;
        its motion choice carries over)."""
        motion_index = self.take.motion_index if self.take is not None else 0
        self.drop_take()
        performer = self.performer_of(character)
        self.take = Take(performer, character, frame.t)
        self.take.motion_index = motion_index
        self.performers[performer].restart(frame, frame.t)
        self.take.origin = self.performers[performer].origin

    def stop_take(self) -> str:
        """Stop recording: the take becomes an action of its character at once (its followers
        rebuilt, in MopStage's worker when it has one); returns ``"ACTION -> MOTION"``.
        InputError when it is too short to learn from (it is then dropped)."""
        take = self.take
        if take is None or not take.recording:
            raise InputError("no take is recording")
        take.recording = False
        performer = self.performers[take.performer]
        rows = len(take.rows)
        take.trim_still(performer.units, performer.jitter, round(TRIM_MARGIN_S * self.rate_hz))
        samples = take.samples()
        if len(samples) < MIN_TAKE_SAMPLES:
            self.take, self.take_action = None, None
            # a take long enough but (nearly) still says so, not only its samples of motion
            still = (f": {take.performer} hardly moved in the {rows / self.rate_hz:.1f} s "
                     "recorded" if rows >= MIN_TAKE_SAMPLES else "")
            raise InputError(f"take too short{still} ({len(samples)} of "
                             f"{MIN_TAKE_SAMPLES} samples of motion)")
        name = self.take_action = self._free_name(take.character)
        motion = self.motion_of(take.character, take.motion_index)
        self._add_take_action(motion, background=True)
        return f"{name} -> {motion}"

    def _free_name(self, character: str) -> str:
        """The next ``takeN`` that is none of the names ``character``'s library holds, loaded
        or not (a template skipped at load as corrupt kept its file: a take of its name was
        saved over it), nor of its actions."""
        existing = set(self.templates[character]) | set(self.taken(character))
        self._counter = free_take_number(existing, self._counter + 1)
        return f"take{self._counter}"

    def assign_motion(self, character: str) -> str:
        """The next motion for ``character``'s take (chosen before recording, or played by the
        pending take at once); returns its name."""
        if self.take is None or self.take.character != character:
            self.drop_take()
            self.take = Take(self.performer_of(character), character, 0.0)
            self.take.recording = False
        self.take.motion_index += 1
        motion = self.motion_of(character, self.take.motion_index)
        if self.take_action is not None:
            self._add_take_action(motion)
        return motion

    def keep_take(self) -> str:
        """Keep the pending take (``save``d, e.g. to the library); returns the name it is kept
        under: its own, or the next free one when ``save`` finds its name taken meanwhile
        (:class:`tabletop.names.NameTaken`; the take's action is renamed, its followers rebuilt
        within the tick). InputError when there is nothing to keep or it cannot be saved (the take
        stays)."""
        take = self.take
        if take is None or self.take_action is None or take.recording:
            raise InputError("nothing to keep")
        motion = self.motion_of(take.character, take.motion_index)
        if self.save is not None:
            save = self.save
            try:
                keep_under_free_name(
                    lambda: save(take.character, self.take_action, take.samples(),
                                 self.performers[take.performer].names, motion),
                    lambda name: self._rename_take(name, motion),
                    lambda: self._free_name(take.character))
            except OSError as exc:
                raise InputError(f"not saved: {exc}") from None
        name = self.take_action
        self.take, self.take_action = None, None
        return name

    def _rename_take(self, name: str, motion: str) -> None:
        """The pending take's action is ``name`` from now (one rebuild of the followers)."""
        assert self.take is not None and self.take_action is not None
        c = self.take.character
        self.templates[c].pop(self.take_action, None)
        self.puppets[c].remove_action(self.take_action)
        self.take_action = name
        self._add_take_action(motion)

    def _add_take_action(self, motion: str, background: bool = False) -> None:
        take = self.take
        assert take is not None and self.take_action is not None
        c = take.character
        self.put_action(c, Action(self.take_action, self.load_motion(c, motion)), take.performer,
                        take.samples(), background)
