"""The performers' state a later recording part carries (:class:`PartStates`, part of
:class:`behaviors.mop.stage.MopStage`; saved and restored by :func:`tabletop.parts.part_states`
and :func:`tabletop.parts.resume_parts`)."""

from __future__ import annotations

from typing import Any

from behaviors.mop.inputs import Performer


class PartStates:
    """Each performer's inputs' state across recording parts (``performers``: name ->
    :class:`~behaviors.mop.inputs.Performer`, set by the stage)."""

    performers: dict[str, Performer]

    def part_state(self) -> dict[str, list]:
        """Each performer's inputs' state (:meth:`Performer.state`), which a later recording
        part carries: replayed alone from afresh, a puck that rested before the part began
        is not resting yet, and its next gesture starts as many samples early as it stood
        within the rest radius before leaving it (1 of 42 frames differed)."""
        return {n: p.state() for n, p in self.performers.items()}

    def resume_part(self, state: Any) -> None:
        """The performers go on from :meth:`part_state`'s ``state`` (a part replayed alone)."""
        for n, s in dict(state).items():
            if n in self.performers:
                self.performers[n].set_state(s)
