"""Live config edits and the studio: an edit turning the studio on or off is applied; one saved
while a take is tried waits for it, shown while it waits."""

import yaml

from tabletop.config import load_config
from tabletop.frames import Frame
from tabletop.kiosk.runner import Runner
from tests.kiosk.test_live_config import config, rebuilt, running, write
from tracking.scenes import wait_for


def test_an_edit_that_turns_the_studio_on_or_off_is_applied(tmp_path):
    """A kiosk started without the designer studio, its config then edited to put the lover in
    designer mode: the rebuilt installation has the studio (designer keys, a ``studio`` status)
    without waiting for a restart, and one edited back has none: each build takes it from its
    own configuration."""
    cfg = config([10, 20, 30])
    path = tmp_path / "config.yaml"
    path.write_text(yaml.safe_dump(cfg))
    with running(Runner(path, load_config(path), headless=True, kiosk=True)) as runner:
        assert runner.reporter.status(Frame(seq=0, t=0.0)).get("studio") is None
        first = runner.inst
        cfg["engines"][0]["designer"] = {"enabled": True, "main_puck": 1, "react_puck": 2,
                                         "library": "lib"}
        write(path, yaml.safe_dump(cfg))
        assert wait_for(rebuilt(runner, first), 30)
        status = runner.reporter.status(Frame(seq=0, t=0.0)).get("studio")
        assert status is not None and "lover" in str(status)
        second = runner.inst
        del cfg["engines"][0]["designer"]
        write(path, yaml.safe_dump(cfg))
        assert wait_for(rebuilt(runner, second), 30)
        assert runner.reporter.status(Frame(seq=0, t=0.0)).get("studio") is None


def test_an_edit_saved_while_a_studio_take_is_tried_waits_for_it(tmp_path):
    """The designer edits config.yaml while trying a take: the applied edit rebuilt the
    installation at once and the take was gone without a word. The edit waits, said on the
    status line, until the take is kept (or dropped); then it is applied."""
    cfg = config([10, 20, 30])
    cfg["engines"][0]["designer"] = {"enabled": True, "main_puck": 1, "react_puck": 2,
                                     "library": "lib", "background_training": False,
                                     "min_seconds": 1.0}      # a take trained after 1 s
    cfg["studio"] = {"countdown_s": 0.1}
    path = tmp_path / "config.yaml"
    path.write_text(yaml.safe_dump(cfg))
    with running(Runner(path, load_config(path), headless=True)) as runner:
        first, studio = runner.inst, runner.studio
        first.loop.commands.put("designer.record")
        assert wait_for(lambda: studio.state == "recording" and studio.target.seconds() > 1.3, 30)
        first.loop.commands.put("designer.record")
        assert wait_for(lambda: studio.state == "trying", 30)
        cfg["engines"][0]["color"] = [200, 100, 50]
        write(path, yaml.safe_dump(cfg))
        assert wait_for(lambda: runner.pending is not None, 15)
        ticks = first.loop.stats.ticks
        assert wait_for(lambda: first.loop.stats.ticks > ticks + 30, 15)
        assert runner.inst is first and studio.state == "trying"
        assert "config edit: applied once this take is kept (K)" in studio.message
        first.loop.commands.put("designer.keep")
        assert wait_for(rebuilt(runner, first), 30)
        assert runner.inst.engines[0].color == (200, 100, 50)
        assert (tmp_path / "lib" / "lover" / "behavior.yaml").is_file()


def test_an_edit_waiting_for_a_studio_take_is_shown_while_it_waits(tmp_path):
    """A deferred edit was said once on the status line, gone at the next message; the status
    file said nothing pending. It shows as config_pending and on the overlay until applied."""
    import json
    cfg = config([10, 20, 30])
    cfg["engines"][0]["designer"] = {"enabled": True, "main_puck": 1, "react_puck": 2,
                                     "library": "lib", "background_training": False,
                                     "min_seconds": 1.0}      # a take trained after 1 s
    cfg["studio"] = {"countdown_s": 0.1}
    cfg["kiosk"]["heartbeat"]["every_s"] = 0.1
    path = tmp_path / "config.yaml"
    path.write_text(yaml.safe_dump(cfg))
    status_file = tmp_path / "status.json"
    with running(Runner(path, load_config(path), headless=True, kiosk=True)) as runner:
        first, studio = runner.inst, runner.studio
        (view,) = [s for s in first.loop.sinks if s.name == "view"]
        notices = lambda: [n for fn in view.notices for n in fn()]   # noqa: E731
        first.loop.commands.put("designer.record")
        assert wait_for(lambda: studio.state == "recording" and studio.target.seconds() > 1.3, 30)
        first.loop.commands.put("designer.record")
        assert wait_for(lambda: studio.state == "trying", 30)
        assert not json.loads(status_file.read_text())["config_pending"]
        cfg["engines"][0]["color"] = [200, 100, 50]
        write(path, yaml.safe_dump(cfg))
        assert wait_for(lambda: json.loads(status_file.read_text())["config_pending"], 15)
        assert "config edit waits: K keeps the take, X drops it" in notices()
        first.loop.commands.put("designer.keep")
        assert wait_for(rebuilt(runner, first), 30)
        assert wait_for(lambda: not json.loads(status_file.read_text())["config_pending"], 15)


def test_an_edit_applied_while_a_designer_behaviour_file_is_bad_keeps_it_playing(tmp_path):
    """A Puppet Master character in designer mode (the studio drives it) whose behaviour file
    went bad: an edit of another part applies, and the character plays on with the behaviour
    read before, as outside the studio; the status's behavior_errors says the new file is
    refused until the file is fixed, and the rebuilt installation's recording replays to the
    same characters."""
    import shutil

    from tests.kiosk.running import replays_without
    from tests.kiosk.test_live_config import ROOT
    shutil.copytree(ROOT / "behaviors" / "library" / "lover", tmp_path / "lover")
    cfg = config([10, 20, 30])
    cfg["engines"][0]["behavior"] = "lover"
    cfg["engines"][0]["designer"] = {"enabled": True, "main_puck": 1, "react_puck": 2,
                                     "library": "lib"}
    path = tmp_path / "config.yaml"
    path.write_text(yaml.safe_dump(cfg))
    session = tmp_path / "session.jsonl"
    with running(Runner(path, load_config(path), headless=True, kiosk=True,
                        record_path=session)) as runner:
        first = runner.inst
        played = first.engines[0].behavior
        assert played is not None and runner.studio is not None
        good = (tmp_path / "lover" / "demonstration.csv").read_text()
        with open(tmp_path / "lover" / "demonstration.csv", "a") as f:
            f.write("1e3,0.5,0.5\n")                     # a short row: a copy cut short
        cfg["engines"][0]["color"] = [200, 100, 50]
        write(path, yaml.safe_dump(cfg))
        assert wait_for(rebuilt(runner, first, ticks=60), 30)
        engine = runner.inst.engines[0]
        assert engine.color == (200, 100, 50) and runner.studio is not None
        assert engine.behavior is played and engine.reactor is not None
        (error,) = runner.reporter.status(Frame(seq=0, t=0.0))["behavior_errors"]
        assert error.startswith("lover: ") and "demonstration.csv: line" in error
        assert error.endswith("; refused, still playing the behaviour read before"), error
        # fixed on disk: the studio plays the folder, and the status says nothing more
        (tmp_path / "lover" / "demonstration.csv").write_text(good)
        assert wait_for(lambda: runner.reporter.status(Frame(seq=0, t=0.0))["behavior_errors"]
                        == [] and engine.behavior is not played, 30)
    live = replays_without(tmp_path / "session-2.jsonl", tmp_path / "replayed.jsonl", {"lover"})
    lover = [c for f in live for c in f["characters"] if c["name"] == "lover"]
    assert lover[0]["valid"] and lover[-1]["valid"]


def test_what_an_applied_edit_did_is_on_the_rebuilt_studio_s_line(tmp_path):
    """The rebuilt studio says what the edit did (takes kept for this run only saved or
    dropped) before its first frame: the message's seconds ran on the loop's clock from the
    last installation's, so it was past at the first frame and never drawn. It is drawn from
    the first frame for MESSAGE_S, then the line is the studio's own again."""
    from tabletop.studio.machine import MESSAGE_S
    cfg = config([10, 20, 30])
    cfg["engines"][0]["designer"] = {"enabled": True, "main_puck": 1, "react_puck": 2,
                                     "library": "lib"}
    cfg["studio"] = {"enabled": True}
    path = tmp_path / "config.yaml"
    path.write_text(yaml.safe_dump(cfg))
    note = "config edit dropped mop/face's takes kept for this run only: take1"
    with running(Runner(path, load_config(path), headless=True, kiosk=True)) as runner:
        first = runner.inst
        runner._notes.append(note)           # as _save_run_only leaves them for the rebuild
        cfg["engines"][0]["color"] = [200, 100, 50]
        write(path, yaml.safe_dump(cfg))
        assert wait_for(rebuilt(runner, first), 30)
        studio = runner.studio

        def line() -> str:
            return studio.character(Frame(seq=0, t=studio._t)).label
        assert studio._t > MESSAGE_S and line() == f"[lover] {note}"
        assert 0 < studio._message_until - studio._t <= MESSAGE_S
        assert wait_for(lambda: "R record" in line(), MESSAGE_S + 10)
