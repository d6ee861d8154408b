"""MOP action slots through the studio's one state machine: record, train, assign a motion, try,
keep (written to the library and loaded by a new engine), discard, redo, too short, focus."""

from pathlib import Path

import numpy as np
import yaml

from tabletop.frames import Frame, Puck
from tabletop.studio.machine import Studio
from tabletop.studio.targets import MopTarget
from tests.mop.test_plugin import RATE, Table, _build, _designer_config


class StudioTable(Table):
    """The stage behind a studio (no countdown, training within the tick), stepped as the loop
    does: studio filter, then the engine; ``status`` is the studio's status line."""

    def __init__(self, engine, lib: Path, focus: str = "mop/face") -> None:
        super().__init__(engine)
        self.targets = [MopTarget(engine, c, lib, background=False) for c in engine.order]
        self.studio = Studio(self.targets, countdown_s=0.0)
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


def test_a_take_is_recorded_trained_assigned_kept_and_reloaded(tmp_path):
    engine = _build(_designer_config(tmp_path), tmp_path)
    table = StudioTable(engine, tmp_path / "lib", focus="mop/lizard")
    table.rest(1.0)
    table.tick(["designer.record"])
    table.tick()
    assert "recording" in table.status and table.studio.state == "recording"
    table.perform("square")
    table.tick(["designer.record"])
    assert "take1 -> strike" in table.status and table.studio.state == "trying"
    assert engine.puppets["lizard"].actions["take1"].clip.name == "strike"
    table.tick(["designer.assign"])
    assert "motion curl" in table.status
    assert engine.puppets["lizard"].actions["take1"].clip.name == "curl"
    # trained at once: perform it (a little faster) and the lizard curls along
    table.rest(1.2)
    run = table.perform("square", speed=lambda u: 1.3)
    late = [ch["lizard"] for u, ch in run if u > 0.5]
    assert np.mean([x.valid and x.action == "take1" for x in late]) > 0.9
    assert late[-1].progress > 0.85
    # keep: written atomically to the library, and a new engine loads it
    table.tick(["designer.keep"])
    assert "kept as take1" in table.status and table.studio.state == "idle"
    saved = yaml.safe_load((tmp_path / "lib" / "lizard" / "actions.yaml").read_text())
    assert saved == {"actions": [{"name": "take1", "template": "take1.csv", "motion": "curl"}]}
    header = (tmp_path / "lib" / "lizard" / "take1.csv").read_text().splitlines()[0]
    assert header == "t,dx,dy"
    again = _build(_designer_config(tmp_path), tmp_path)
    assert "take1" in again.puppets["lizard"].actions
    assert again.templates["lizard"]["take1"][1].shape == engine.templates["lizard"]["take1"][1].shape


def test_discard_redo_and_a_take_too_short(tmp_path):
    engine = _build(_designer_config(tmp_path), tmp_path)
    table = StudioTable(engine, tmp_path / "lib")
    table.rest(1.0)
    table.tick(["designer.record"])
    table.perform("line")
    table.tick(["designer.record"])
    assert "take1" in engine.puppets["face"].actions
    n1 = len(engine.templates["face"]["take1"][1])
    table.rest(1.0)
    table.tick(["designer.record"])            # redo: the pending take is replaced
    assert "take1" not in engine.puppets["face"].actions
    assert table.studio.tries[-1].outcome == "redone"
    table.perform("zigzag")
    table.tick(["designer.record"])
    assert "take2" in engine.puppets["face"].actions
    assert n1 != len(engine.templates["face"]["take2"][1])
    table.tick(["designer.discard"])
    assert "discarded" in table.status and table.studio.tries[-1].outcome == "discarded"
    assert set(engine.puppets["face"].actions) == {"circle"}
    assert not (tmp_path / "lib").exists()
    # a take too short to learn from is refused
    table.tick(["designer.record"])
    table.tick(["designer.record"])
    assert "too short" in table.status and set(engine.puppets["face"].actions) == {"circle"}
    assert table.studio.tries[-1].outcome == "too short" and table.studio.state == "idle"


def test_the_focus_selects_the_character_and_other_targets_commands_pass(tmp_path):
    engine = _build(_designer_config(tmp_path), tmp_path)
    table = StudioTable(engine, tmp_path / "lib")
    assert table.studio.designer_targets() == ("mop/face", "mop/lizard")
    assert not hasattr(engine, "designer_targets")     # the studio lists the slots
    table.rest(0.5)
    table.focus = "mop/lizard"                         # Tab in the view
    table.tick(["designer.record"])
    assert engine.take.character == "lizard" and "[mop/lizard] recording" in table.status
    table.perform("square")
    table.tick(["designer.record"])
    assert "take1" in engine.puppets["lizard"].actions
    # commands addressed to another engine are not the studio's
    table.tick(["designer.discard"], focus="pm")
    assert "take1" in engine.puppets["lizard"].actions and table.studio.state == "trying"
    # moving the focus away from the take being tried discards it
    table.tick(focus="mop/face")
    assert "take1" not in engine.puppets["lizard"].actions
    assert table.studio.tries[-1].outcome == "discarded"
