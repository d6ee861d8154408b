"""The MOP stage behind a studio, stepped as the loop does (the studio's tests and
benchmarks)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Iterable

from tabletop.frames import CharacterState, Frame, Puck
from tabletop.plugins.mop_table import RATE, Table
from tabletop.studio.machine import Studio
from tabletop.studio.mop_target import MopTarget

if TYPE_CHECKING:
    from behaviors.mop.stage import MopStage


class StudioTable(Table):
    """The stage behind a studio (no countdown, followers built within the tick, a take tried
    from the tick after its stop), stepped as the loop does: studio filter, then the engine;
    ``status`` is the studio's status line."""

    def __init__(self, engine: MopStage, lib: Path, focus: str = "mop/face") -> None:
        super().__init__(engine)
        self.targets = [MopTarget(engine, c, lib, background=False) for c in engine.order]
        self.studio = Studio(self.targets, countdown_s=0.0, swap_s=0.0)
        self.focus, self.status = focus, ""

    def tick(self, commands: Iterable[str] = (),
             focus: str | None = None) -> dict[str, CharacterState]:
        pucks = tuple(Puck(i, x, y, 0.0) for i, (x, y) in self.pucks.items())
        frame = self.studio(Frame(self.seq, self.t, pucks=pucks, commands=tuple(commands),
                                  focus=focus or self.focus))
        self.status = frame.character("studio").label
        out = {c.name: c for c in self.engine.step(frame)}
        self.t += 1.0 / RATE
        self.seq += 1
        return out

    def stop_take(self) -> dict[str, CharacterState]:
        """The tick that stops the take, then the ticks until it is tried (the take's likeness
        check runs in its target's worker, waited for on the next tick); the last tick's
        characters."""
        out = self.tick(["designer.record"])
        while self.studio.state == "training":
            out = self.tick()
        return out
