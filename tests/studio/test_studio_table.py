"""The studio on the table: control markers seen through the synthetic camera drive a take
(record, stop, keep); the library is reloaded when it changes on disk; review sheets."""

import json
import math
from pathlib import Path

import numpy as np
import pytest
import yaml

from behaviors.puppet_master import designers
from tabletop import library
from tabletop.cli import main as cli
from tabletop.config import load_config
from tabletop.kiosk.simulate import SimClock, simulated
from tabletop.studio.targets import PuppetMasterTarget

ROOT = Path(__file__).resolve().parents[2]
RATE = 20.0


def studio_config(tmp_path: Path) -> Path:
    path = tmp_path / "config.yaml"
    path.write_text(yaml.safe_dump({
        "loop": {"rate_hz": RATE},
        "sources": [{"kind": "synthetic_camera", "name": "camera", "pucks": [],
                     "resolution": [480, 270], "fps": RATE, "hands": {"every_s": 0}}],
        "engines": [{"kind": "puppet_master", "name": "pet", "main": {"puck": 1},
                     "designer": {"enabled": True, "library": "lib"}}],
        "view": {"size": [320, 180]},
        "studio": {"enabled": True, "countdown_s": 0.5},
    }))
    return path


def test_control_markers_through_the_camera_record_train_and_keep(tmp_path, capsys):
    demo = designers.demonstrate("lover", seed=3, seconds=12)

    def poses(s):
        i = min(int(np.searchsorted(demo[:, 0], s)), len(demo) - 1)
        r = demo[i]
        out = [(1, r[1], r[2], r[3]), (2, r[4], r[5], r[6])]
        if 0.5 <= s < 4.5:
            out.append((45, 0.06, 0.06, 0.0))        # the record marker, in a corner
        if 5.0 <= s < 6.0:
            out.append((47, 1.14, 0.06, 0.0))        # the keep marker
        return out

    path = studio_config(tmp_path)
    clock = SimClock()
    runner, inst = simulated(load_config(path), path, clock, kiosk=False, studio=True)
    runner.studio.session.wait()   # what the studio loads at start, before the clock runs
    inst.loop.inputs.sources[0].reader.poses = poses
    states = []
    for _ in range(int(6.5 * RATE)):
        frame = inst.loop.tick()
        states.append(frame.character("studio").action)
        assert 45 not in {p.id for p in frame.pucks}    # markers are controls, not inputs
        if states[-1] == "training":     # the worker trains; the take plays from the next tick
            runner.studio.target.trainer.wait(30.0)
        clock.advance(1 / RATE)
    inst.loop.close()
    runner.studio.session.wait()
    order = [s for i, s in enumerate(states) if i == 0 or s != states[i - 1]]
    assert order == ["idle", "countdown", "recording", "training", "trying", "idle"]
    assert states.count("training") == 3      # 0.15 s after the stop, at 20 Hz
    # started 0.3 s (debounce) + 0.5 s (countdown) after the marker was put down at 0.5 s and
    # confirmed by the tracker, stopped 0.3 s after it was lifted at 4.5 s
    rec = [i / RATE for i, s in enumerate(states) if s == "recording"]
    assert 1.3 <= rec[0] <= 1.55 and 4.8 <= rec[-1] <= 5.05
    saved = library.load_behavior(tmp_path / "lib" / "pet")
    take = saved.demonstration
    assert take[-1, 0] == pytest.approx(rec[-1] - rec[0], abs=0.05)
    # the take is the pucks as the camera saw them: within 1 cm of where they were
    i0 = np.searchsorted(demo[:, 0], rec[0])
    truth = demo[i0:i0 + len(take)]
    t_truth = np.interp(take[:, 0] + rec[0], demo[:, 0], demo[:, 1])
    assert np.median(np.abs(take[:, 1] - t_truth)) < 0.01
    assert len(truth) > 0
    log = [json.loads(x) for x in runner.studio.session.path.read_text().splitlines()]
    assert [x["outcome"] for x in log] == ["kept"] and log[0]["name"] == "pet"
    assert (runner.studio.session.folder / log[0]["review"]).stat().st_size > 10_000
    # after a restart the behaviour is in the library and plays
    runner2, inst2 = simulated(load_config(path), path, SimClock(), kiosk=False, studio=True)
    target = runner2.studio.target
    assert target.items() == ["pet"]
    target.use("pet")
    target.between_ticks(math.inf)           # (the loop: the first tick LOAD_S after the pick)
    assert abs(inst2.engines[0].behavior.samples - 40 * take[-1, 0]) <= 2   # at 40 Hz
    inst2.loop.close()
    # the session's contact sheet
    sheet = tmp_path / "sheet.png"
    assert cli(["review", str(runner.studio.session.path), "--out", str(sheet)]) == 0
    assert sheet.stat().st_size > 10_000
    assert "1 try, 1 kept (1.0 tries per kept take)" in capsys.readouterr().out


def test_a_corrupt_behaviour_is_reported_and_skipped_and_a_fix_is_picked_up(tmp_path):
    from tabletop.plugins import puppet_master as pm
    from tabletop.config import validate_config
    from tabletop.registry import BuildContext
    lib = tmp_path / "lib"
    good = library.save_behavior(lib, "good", designers.demonstrate("lover", seconds=4), {})
    bad = library.save_behavior(lib, "bad", designers.demonstrate("afraid", seconds=4), {})
    csv = bad / "demonstration.csv"
    text = csv.read_text()
    cfg = validate_config({"sources": [{"kind": "scripted"}], "engines": [
        {"kind": "puppet_master", "name": "pet", "behavior": str(good),
         "designer": {"enabled": True, "library": str(lib)}}]}, "t.yaml", tmp_path)
    engine = pm.build(cfg["engines"][0], BuildContext((1.2, 0.8), 60.0, cfg, tmp_path))
    target = PuppetMasterTarget(engine)
    target.lib_poller.every_s = target.play_poller.every_s = 0.0
    csv.write_text(text.replace("\n", "\nnot,a,number,row,at,all,x\n", 1))
    problems = target.poll()
    assert len(problems) == 1 and "bad/demonstration.csv" in problems[0] and "line 2" in problems[0]
    assert target.items() == ["bad", "good"]
    target.use("good")                       # the others keep working
    target.between_ticks(math.inf)           # (the loop: the first tick LOAD_S after the pick)
    assert engine.behavior_name == "good"
    csv.write_text(text)                     # fixed on disk: picked up, no restart
    assert target.poll() == []
    target.use("bad")
    target.between_ticks(math.inf)
    assert engine.behavior_name == "bad"
    # the behaviour in play is reloaded when its files change
    before = engine.behavior
    library.save_behavior(lib, "bad", designers.demonstrate("stalker", seconds=5), {},
                          replace=True)
    assert target.poll() == []
    target.between_ticks(math.inf)
    assert engine.behavior is not before
    assert engine.behavior.samples == len(designers.demonstrate("stalker", seconds=5))


def test_review_refuses_a_bad_session_log_in_one_line(tmp_path, capsys):
    log = tmp_path / "s.jsonl"
    log.write_text('{"target": "pet"}\nnot json\n{"target": "pet"}\n')
    assert cli(["review", str(log)]) == 2
    err = capsys.readouterr().err
    assert "s.jsonl:2" in err and len(err.splitlines()) == 1
    assert cli(["review", str(tmp_path / "missing.jsonl")]) == 2


@pytest.mark.parametrize("line, words", [
    ('{"target": "pet", "duration_s": "x"}', "duration_s is 'x', expected a number of seconds"),
    ('{"target": "pet", "training_s": -1}', "training_s is '-1', expected a number"),
    ('{"target": ["pet"]}', "target is \"['pet']\", expected a string"),
    ("not json", "not a session log line"),
    ("[" * 100_000, "not a session log line (nested too deep"),
])
def test_review_names_a_bad_field_of_a_complete_last_line(tmp_path, capsys, line, words):
    # (a wrong field was an internal error; a complete last line that is wrong was skipped as
    # if a power cut had cut it: only a line without its newline is)
    log = tmp_path / "s.jsonl"
    log.write_text('{"target": "pet", "outcome": "kept", "duration_s": 4.0}\n' + line + "\n")
    assert cli(["review", str(log)]) == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and "s.jsonl:2: " in err and words in err, err
    log.write_text('{"target": "pet", "outcome": "kept", "duration_s": 4.0}\n' + line[:12])
    assert cli(["review", str(log)]) == 0               # cut short: the tries before it


@pytest.mark.parametrize("text, code, words", [
    ("KEPT\n\n  \n", 0, None),    # an editor's blank lines at the end
    ("KEPT\n\nKEPT\n", 2, "s.jsonl:2: a blank line between tries"),
    ('{"format": "tabletop-session", "version": 3}\n', 2,
     "s.jsonl: a session recording (`tabletop replay` plays it), not a studio session log"),
])
def test_review_of_blank_lines_and_of_a_recording(tmp_path, capsys, text, code, words):
    # (a blank line said JSON's "Expecting value"; a recording "not a session log line (not a
    # try)")
    log = tmp_path / "s.jsonl"
    log.write_text(text.replace("KEPT", '{"target": "pet", "outcome": "kept", "duration_s": 4}'))
    assert cli(["review", str(log), "--out", str(tmp_path / "sheet.png")]) == code
    err = capsys.readouterr().err.strip().splitlines()
    assert (err == []) if words is None else (len(err) == 1 and words in err[0]), err


@pytest.mark.parametrize("columns, words", [
    ("", "--columns: the value is empty"),            # (both were argparse's "invalid int
    ("x", "--columns 'x' is not a whole number"),     # value: ''", unlike every other number)
    ("0", "--columns '0' must be a whole number of sheets per row from 1 to 1e+06"),
])
def test_review_columns_that_are_no_count_are_named(tmp_path, capsys, columns, words):
    log = tmp_path / "s.jsonl"
    log.write_text('{"target": "pet", "outcome": "kept", "duration_s": 4.0}\n')
    assert cli(["review", str(log), "--columns", columns]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"tabletop review: error: {words}"), err


@pytest.mark.parametrize("name", ["sheet.jpg", "sheet.txt", "sheet"])
def test_review_refuses_a_sheet_name_that_is_no_png(tmp_path, capsys, name):
    # the sheet is PNG bytes: under a .jpg name a viewer refuses or misreads it
    log = tmp_path / "s.jsonl"
    log.write_text('{"target": "pet", "outcome": "kept", "duration_s": 4.0}\n')
    assert cli(["review", str(log), "--out", str(tmp_path / name)]) == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and "written as PNG" in err and "sheet.png" in err, err
    assert not (tmp_path / name).exists()


def test_review_sheet_title_stays_on_the_sheet(tmp_path):
    # the summary was one centred line wider than a one-try sheet: cut at both edges
    import matplotlib.image as mpimg
    log = tmp_path / "session-20261203-071321.jsonl"
    log.write_text('{"target": "lover", "outcome": "kept", "name": "lover", "duration_s": 10.7, '
                   '"samples": 246, "training_s": 0.217}\n')
    out = tmp_path / "sheet.png"
    assert cli(["review", str(log), "--out", str(out)]) == 0
    img = mpimg.imread(str(out))[..., :3].sum(axis=2)           # white 3.0, text darker
    top = img[: img.shape[0] // 8]                               # the title's band
    assert (top < 2.0).any()                                     # the title is drawn
    assert (top[:, :4] > 2.9).all() and (top[:, -4:] > 2.9).all()   # within the edges


def test_review_with_more_columns_than_tries_draws_the_tries_wide(tmp_path, capsys):
    """--columns 100000 on a two-try log drew a figure 100,000 sheets wide (minutes, gigabytes);
    the sheet is as wide as its tries."""
    import matplotlib.image as mpimg
    log = tmp_path / "s.jsonl"
    log.write_text('{"target": "pet", "outcome": "kept"}\n{"target": "pet"}\n')
    widths = []
    for columns in ("2", "100000"):
        out = tmp_path / f"sheet-{columns}.png"
        assert cli(["review", str(log), "--columns", columns, "--out", str(out)]) == 0
        widths.append(mpimg.imread(str(out)).shape[1])
    assert widths[0] == widths[1] and "2 tries, 1 kept" in capsys.readouterr().out


def test_a_playing_behaviour_outside_the_studio_is_reloaded_or_kept(tmp_path):
    from tabletop.config import validate_config
    from tabletop.frames import Frame
    from tabletop.plugins import puppet_master as pm
    from tabletop.registry import BuildContext
    from tabletop.studio.reloader import BehaviorReloader
    folder = library.save_behavior(tmp_path, "x", designers.demonstrate("lover", seconds=4), {})
    good_yaml = (folder / "behavior.yaml").read_bytes()
    cfg = validate_config({"sources": [{"kind": "scripted"}], "engines": [
        {"kind": "puppet_master", "name": "pet", "behavior": str(folder)}]}, "t.yaml", tmp_path)
    engine = pm.build(cfg["engines"][0], BuildContext((1.2, 0.8), 60.0, cfg, tmp_path))
    hook = BehaviorReloader(engine)
    hook.poller.every_s = 0.0                   # looks at every call (the loop: once a second)
    first = engine.behavior
    (folder / "behavior.yaml").write_text("format: [\n")
    hook()
    hook.wait()
    assert engine.behavior is first and "behavior.yaml" in hook.problem
    assert "still playing" in engine.step(Frame(seq=0, t=1.0))[0].label
    (folder / "behavior.yaml").write_bytes(good_yaml)       # fixed: reloaded, label back
    hook()
    hook.wait()                                 # (the loop: the first tick after the worker)
    assert hook.problem == "" and engine.behavior is not first
    from tabletop.frames import Puck
    assert "playing x" in engine.step(Frame(seq=1, t=1.1, pucks=(Puck(1, 0.3, 0.3, 0.0),)))[0].label


def test_an_edit_saved_between_build_and_its_watchers_is_seen(tmp_path):
    """The behaviour folder's watchers (the reloader outside the studio, the studio's target)
    are made after the engine read the folder (seconds later at a cold start): their first
    look compares with the folder as it was read, so an edit saved in between is refused or
    reloaded (with the edited folder as their baseline, the edit would never be seen)."""
    from tabletop.config import validate_config
    from tabletop.plugins import puppet_master as pm
    from tabletop.registry import BuildContext
    from tabletop.studio.reloader import BehaviorReloader
    folder = library.save_behavior(tmp_path, "x", designers.demonstrate("lover", seconds=4), {})
    cfg = validate_config({"sources": [{"kind": "scripted"}], "engines": [
        {"kind": "puppet_master", "name": "pet", "behavior": str(folder), "main": {"puck": 1},
         "designer": {"enabled": True, "library": "lib"}}]}, "t.yaml", tmp_path)
    engine = pm.build(cfg["engines"][0], BuildContext((1.2, 0.8), 60.0, cfg, tmp_path))
    (folder / "behavior.yaml").write_text("format: [\n")     # saved while the rest starts
    hook = BehaviorReloader(engine)
    hook()
    hook.wait()
    assert "behavior.yaml" in (hook.problem or "")
    target = PuppetMasterTarget(engine)
    target.play_poller.every_s = 0.0
    target.poll()
    target.between_ticks(math.inf)              # (read in the loader: said at its swap)
    assert any("behavior.yaml" in p for p in target.poll())


def test_an_action_review_sheet_shows_the_take_and_its_followed_progress(tmp_path):
    from tabletop.files import read_csv
    from tabletop.studio.review import followed_progress, review_sheet
    _, g = read_csv(ROOT / "examples" / "mop" / "gestures" / "circle.csv")
    take = g[::2, 1:3]                     # dx, dy at 30 Hz
    truth, got = followed_progress(take)
    assert np.abs(truth - got)[len(got) // 4:].mean() < 0.1   # the follower keeps up
    review_sheet("action", take, tmp_path / "try.png", title="lizard: kept take1")
    assert (tmp_path / "try.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_scripted_key_events_through_the_view_record_train_try_and_keep(tmp_path):
    """Key presses posted to pygame, read by the view, queued for the loop, handled by the
    studio: R (countdown, then record), R (stop: trained, trying), K (kept)."""
    import pygame
    path = tmp_path / "config.yaml"
    path.write_text(yaml.safe_dump({
        "loop": {"rate_hz": RATE},
        "sources": [{"kind": "scripted", "pucks": [1, 2]}],
        "engines": [{"kind": "puppet_master", "name": "pet", "main": {"puck": 1},
                     "designer": {"enabled": True, "library": "lib"}}],
        "view": {"size": [320, 180]},
        "studio": {"countdown_s": 1.0, "review": False},
    }))
    clock = SimClock()
    runner, inst = simulated(load_config(path), path, clock, kiosk=False, studio=False)
    keys = {int(1 * RATE): pygame.K_r, int(5 * RATE): pygame.K_r, int(7 * RATE): pygame.K_k}
    states = []
    for i in range(int(8 * RATE)):
        if i in keys:
            pygame.event.post(pygame.event.Event(pygame.KEYDOWN, key=keys[i], mod=0,
                                                 unicode="", scancode=0))
        states.append(inst.loop.tick().character("studio").action)
        if states[-1] == "training":     # the worker trains; the take plays from the next tick
            runner.studio.target.trainer.wait(30.0)
        clock.advance(1 / RATE)
    inst.loop.close()
    order = [s for i, s in enumerate(states) if i == 0 or s != states[i - 1]]
    assert order == ["idle", "countdown", "recording", "training", "trying", "idle"]
    take = library.load_behavior(tmp_path / "lib" / "pet").demonstration
    # pressed at 1 s (read by the view that tick, handled the next), 1 s countdown, stopped at 5 s
    assert take[-1, 0] == pytest.approx(3.0, abs=2.5 / RATE)


def test_studio_mode_gives_a_reactor_on_puck_2_another_puck_to_demonstrate_with(tmp_path):
    """``--studio`` makes every reactor a designer target; one whose main is puck 2 (the
    default reactor puck) demonstrates its reaction with puck 1, not with its main puck."""
    from tabletop.studio.build import studio_targets
    from tests.puppet_master.test_plugin import build

    entries = [{"kind": "puppet_master", "name": n, "behavior": "behaviors/library/lover",
                "main": {"puck": p}} for n, p in (("on_one", 1), ("on_two", 2))]
    cfg = {"engines": [dict(e, designer={"enabled": False}) for e in entries]}
    targets = studio_targets(build(entries), cfg, tmp_path, all_engines=True)
    pucks = {t.engine.name: (t.main_puck, t.react_puck) for t in targets}
    assert pucks == {"on_one": (1, 2), "on_two": (2, 1)}


MAINS = {"nearest_3_1": {"nearest": [{"puck": 3}, {"puck": 1}]},
         "first_2": {"first": [{"puck": 2}, {"touch": 4}]},
         "first_character": {"first": [{"character": "on_one"}, {"puck": 3}]}}


def test_studio_mode_takes_the_main_puck_of_several_mains_as_designer_mode_does(tmp_path):
    """A reactor bound to several mains is demonstrated in studio mode with the main puck its
    own designer mode takes (the first binding's puck, else puck 1), not always puck 1."""
    from tabletop.studio.build import studio_targets
    from tests.puppet_master.test_plugin import build

    entries = [{"kind": "puppet_master", "name": "on_one", "behavior": "behaviors/library/lover",
                "main": {"puck": 1}}]
    entries += [{"kind": "puppet_master", "name": n, "behavior": "behaviors/library/lover",
                 "main": m} for n, m in MAINS.items()]
    cfg = {"engines": [dict(e, designer={"enabled": False}) for e in entries]}
    studio = {t.engine.name: t.main_puck
              for t in studio_targets(build(entries), cfg, tmp_path, all_engines=True)}
    designed = [dict(e, designer={"enabled": True, "library": str(tmp_path / "lib"),
                                  "sequential": True}) for e in entries]
    own = {e.name: e.designer["main_puck"] for e in build(designed)}
    assert studio == own == {"on_one": 1, "nearest_3_1": 3, "first_2": 2, "first_character": 1}


def test_studio_mode_keeps_the_takes_of_a_reactor_whose_name_no_folder_may_have(tmp_path):
    """``--studio`` keeps a reactor's takes under its engine's name; for one named "mein
    Liebling" K refused every take (the name is no folder's), now they are "behaviour"."""
    from tabletop.studio.build import studio_targets
    from tabletop.studio.machine import Studio
    from tabletop.frames import Frame, Puck
    from tests.puppet_master.test_plugin import build

    entries = [{"kind": "puppet_master", "name": n, "behavior": "behaviors/library/lover"}
               for n in ("mein Liebling", "pet")]
    cfg = {"engines": [dict(e, designer={"enabled": False, "library": str(tmp_path / "lib")})
                       for e in entries]}
    targets = studio_targets(build(entries), cfg, tmp_path, all_engines=True)
    assert [t.engine.designer["name"] for t in targets] == ["behaviour", "pet"]
    studio = Studio(targets[:1], countdown_s=0.0)
    demo = designers.demonstrate("lover", seed=2, seconds=4)
    for i, row in enumerate(demo):
        studio(Frame(seq=i, t=100.0 + row[0], pucks=(Puck(1, *row[1:4]), Puck(2, *row[4:7])),
                     commands=("designer.record",) if i in (0, len(demo) - 1) else ()))
    studio(Frame(seq=len(demo), t=100.5 + demo[-1, 0]))     # trained in its worker: in play
    studio.command("designer.keep")
    assert studio.message == "kept as behaviour in library/"   # (the default, the config's)
    assert library.list_behaviors(targets[0].lib) == ["behaviour"]


def test_review_cells_are_as_tall_as_their_sheets(tmp_path):
    """The contact sheet's cells were 400 x 360 px for sheets of 640 x 288 scaled to 176 px
    tall: 146 px of every cell blank, the sheet half empty. A cell is its caption and its
    sheet: no white band between one row's sheets and the next row's caption."""
    import matplotlib.image as mpimg
    import numpy as np
    from PIL import Image
    Image.new("RGB", (640, 288), (90, 90, 90)).save(tmp_path / "try.png")
    log = tmp_path / "s.jsonl"
    log.write_text('{"target": "pet", "outcome": "kept", "review": "try.png"}\n' * 3)
    out = tmp_path / "sheet.png"
    assert cli(["review", str(log), "--columns", "1", "--out", str(out)]) == 0
    img = mpimg.imread(str(out))[..., :3].sum(axis=2)
    grey = np.flatnonzero((np.abs(img - 3 * 90 / 255) < 0.05).sum(axis=1) > 300)  # sheets' rows
    assert len(grey) >= 3 * 150, len(grey)
    white = (img > 2.95).all(axis=1)
    runs, n = [], 0
    for w in white[grey[0]:]:            # from the first sheet down: blank rows in a row
        n = n + 1 if w else 0
        runs.append(n)
    assert max(runs) < 40, max(runs)     # a caption's margins, never a blank band
    assert img.shape[0] < 3 * 260, img.shape


def test_review_and_replay_given_the_studios_other_files_name_the_one_to_give(tmp_path,
                                                                             capsys):
    """A take saved at quit or a review sheet given to ``review`` said "not a session log line
    (Expecting value: line 1 column 1 (char 0))", and a studio session log given to ``replay``
    "line 1: not a tabletop-session header": each names what it is and the file to give."""
    log = tmp_path / "session-20260101-120000.jsonl"
    log.write_text('{"target": "pet", "outcome": "quit", "duration_s": 4.0, '
                   '"take": "session-20260101-120000-take001.csv"}\n')
    (tmp_path / "session-20260101-120000-take001.csv").write_text("t,main_x\n0,0\n")
    (tmp_path / "session-20260101-120000-take001-react.csv").write_text("t,react_x\n0,0\n")
    (tmp_path / "session-20260101-120000-try001.png").write_bytes(b"\x89PNG\r\n\x1a\n\0\0")
    assert cli(["review", str(tmp_path)]) == 2       # the studio folder: its latest log named
    assert capsys.readouterr().err.splitlines()[-1].endswith(
        f"{tmp_path}: is a folder, expected a studio session log (.jsonl); its latest is {log}")
    for name, what in (("take001.csv", "a take saved at quit"),
                       ("take001-react.csv", "a take saved at quit"),
                       ("try001.png", "a try's review sheet")):
        assert cli(["review", str(tmp_path / f"session-20260101-120000-{name}")]) == 2
        err = capsys.readouterr().err.splitlines()
        assert len(err) == 1 and f"{name}: {what}, not a studio session log; its log is " \
            f"{log}" in err[0], err
    assert cli(["replay", str(log), "--headless", "--fast"]) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and f"{log}: a studio session log (its tries: `tabletop review` " \
        "draws them), not a session recording" in err[0], err
    assert cli(["review", str(log), "--out", str(tmp_path / "sheet.png")]) == 0   # as said


def test_review_tells_a_recording_by_its_first_line_and_refuses_what_is_no_log(tmp_path,
                                                                                capsys):
    """A session recording given to review was read whole before it was told apart by its
    first line (266 MB: 14 s and 573 MB of memory; a kiosk's hour 1.9 GB); a device was "not
    found"."""
    import tracemalloc
    rec = tmp_path / "rec.jsonl"
    with rec.open("wb") as f:
        f.write(b'{"format": "tabletop-session", "version": 2}\n')
        f.truncate(150 * 2**20)                    # (sparse: made at once)
    tracemalloc.start()
    try:
        assert cli(["review", str(rec)]) == 2
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "rec.jsonl: a session recording (`tabletop replay` plays it)" \
        in err[0], err
    assert peak < 20 * 2**20, peak                 # its first line, not its 150 MB
    big = tmp_path / "big.jsonl"
    with big.open("wb") as f:
        f.write(b'{"target": "pet", "outcome": "kept", "duration_s": 4}\n')
        f.truncate(129 * 2**20)
    assert cli(["review", str(big)]) == 2
    assert "big.jsonl: over 128 MB, more than a studio session log holds" in \
        capsys.readouterr().err
    assert cli(["review", "/dev/null"]) == 2
    assert "/dev/null: not a regular file" in capsys.readouterr().err
