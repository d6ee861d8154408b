"""What a Puppet Master take recorded at the table tells the designer: a take where neither
puck moved, or the reactor's did not, is refused (it trained a character that stands still,
and K kept it), and a take
whose reactor puck was lost part of the time says how long (those stretches are left out)."""

import json

import numpy as np

from behaviors.puppet_master import designers
from tabletop import library
from tabletop.frames import Frame, Puck
from tabletop.studio.build import left_words
from tabletop.studio.session import left_at_quit

from tests.studio.test_studio_keys import Bench, designer


def take(tmp_path, demo, react_seen=lambda i: True, base=None, **extra):
    """Record ``demo`` (R at its 5th and 5th-last frame) and press K; (labels, bench)."""
    (e,) = designer(tmp_path, **extra)
    bench = Bench([e], tmp_path)
    bench.studio.target.base = base
    n, labels = len(demo), []
    for i, row in enumerate(demo):
        pucks = (Puck(1, *row[1:4]),) + ((Puck(2, *row[4:7]),) if react_seen(i) else ())
        cmd = ("designer.record",) if i in (5, n - 5) else ()
        labels.append(bench.step(Frame(seq=i, t=100.0 + row[0], pucks=pucks,
                                       commands=cmd))[1].label)
    bench.studio.command("designer.keep")
    return labels, bench


def tried(tmp_path, demo, **extra):
    """Record ``demo`` whole (R at its first and last frame), not kept: the bench."""
    (e,) = designer(tmp_path, **extra)
    bench = Bench([e], tmp_path)
    n = len(demo)
    for i, row in enumerate(demo):
        bench.step(Frame(seq=i, t=100.0 + row[0], pucks=(Puck(1, *row[1:4]), Puck(2, *row[4:7])),
                         commands=("designer.record",) if i in (0, n - 1) else ()))
    return bench


def test_a_take_where_neither_puck_moved_is_refused_and_one_puck_moving_is_trained(tmp_path):
    demo = designers.demonstrate("lover", seed=3, seconds=3)
    still = demo.copy()
    still[:, 1:] = demo[0, 1:]
    still[:, 1] += 0.002 * (-1) ** (still[:, 0] * 40).astype(int)    # 2 mm of tracking jitter
    labels, bench = take(tmp_path / "a", still)
    assert ("neither puck moved (puck 1 0.4 cm, puck 2 0.0 cm from where the take began): "
            "R to record again") in labels[-5], labels[-5]
    assert bench.studio.message == "nothing to keep: R records a take"
    assert library.list_behaviors(tmp_path / "a" / "lib") == []
    logged = [json.loads(x) for x in bench.session.path.read_text().splitlines()]
    assert [x["outcome"] for x in logged] == ["refused"]
    watcher = demo.copy()                        # the reactor only turns to look: a reaction
    watcher[:, 1:3], watcher[:, 4:6] = demo[0, 1:3], demo[0, 4:6]
    watcher[:, 6] = demo[0, 6] + 0.8 * (watcher[:, 0] / watcher[-1, 0])
    labels, _ = take(tmp_path / "b", watcher)
    assert "trained" in labels[-5], labels[-5]
    reactor = demo.copy()                        # a still main, a reactor walking off
    reactor[:, 1:4] = demo[0, 1:4]
    labels, bench = take(tmp_path / "c", reactor)
    assert "trained" in labels[-5] and library.list_behaviors(tmp_path / "c" / "lib") == ["pet"]


def test_a_take_whose_reactor_puck_was_left_still_is_refused(tmp_path):
    # the main walks, the reactor puck lies where it was put down (a millimetre of jitter):
    # the character trained would stand still whatever the visitor does
    demo = designers.demonstrate("lover", seed=3, seconds=3)
    forgotten = demo.copy()
    forgotten[:, 4:7] = demo[0, 4:7]
    forgotten[:, 4] += 0.001 * (-1) ** (forgotten[:, 0] * 40).astype(int)
    labels, bench = take(tmp_path / "a", forgotten)
    assert ("the reactor, puck 2, never moved (0.2 cm from where the take began, turned 0.00 "
            "rad): its character would stand still: R to record again") in labels[-5], labels[-5]
    assert library.list_behaviors(tmp_path / "a" / "lib") == []
    # the same take with the reactor moving 3 cm is a demonstration
    forgotten[:, 4] += 0.03 * forgotten[:, 0] / forgotten[-1, 0]
    labels, _ = take(tmp_path / "b", forgotten)
    assert "trained" in labels[-5], labels[-5]


def test_a_take_whose_reactor_was_lost_half_the_time_says_how_long(tmp_path):
    demo = designers.demonstrate("lover", seed=3, seconds=6)     # 40 Hz
    labels, _ = take(tmp_path / "a", demo, react_seen=lambda i: (i // 20) % 2 == 0)
    assert "; puck 2 unseen 2.9 s of 5.7 s (left out); try it" in labels[-5], labels[-5]
    labels, _ = take(tmp_path / "b", demo, react_seen=lambda i: i % 100 != 50)  # one frame
    assert "unseen" not in labels[-5] and "trained" in labels[-5], labels[-5]
    # never seen: "take too short (0.0 s of both pucks)" of 6 s recorded, said why
    labels, _ = take(tmp_path / "c", demo, react_seen=lambda i: False)
    assert ("take too short (0.0 s of both pucks, needs 2 s; puck 2 unseen 5.7 s of 5.7 s): R "
            "to record again") in labels[-5], labels[-5]


def test_a_sequential_take_counts_only_the_puck_each_part_needs(tmp_path):
    # the main part needs puck 1 alone, the reaction puck 2 alone; the pause between the
    # parts is no recording time; the reaction part ends with the main's playback. Puck 2 is
    # counted against the reaction it was needed in, the 2.8 s the line trains (it was said
    # "of 5.7 s", both parts, beside "trained 75 samples (2.8 s)")
    demo = designers.demonstrate("lover", seed=3, seconds=8)
    (e,) = designer(tmp_path, sequential=True)
    bench = Bench([e], tmp_path)
    keys = {5: "designer.record", 120: "designer.record", 160: "designer.record"}
    labels = []
    for i, row in enumerate(demo):
        lost = 200 <= i < 240                                    # puck 2 lost 1 s
        pucks = (Puck(1, *row[1:4]),) + (() if i < 160 or lost else (Puck(2, *row[4:7]),))
        labels.append(bench.step(Frame(seq=i, t=100.0 + row[0], pucks=pucks, commands=(
            keys[i],) if i in keys else ()))[1].label)
    said = next(lab for lab in labels if "trained" in lab)    # the playback's end stopped it
    assert "trained 75 samples (2.8 s); puck 2 unseen 1.0 s of 2.8 s (left out)" in said, said
    assert "puck 1" not in said, said


def test_the_keep_says_where_the_take_was_saved(tmp_path, monkeypatch):
    # "kept as pet" named no folder: the designer had to know the engine's library setting
    demo = designers.demonstrate("lover", seed=3, seconds=3)
    monkeypatch.chdir(tmp_path)                  # no config's folder: the working folder's
    _, bench = take(tmp_path / "here", demo)
    assert bench.studio.message == "kept as pet in here/lib/"
    assert library.list_behaviors(tmp_path / "here" / "lib") == ["pet"]
    # as the studio is built: relative to the config's folder (a replay's temporary one
    # names it as the run did), the whole path when outside it
    _, bench = take(tmp_path / "away", demo, base=tmp_path / "away")
    assert bench.studio.message == "kept as pet in lib/"
    _, bench = take(tmp_path / "away", demo, base=tmp_path / "here")
    assert bench.studio.message == f"kept as pet-2 in {tmp_path / 'away' / 'lib'}/"


def test_a_take_dropped_while_it_trains_is_logged_with_its_samples(tmp_path):
    # X, R or Esc while the worker trained logged "samples": 0 (and drew no review sheet)
    demo = designers.demonstrate("lover", seed=3, seconds=3)
    bench, n = tried(tmp_path, demo, background_training=True), len(demo)
    assert bench.studio.state == "training"
    bench.studio.close()                          # Esc: the run ends
    (line,) = [json.loads(x) for x in bench.session.path.read_text().splitlines()]
    assert line["outcome"] == "quit" and line["samples"] == n - 1, line


def test_k_during_a_take_says_to_stop_it_first(tmp_path):
    """K while recording says to stop the take first (R then K); K in the countdown says the
    take has not begun (R there cancels it, it does not stop a take)."""
    demo = designers.demonstrate("lover", seed=3, seconds=3)
    (e,) = designer(tmp_path)
    bench = Bench([e], tmp_path)
    said = []
    for i, row in enumerate(demo[:60]):
        cmds = {0: ("designer.record",), 50: ("designer.keep",)}.get(i, ())
        said.append(bench.step(Frame(seq=i, t=100.0 + row[0], pucks=(
            Puck(1, *row[1:4]), Puck(2, *row[4:7])), commands=cmds))[1])
    assert said[50].action == "recording"
    assert "nothing to keep yet: R stops the take, then K keeps it" in said[50].label
    from tabletop.studio.machine import Studio
    from tabletop.studio.targets import PuppetMasterTarget
    studio = Studio([PuppetMasterTarget(designer(tmp_path / "c")[0])], countdown_s=1.0)
    said = []
    for i in range(10):                          # 20 Hz: R at 0 s, K at 0.25 s
        cmds = {0: ("designer.record",), 5: ("designer.keep",)}.get(i, ())
        frame = Frame(seq=i, t=100.0 + i / 20, commands=cmds,
                      pucks=(Puck(1, 0.3, 0.3, 0.0), Puck(2, 0.5, 0.3, 0.0)))
        said.append(studio(frame).character("studio"))
    assert said[5].action == "countdown"
    assert ("nothing to keep yet: the take starts when the countdown ends (R cancels it)"
            in said[5].label), said[5].label


def test_the_record_marker_lifted_during_the_countdown_says_it_cancelled(tmp_path):
    # R during the countdown said "countdown cancelled"; the record marker lifted (or a hand
    # over it for the debounce time) ended the countdown without a word
    from tabletop.studio.build import Markers
    from tabletop.studio.machine import Studio
    from tabletop.studio.targets import PuppetMasterTarget
    (e,) = designer(tmp_path)
    studio = Studio([PuppetMasterTarget(e)], countdown_s=3.0)
    markers = Markers({"record": 45}, studio, debounce_s=0.3)
    said = []
    for i in range(60):                          # 20 Hz; the marker on from 0 s to 1 s
        t = 100.0 + i / 20
        pucks = (Puck(1, 0.3, 0.3, 0.0), Puck(2, 0.5, 0.3, 0.0)) + (
            (Puck(45, 0.06, 0.06, 0.0),) if i < 20 else ())
        said.append(studio(markers(Frame(seq=i, t=t, pucks=pucks))).character("studio"))
    assert said[10].action == "countdown"
    gone = next(c for i, c in enumerate(said) if i > 10 and c.action == "idle")
    assert "countdown cancelled" in gone.label, gone.label


def test_a_reactor_puck_lifted_while_recording_leaves_its_character_where_it_was_seen(tmp_path):
    """Lifting the reactor puck mid-take slid its character to the table's centre (seen in an
    Xvfb snapshot: 0.25 m in 1.5 s) and back when the puck came down: it stays, calmer, where
    the puck was last seen."""
    import numpy as np
    import pygame
    from tabletop.renderer import Renderer
    (e,) = designer(tmp_path)
    bench = Bench([e], tmp_path)
    demo = designers.demonstrate("lover", seed=4, seconds=6)
    renderer, surface = Renderer((1.2, 0.8), (640, 360), margin=24), pygame.Surface((640, 360))
    lifted = range(120, 200)
    last, drawn = None, []
    for i, row in enumerate(demo[:200]):
        pucks = (Puck(1, *row[1:4]),) + (() if i in lifted else (Puck(2, *row[4:7]),))
        if i not in lifted:
            last = row[4:6]
        chars, _ = bench.step(Frame(seq=i, t=100.0 + row[0], pucks=pucks,
                                    commands=("designer.record",) if i == 5 else ()))
        if i in lifted:
            c = chars["pet"]
            assert np.hypot(c.x - last[0], c.y - last[1]) < 1e-9 and not c.valid
            renderer.draw(surface, Frame(seq=i, t=100.0 + row[0], characters=(c,)))
            img = pygame.surfarray.array3d(surface).astype(int)
            pink = np.argwhere((img[..., 0] > 150) & (img[..., 0] > img[..., 2] + 40))
            drawn.append(pink.mean(axis=0) if len(pink) > 100 else None)
    assert bench.studio.state == "recording"
    seen = renderer.map.point(*last)
    # the body drawn where its puck was last seen, to the end of the lift (measured: 67 px
    # off, 17 cm, at the centre; under 1 px now)
    assert all(d is not None for d in drawn[20:])      # (faded in over its first frames)
    assert max(np.hypot(*(d - seen)) for d in drawn[20:]) < 6


def test_a_sequential_main_part_leaves_the_character_where_it_stood(tmp_path):
    """Recording the main alone (sequential training, no reactor puck on the table), the
    character stays where it stood when the take began until the reaction part (without it,
    it jumped to the table's centre at the countdown's end and stood there)."""
    import numpy as np
    lib = tmp_path / "lib"
    library.save_behavior(lib, "a", designers.demonstrate("lover", seconds=6), {})
    (e,) = designer(tmp_path, sequential=True)
    bench = Bench([e], tmp_path)
    bench.studio.command("designer.item_next")          # plays "a"
    demo = designers.demonstrate("lover", seed=4, seconds=8)
    before = None
    for i, row in enumerate(demo[:300]):
        chars, studio = bench.step(Frame(seq=i, t=100.0 + row[0], pucks=(Puck(1, *row[1:4]),),
                                         commands=("designer.record",) if i == 100 else ()))
        c = chars["pet"]
        if i == 99:                                    # the last tick before the take
            before = (c.x, c.y)
        if i >= 100:
            assert studio.action == "recording"
            assert np.hypot(c.x - before[0], c.y - before[1]) < 1e-9, (i, c.x, c.y, before)
    assert np.hypot(before[0] - 0.6, before[1] - 0.4) > 0.05    # not the centre by chance


def test_a_take_tried_at_quit_is_saved_beside_the_session_log(tmp_path, caplog):
    """Esc (the studio's close) while a take was tried left only its session log line: the
    demonstration was lost. It is saved beside the log (atomically, the CSV ``behave --train``
    takes), named in the log line, the log and the overlay, and is no library behaviour."""
    from tabletop.cli import main as cli
    demo = designers.demonstrate("lover", seed=3, seconds=4)
    bench = tried(tmp_path, demo)
    assert bench.studio.state == "trying"
    trained = bench.studio.target.demo.copy()
    with caplog.at_level("INFO", logger="tabletop"):
        bench.studio.close()                          # Esc: the run ends
    (line,) = [json.loads(x) for x in bench.session.path.read_text().splitlines()]
    saved = bench.session.folder / line["take"]
    assert line["outcome"] == "quit" and saved.name == \
        bench.session.path.stem + "-take001.csv", line
    assert left_words(*left_at_quit(saved.parent), tmp_path) == "studio: the last session's " \
        f"take tried, not kept, at quit is in studio/{saved.name} (not in the library)"
    assert bench.studio.message == f"pet: take tried, not kept; saved as {saved} (not in the " \
        "library)"
    assert any(f"take tried, not kept, at quit; saved as {saved}" in r.getMessage()
               for r in caplog.records), caplog.text
    assert (library.read_demonstration(saved) == trained).all()     # the take, all of it
    assert library.list_behaviors(tmp_path / "lib") == []         # nothing loads it
    assert sorted(p.name for p in saved.parent.iterdir()) == sorted(
        [saved.name, bench.session.path.name])
    rows = tmp_path / "main.csv"
    rows.write_text("t,main_x,main_y,main_dir\n" + "".join(
        f"{r[0]},{r[1]},{r[2]},{r[3]}\n" for r in demo[::10]))
    assert cli(["behave", "--train", str(saved), "--input", str(rows),
                "--out", str(tmp_path / "o.csv")]) == 0   # got back: trained from the file


def quit_while(tmp_path, demo, keys, caplog, **extra):
    """Step ``demo`` with R at the frames ``keys``, then Esc (the studio's close): (the bench,
    its session log's lines, the log's text)."""
    countdown = dict(extra.pop("countdown", ()))     # frame -> the countdown set and R pressed
    (e,) = designer(tmp_path, **extra)
    bench = Bench([e], tmp_path)
    for i, row in enumerate(demo):
        if i in countdown:
            bench.studio.countdown_s, keys = countdown[i], {*keys, i}
        bench.step(Frame(seq=i, t=100.0 + row[0], pucks=(Puck(1, *row[1:4]), Puck(2, *row[4:7])),
                         commands=("designer.record",) if i in keys else ()))
    with caplog.at_level("INFO", logger="tabletop"):
        bench.studio.close()
    path = bench.session.path
    lines = [json.loads(x) for x in path.read_text().splitlines()] if path.exists() else []
    return bench, lines, caplog.text


def test_a_take_still_recorded_at_quit_is_saved_when_long_enough(tmp_path, caplog):
    """A take still recorded at Esc (or a sequential take's main part waiting for its
    reaction) was dropped, "take cancelled at quit": it is saved beside the session log as a
    tried one is, named in its log line; one too short to train says so and saves nothing."""
    from tabletop.cli import main as cli
    demo = designers.demonstrate("lover", seed=3, seconds=4)            # 160 frames at 40 Hz
    bench, (line,), text = quit_while(tmp_path / "a", demo, {10}, caplog)
    saved = bench.session.folder / line["take"]
    assert line["outcome"] == "quit" and saved.name == bench.session.path.stem + "-take001.csv"
    assert line["duration_s"] == round(demo[-1, 0] - demo[10, 0], 3) == 3.725, line
    assert f"pet: take recorded, not tried, at quit; saved as {saved}" in text, text
    assert np.allclose(library.read_demonstration(saved)[:, 1:], demo[10:, 1:])
    rows = tmp_path / "main.csv"
    rows.write_text("t,main_x,main_y,main_dir\n" + "".join(
        f"{r[0]},{r[1]},{r[2]},{r[3]}\n" for r in demo[::10]))
    assert cli(["behave", "--train", str(saved), "--input", str(rows),
                "--out", str(tmp_path / "o.csv")]) == 0
    assert library.list_behaviors(tmp_path / "a" / "lib") == []         # nothing loads it
    # the main part of a sequential take, waiting for its reaction: behave --train-main's file
    bench, (line,), text = quit_while(tmp_path / "s", demo, {10, 120}, caplog, sequential=True)
    assert bench.studio.state == "idle" and "take recorded, not tried, at quit" in text
    main = (bench.session.folder / line["take"]).read_text().splitlines()
    assert main[0] == "t,main_x,main_y,main_dir" and len(main) == 1 + 110, main[:2]
    assert [float(v) for v in main[1].split(",")] == [0.0, *demo[10, 1:4]]
    assert line["take_state"] == "ready" and "take_reaction" not in line
    bench, (line,), _ = quit_while(tmp_path / "w", demo[:110], {10, 100}, caplog,
                                   sequential=True, countdown=[(105, 5.0)])
    assert bench.studio.state == "idle" and line["take_state"] == "ready", line   # (counting
    # down to the reaction: the take still waits between its parts)
    # its reaction cut short (R again at frame 101; Esc 59 frames into the 90-frame
    # playback): saved beside the main part, on its times, the two pair as behave's files
    bench, (line,), text = quit_while(tmp_path / "r", demo, {10, 100, 101}, caplog,
                                      sequential=True)
    folder = bench.session.folder
    react = folder / line["take_reaction"]
    assert line["take_state"] == "recording" and react.name == line["take"][:-4] + "-react.csv"
    assert f"its reaction so far as {react}" in text, text
    rows = react.read_text().splitlines()
    assert rows[0] == "t,react_x,react_y,react_dir" and 55 <= len(rows) - 1 <= 59, rows[:2]
    assert [float(v) for v in rows[1].split(",")][1:] == list(demo[101, 4:7])
    assert cli(["behave", "--train-main", str(folder / line["take"]), "--train-react",
                str(react), "--input", str(tmp_path / "main.csv"),
                "--out", str(tmp_path / "o2.csv")]) == 0
    from tabletop.studio.review import caption            # the contact sheet: no training
    assert caption(line).endswith(", recorded, not tried: take001.csv and its reaction")
    # the next start says what it was: tried, recorded, the main part alone, or both parts
    said = left_words(*left_at_quit(folder), tmp_path / "r")
    assert said == ("studio: the last session's sequential take, its reaction cut short at "
                    f"quit, is in studio/{line['take']} (the main part) and {react.name} (the "
                    "reaction so far), not in the library"), said
    assert "'s sequential take's main part (its reaction not recorded) at quit is in " \
        "studio/" in left_words(*left_at_quit(tmp_path / "s" / "studio"), tmp_path / "s")
    assert "'s take still recorded at quit is in studio/" in left_words(
        *left_at_quit(tmp_path / "a" / "studio"), tmp_path / "a")
    # too short to train (1.5 s of the 2 s a take needs): nothing saved, and why
    caplog.clear()
    bench, lines, text = quit_while(tmp_path / "c", demo[:80], {20}, caplog)
    assert lines == [] and list(bench.session.folder.glob("*-take*")) == []
    assert "pet: take cancelled at quit; nothing saved: take too short (1.4 s of both " \
        "pucks, needs 2 s)" in text, text
