"""The MOP stage behind a studio, stepped as the loop does, and the takes the studio's MOP tests
start from (a face's take tried, kept, kept without a library)."""

from pathlib import Path

from tabletop.frames import Frame, Puck
from tabletop.studio.machine import Studio
from tabletop.studio.mop_target import MopTarget
from tests.mop.helpers import RATE, Table, build, designer_config


class StudioTable(Table):
    """The stage behind a studio (no countdown, followers built within the tick, a take tried
    from the tick after its stop), stepped as the loop does: studio filter, then the engine;
    ``status`` is the studio's status line."""

    def __init__(self, engine, lib: Path, focus: str = "mop/face") -> None:
        super().__init__(engine)
        self.targets = [MopTarget(engine, c, lib, background=False) for c in engine.order]
        self.studio = Studio(self.targets, countdown_s=0.0, swap_s=0.0)
        self.focus, self.status = focus, ""

    def tick(self, commands=(), focus=None):
        pucks = tuple(Puck(i, x, y, 0.0) for i, (x, y) in self.pucks.items())
        frame = self.studio(Frame(self.seq, self.t, pucks=pucks, commands=tuple(commands),
                                  focus=focus or self.focus))
        self.status = frame.character("studio").label
        out = {c.name: c for c in self.engine.step(frame)}
        self.t += 1.0 / RATE
        self.seq += 1
        return out

    def stop_take(self):
        """The tick that stops the take, then the ticks until it is tried (the take's likeness
        check runs in its target's worker, waited for on the next tick); the last tick's
        characters."""
        out = self.tick(["designer.record"])
        while self.studio.state == "training":
            out = self.tick()
        return out

def face_take(tmp_path, gesture: str = "line"):
    """A run with the face's take of ``gesture`` being tried; (engine, table), the library
    read at once."""
    engine = build(designer_config(tmp_path), tmp_path)
    table = StudioTable(engine, tmp_path / "lib")
    for t in table.targets:
        t._poller.every_s = 0.0
    table.rest(1.0)
    table.tick(["designer.record"])
    table.perform(gesture)
    table.stop_take()
    return engine, table

def kept_line(tmp_path):
    """The face's take of a line, kept as take1; (engine, table), the library read at once."""
    engine, table = face_take(tmp_path)
    table.tick(["designer.keep"])
    return engine, table

def kept_without_library(tmp_path, cfg: dict | None = None):
    """A face's take of a line kept "for this run only" by an engine without a library
    (``cfg``: the designer config by default, its library taken away). Returns (the engine,
    its studio table, the config)."""
    cfg = cfg or designer_config(tmp_path)
    cfg["engines"][0].pop("library", None)
    engine = build(cfg, tmp_path)
    table = StudioTable(engine, None)
    table.rest(1.0)
    table.tick(["designer.record"])
    table.perform("line")
    table.stop_take()
    table.tick(["designer.keep"])
    assert "for this run only" in table.status
    return engine, table, cfg
