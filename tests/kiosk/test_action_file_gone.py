"""A kiosk started (a reboot, a restart) while a MOP template named in its config is a folder
(a technician's ``mkdir`` over it) and a clip file is deleted: the table runs without those
actions, each named in the status's behavior_errors with its file and what is wrong, as for a
corrupt file; the recording replays to the same characters; the files put back are followed
without a restart. A config edit refused for a corrupt template is applied once the template is
fixed, and a fixed template copied in two writes is read whole."""

import numpy as np
import yaml

from tabletop.kiosk import last_good
from tabletop.kiosk.actions import ActionReloader
from tabletop.kiosk.runner import Runner
from tabletop.kiosk.watch import ConfigWatcher
from tabletop.plugins.mop_files import load_template
from tests.kiosk.running import Latest, kiosk_built, replays_without, running
from tests.kiosk.test_bad_action_start import _config, _corrupt, drawing_config
from tests.kiosk.test_kiosk_lock import status
from tracking.scenes import wait_for


def test_a_kiosk_starts_without_a_template_made_a_folder_and_a_deleted_clip(tmp_path):
    cfg_path, good = drawing_config(tmp_path)
    (tmp_path / "line.csv").unlink()
    (tmp_path / "line.csv").mkdir()
    (tmp_path / "wag.json").unlink()
    session = tmp_path / "session.jsonl"
    inst, refused = kiosk_built(cfg_path, record_path=session)
    assert refused is None
    stage = inst.engines[0]
    errors = stage.start_problems
    assert len(errors) == 3, errors
    assert all("\n" not in e for e in errors)
    assert sum("action 'line'" in e and "line.csv" in e and "folder" in e
               for e in errors) == 2, errors
    assert any("'walker', action 'square'" in e and "wag.json" in e and "not found" in e
               for e in errors), errors
    latest = Latest()
    inst.loop.sinks.insert(0, latest)
    with running(inst, 60):
        assert wait_for(lambda: len(status(tmp_path).get("behavior_errors", ())) == 3, 10.0)
        (tmp_path / "line.csv").rmdir()
        (tmp_path / "line.csv").write_text(good["line.csv"])
        (tmp_path / "wag.json").write_text(good["wag.json"])
        assert wait_for(lambda: status(tmp_path).get("behavior_errors") == [], 10.0), \
            status(tmp_path)
        assert {n: set(t) for n, t in stage.templates.items()} == {
            "walker": {"circle", "line", "square"}, "lone": {"line"}}
        assert wait_for(lambda: {"walker", "lone"} <= {c.name for c in latest.characters
                                                        if c.action == "line"}, 20.0)
    replays_without(session, tmp_path / "replayed.jsonl", {"mop"}, least=30, aside=())


def test_an_edit_refused_for_a_corrupt_template_applies_once_the_template_is_fixed(tmp_path):
    """The refusal names the template; the technician fixes the template, not the config: the
    edit is validated again at the next look and applied, and the status's config_error goes."""
    cfg_path = _config(tmp_path)
    good = (tmp_path / "line.csv").read_text()
    cfg, _ = last_good.load(cfg_path, kiosk=True)
    runner = Runner(cfg_path, cfg, headless=True, kiosk=True)
    applied = []
    watcher = ConfigWatcher(cfg_path, runner.cfg, runner._load, applied.append, every_s=0.0)
    watcher()
    assert watcher.error is None and not applied
    with open(tmp_path / "line.csv", "a") as f:
        f.write("1e3,0.5\n")
    edited = yaml.safe_load(cfg_path.read_text())
    edited["loop"]["rate_hz"] = 25
    cfg_path.write_text(yaml.safe_dump(edited))
    watcher()
    assert watcher.refused == 1 and "line.csv: line" in watcher.error and not applied
    watcher()                                          # nothing changed: nothing said again
    assert watcher.refused == 1 and not applied
    (tmp_path / "line.csv").write_text(good)
    watcher()
    assert watcher.error is None and [c["loop"]["rate_hz"] for c in applied] == [25]
    watcher()
    assert len(applied) == 1


def test_a_template_copied_in_two_writes_is_followed_whole(tmp_path):
    """The technician's copy of the fixed template arrives in two writes (a slow disk or network
    share) with a look in between, its first half a valid CSV: the action is read once the file
    stayed as it was for a whole look, the whole template, not its first half."""
    cfg_path = _config(tmp_path)
    good = (tmp_path / "line.csv").read_text()
    _corrupt(tmp_path)
    cfg, _ = last_good.load(cfg_path, kiosk=True)
    stage = Runner(cfg_path, cfg, headless=True, kiosk=True)._build(cfg).engines[0]
    now = [0.0]
    reloader = ActionReloader(stage, every_s=1.0, clock=lambda: now[0])
    reloader()
    rows = good.splitlines(keepends=True)
    (tmp_path / "line.csv").write_text("".join(rows[:len(rows) // 2]))
    now[0] = 1.0                                          # a look between the two writes
    reloader()
    with open(tmp_path / "line.csv", "a") as f:
        f.write("".join(rows[len(rows) // 2:]))
    for t in (2.0, 3.0):                                  # seen written, then steady
        assert "line" not in stage.templates["lone"]
        now[0] = t
        reloader()
    whole = load_template(tmp_path / "line.csv", ("dx", "dy"), cfg["engines"][0]["rate_hz"])
    for name in ("walker", "lone"):
        assert np.array_equal(stage.templates[name]["line"][1], whole)
