"""The designer studio refusing a command while a take is tried or recorded, saying so where
the designer looks, and a take left by Tab or Esc said and logged."""

import json

from behaviors.puppet_master import designers
from tabletop import library
from tabletop.config import validate_config
from tabletop.frames import Frame, Puck

from tests.keys import key
from tests.studio.test_studio_keys import ROOT, TABLE, Bench, build, demo_frames, designer


def test_rename_delete_and_undo_wait_while_a_take_is_tried(tmp_path):
    """F2 on a take being tried renamed the library item played before it (the designer
    naming the take: lover became "shy", the take then kept as "pet"); Delete deleted that
    item and U undid the last keep under the take. Each is refused, said, until the take is
    kept or discarded."""
    lib = tmp_path / "lib"
    library.save_behavior(lib, "lover", designers.demonstrate("lover", seconds=4), {})
    (e,) = designer(tmp_path)
    bench = Bench([e], tmp_path)
    bench.studio.command("designer.item_next")
    assert e.behavior_name == "lover"
    demo = designers.demonstrate("afraid", seed=8, seconds=6)
    for f in demo_frames(demo, {5: ("designer.record",), 200: ("designer.record",)}):
        bench.step(f)
    s = bench.studio
    assert s.state == "trying"
    for cmd, doing in (("designer.rename:shy", "renaming"), ("designer.delete", "deleting"),
                       ("designer.undo", "undoing")):
        s.command(cmd)
        assert s.message == f"no {doing} while a take is tried: K keeps or X discards it first"
    assert library.list_behaviors(lib) == ["lover"] and s.state == "trying"
    s.command("designer.keep")
    s.command("designer.rename:shy")                   # the kept take is the item in play
    assert library.list_behaviors(lib) == ["lover", "shy"] and e.behavior_name == "shy"
    s.command("designer.record")                       # a countdown: a take is under way
    s.command("designer.undo")
    assert s.message == "no undoing during a take: finish it, or X cancels it"
    s.command("designer.discard")
    s.command("designer.undo")
    assert s.message == "undone: rename pet -> shy"
    assert library.list_behaviors(lib) == ["lover", "pet"]


def test_a_take_left_by_tab_is_said_discarded(tmp_path):
    """Tab while a take was tried (or recorded) dropped it without a word: the next target's
    line showed, and the take was gone when the designer came back."""
    a, b = build([{"kind": "puppet_master", "name": n, "designer": {
        "enabled": True, "library": str(tmp_path), "background_training": False}}
        for n in ("a", "b")])
    bench = Bench([a, b], tmp_path)
    demo = designers.demonstrate("lover", seed=1, seconds=4)
    for f in demo_frames(demo, {4: ("designer.record",), 120: ("designer.record",)}, focus="a"):
        _, studio = bench.step(f)
    assert bench.studio.state == "trying"
    _, studio = bench.step(Frame(seq=500, t=200.0, focus="b"))
    assert studio.label == "[b] a: take discarded (Tab left it)", studio.label
    bench.step(Frame(seq=501, t=201.0, focus="b", commands=("designer.record",)))
    _, studio = bench.step(Frame(seq=502, t=202.0, focus="a"))
    assert studio.label == "[a] b: take cancelled (Tab left it)", studio.label
    assert bench.studio.state == "idle" and a.behavior is None


def test_esc_while_a_take_is_tried_logs_it_as_quit(tmp_path):
    """Esc in the view while a take was tried ended the run and the take went without a line
    in the session log: the loop closes the studio, which logs it (outcome "quit")."""
    import threading

    import pygame

    from tabletop.loop import CommandQueue, Loop
    from tabletop.replay_inputs import FrameInputs
    from tabletop.studio.build import Markers, StudioStage
    from tabletop.view import ProjectorView

    (e,) = designer(tmp_path)
    bench = Bench([e], tmp_path)
    stop, q = threading.Event(), CommandQueue()
    cfg = validate_config({"sources": [{"kind": "scripted"}]}, "test.yaml", ROOT)
    view = ProjectorView(TABLE, dict(cfg["view"], size=[320, 180]), commands=q, stop=stop,
                         headless=True)
    demo = designers.demonstrate("lover", seed=8, seconds=30)
    frames = list(demo_frames(demo, {10: ("designer.record",), 300: ("designer.record",)}))

    def esc_once_tried(frame):
        if bench.studio.state == "trying" and not stop.is_set():
            key(pygame.K_ESCAPE)

    loop = Loop(FrameInputs(iter(frames), honour_times=False), [e], [view], commands=q,
                stop=stop, paced=False, hooks=[esc_once_tried],
                filters=[StudioStage(Markers({}, bench.studio), bench.studio)])
    ran = loop.run()
    assert stop.is_set() and ran < len(frames)          # Esc ended the run
    (line,) = [json.loads(x) for x in bench.session.path.read_text().splitlines()]
    assert line["outcome"] == "quit" and line["target"] == "pet" and line["samples"] == 290
    assert bench.studio.state == "idle"


def test_f2_with_nothing_to_rename_is_refused_at_once(tmp_path):
    """F2 opened the name prompt with no library item in play; "nothing to rename" came only
    after a name was typed and Enter: the prompt stays closed and the refusal is said at F2."""
    import types

    import pygame

    from tabletop.loop import CommandQueue, Loop
    from tabletop.replay_inputs import FrameInputs
    from tabletop.studio.build import attach_studio
    from tabletop.view import ProjectorView

    lib = tmp_path / "lib"
    library.save_behavior(lib, "shy", designers.demonstrate("lover", seconds=4), {})
    engines = designer(tmp_path)
    cfg = validate_config({"sources": [{"kind": "scripted"}], "engines": [
        {"kind": "puppet_master", "name": "pet",
         "designer": {"enabled": True, "library": str(lib)}}],
        "studio": {"folder": str(tmp_path / "studio"), "review": False}}, "test.yaml", ROOT)
    q = CommandQueue()
    view = ProjectorView(TABLE, dict(cfg["view"], size=[320, 180]), commands=q, headless=True)
    loop = Loop(FrameInputs(iter(()), honour_times=False), engines, [view], commands=q,
                paced=False)
    studio = attach_studio(types.SimpleNamespace(loop=loop), cfg, tmp_path)

    def f2(t):
        key(pygame.K_F2)
        view.consume(studio(Frame(seq=int(t), t=t)))
    try:
        f2(1.0)
        assert not view.prompt.active and studio.message == "nothing to rename"
        studio.command("designer.item_next")
        f2(2.0)
        assert view.prompt.active                      # shy is in play: type its new name
        assert view.prompt.line == "rename shy as: _   (Esc cancels)"   # what Enter renames
        key(pygame.K_ESCAPE)
        view.consume(studio(Frame(seq=3, t=3.0)))
        studio.command("designer.record")              # a take under way: refused, said
        f2(4.0)
        assert not view.prompt.active and studio.message.startswith("no renaming during a take")
    finally:
        view.close()


def test_a_refusal_while_a_puck_is_missing_is_shown_beside_the_missing_puck(tmp_path):
    """Recording with puck 2 gone, "recording: no puck 2" took the status line every tick: a
    refusal said at that moment (F2 during the take) was never seen. Both are shown."""
    (e,) = designer(tmp_path)
    bench = Bench([e], tmp_path)

    def tick(i, cmds=()):
        _, studio = bench.step(Frame(seq=i, t=100 + i / 60, pucks=(Puck(1, 0.5, 0.4, 0.0),),
                                     commands=cmds))
        return studio.label
    tick(0, ("designer.record",))
    assert "recording: no puck 2" in tick(1)
    said = tick(2, ("designer.rename:shy",))
    assert "recording: no puck 2" in said and "no renaming during a take" in said
    said = tick(30)                                    # half a second on: both still shown
    assert "recording: no puck 2" in said and "no renaming during a take" in said


def test_tab_in_a_quiet_studio_shows_the_target_it_picked(tmp_path):
    """A studio outside studio mode draws nothing until a designer key: Tab, the first key a
    designer of several characters presses, changed the target without a word (the MOP
    example: Tab, then nothing on the table to say that the bird was picked)."""
    from tabletop.studio.machine import Studio
    from tabletop.studio.targets import PuppetMasterTarget

    a, b = build([{"kind": "puppet_master", "name": n, "designer": {
        "enabled": True, "library": str(tmp_path)}} for n in ("a", "b")])
    studio = Studio([PuppetMasterTarget(e) for e in (a, b)], countdown_s=0.0, quiet=True)
    assert studio(Frame(seq=0, t=1.0, focus="a")).character("studio").label == ""
    label = studio(Frame(seq=1, t=1.1, focus="b")).character("studio").label
    assert label.startswith("[b] ") and "R record" in label, label


def test_a_message_to_a_quiet_studio_is_on_the_table_for_its_seconds(tmp_path,
                                                                      pygame_display):
    """A studio outside studio mode drew nothing until a designer key, so what it said (the
    behaviour in play deleted from the library elsewhere, a kiosk's config edit on the takes)
    reached the log alone: the message is on the table for its seconds, then nothing again."""
    import shutil

    import pygame

    from tabletop.renderer import Renderer
    from tabletop.studio.draw import draw_studio
    from tabletop.studio.machine import Studio
    from tabletop.studio.targets import PuppetMasterTarget

    lib = tmp_path / "lib"
    library.save_behavior(lib, "lover", designers.demonstrate("lover", seconds=3), {})
    (e,) = build([{"kind": "puppet_master", "name": "a", "behavior": str(lib / "lover"),
                   "designer": {"enabled": True, "library": str(lib),
                                "background_training": False}}])
    target = PuppetMasterTarget(e)
    target.lib_poller.every_s = target.play_poller.every_s = 0.0   # (the loop: once a second)
    studio = Studio([target], countdown_s=0.0, quiet=True)
    renderer, surface = Renderer(TABLE, (640, 360)), pygame.Surface((640, 360))

    def drawn(t: float) -> tuple[str, bool]:
        studio.poll()
        c = studio(Frame(seq=int(t * 10), t=t)).character("studio")
        surface.fill((0, 0, 0))
        draw_studio(surface, renderer, c)
        return c.label, pygame.transform.average_color(surface)[:3] != (0, 0, 0)
    assert drawn(1.0) == ("", False)
    shutil.rmtree(lib / "lover")
    said = ("[a] lover was removed from the library elsewhere; it plays on from memory, ] "
            "plays another", True)
    assert drawn(1.1) == drawn(5.9) == said
    assert drawn(6.2) == ("", False) and studio.quiet


def test_a_switch_with_nothing_kept_names_the_folder_it_looked_in(tmp_path):
    """] with nothing kept said "the library is empty", beside a MOP character that knows the
    actions of its config (those are no library items): the line names the folder it plays
    from and what fills it."""
    (e,) = designer(tmp_path)
    bench = Bench([e], tmp_path)
    bench.studio.command("designer.item_next")
    assert bench.studio.message == f"nothing kept in {tmp_path / 'lib'}/ yet: ] and [ play " \
                                   "what K keeps", bench.studio.message


def test_previous_from_the_configs_behaviour_plays_the_last_kept_one(tmp_path):
    """[ from the config's behaviour (no library item) played the first kept item, as ] does:
    it plays the last."""
    lib = tmp_path / "lib"
    for name in ("a", "b", "c"):
        library.save_behavior(lib, name, designers.demonstrate("lover", seconds=3), {})
    (e,) = designer(tmp_path)
    bench = Bench([e], tmp_path)
    bench.studio.command("designer.item_previous")
    assert bench.studio.message == "playing c (3 of 3)" and e.behavior_name == "c"
    bench.studio.command("designer.item_previous")
    assert bench.studio.message == "playing b (2 of 3)"


def test_renaming_an_item_to_the_name_it_has_says_so(tmp_path):
    """F2 and Enter on the name shown (lover) said "cannot: LIB/lover: already exists", as if
    another behaviour held the name; nothing is renamed and the session log has no line."""
    lib = tmp_path / "lib"
    library.save_behavior(lib, "lover", designers.demonstrate("lover", seconds=3), {})
    (e,) = designer(tmp_path)
    bench = Bench([e], tmp_path)
    bench.studio.command("designer.item_next")
    bench.studio.command("designer.rename:lover=lover")
    assert bench.studio.message == "nothing renamed: lover is already its name", \
        bench.studio.message
    assert library.list_behaviors(lib) == ["lover"] and not bench.session.path.exists()
    bench.studio.command("designer.rename:lover=shy")
    assert library.list_behaviors(lib) == ["shy"]


def test_a_bad_library_file_in_a_quiet_studio_is_on_the_overlay_not_the_table(tmp_path, caplog,
                                                                           pygame_display):
    """A behaviour file edited by hand into a typo while a designer engine ran outside studio
    mode was said in the log alone: the studio draws nothing until a designer key, so the
    operator overlay had no line for it. It has one now, and the table still shows nothing."""
    import pygame

    from tabletop.renderer import Renderer
    from tabletop.studio.draw import draw_studio
    from tabletop.studio.machine import Studio
    from tabletop.studio.targets import PuppetMasterTarget
    from tabletop.view import overlay_lines

    lib = tmp_path / "lib"
    library.save_behavior(lib, "lover", designers.demonstrate("lover", seconds=3),
                          {"rate_hz": 40.0})
    (e,) = build([{"kind": "puppet_master", "name": "a", "designer": {
        "enabled": True, "library": str(lib)}}])
    target = PuppetMasterTarget(e)
    target.lib_poller.every_s = 0.0             # looks at every call (the loop: once a second)
    studio = Studio([target], countdown_s=0.0, quiet=True)
    studio.poll()
    good = studio(Frame(seq=0, t=1.0)).character("studio")
    assert good.label == "" and good.action == "idle"
    yaml = lib / "lover" / library.BEHAVIOR_FILE
    text = yaml.read_text()
    assert "rate_hz: 40.0\n" in text
    yaml.write_text(text.replace("rate_hz: 40.0", "rate_hz: 40.0x"))
    studio.poll()
    f = studio(Frame(seq=1, t=1.1))
    c = f.character("studio")
    assert c.action == "quiet", c
    line = next(x for x in overlay_lines(f, None) if x.startswith("studio: "))
    assert line.startswith("studio: 1 bad library file(s): ") and "lover" in line \
        and "rate_hz: expected a number, got '40.0x'" in line, line
    renderer = Renderer(TABLE, (640, 360))
    surface = pygame.Surface((640, 360))
    assert draw_studio(surface, renderer, c) == []           # nothing drawn on the table
    assert pygame.transform.average_color(surface)[:3] == (0, 0, 0)
    yaml.write_text(text)                                     # fixed on disk: gone
    with caplog.at_level("INFO", logger="tabletop"):
        studio.poll()
    assert studio(Frame(seq=2, t=1.2)).character("studio").label == ""
    said = [r.getMessage() for r in caplog.records if "no longer said" in r.getMessage()]
    assert len(said) == 1 and "rate_hz: expected a number" in said[0], said


def test_the_take_the_last_session_left_at_quit_is_said_at_the_next_start(tmp_path, caplog):
    """A take tried at quit is saved beside the session log; the next start says where, in
    the log and on the operator overlay until the next take (not on the studio's line, which
    a replay makes again), and says nothing once the file is gone."""
    import subprocess
    import sys
    import types

    from tabletop.loop import CommandQueue, Loop
    from tabletop.replay_inputs import FrameInputs
    from tabletop.studio.build import attach_studio
    from tabletop.view import ProjectorView

    studio_dir = tmp_path / "studio"
    studio_dir.mkdir()
    take = studio_dir / "session-20260101-120000-take001.csv"
    take.write_text("t,main_x,main_y,main_dir,react_x,react_y,react_dir\n0,0,0,0,0,0,0\n")
    (studio_dir / "session-20260101-120000.jsonl").write_text(
        '{"target": "pet", "outcome": "kept"}\n{"target": "pet", "outcome": "quit", '
        '"take": "session-20260101-120000-take001.csv"}\n')
    said = "studio: the last session's take saved at quit is in " \
        "studio/session-20260101-120000-take001.csv (not in the library)"
    cfg = tmp_path / "c.yaml"
    cfg.write_text("sources: [{kind: scripted, pucks: [1, 2]}]\nengines: [{kind: puppet_master, "
                   "name: pet, main: {puck: 1}, designer: {enabled: true, library: lib}}]\n")
    err = subprocess.run([sys.executable, "-m", "tabletop", "run", "--config", str(cfg),
                          "--headless", "--seconds", "0.5"], capture_output=True, text=True,
                         cwd=ROOT, timeout=120).stderr
    assert said in err, err

    def started(replay=False):
        config = validate_config({"sources": [{"kind": "scripted"}], "engines": [
            {"kind": "puppet_master", "name": "pet", "designer": {
                "enabled": True, "library": str(tmp_path / "lib")}}],
            "studio": {"review": False, "countdown_s": 0}}, "test.yaml", tmp_path)
        q = CommandQueue()
        view = ProjectorView(TABLE, dict(config["view"], size=[320, 180]), commands=q,
                             headless=True)
        loop = Loop(FrameInputs(iter(()), honour_times=False), designer(tmp_path), [view],
                    commands=q, paced=False)
        return view, attach_studio(types.SimpleNamespace(loop=loop), config, tmp_path,
                                   replay=replay)
    view, studio = started()
    demo = designers.demonstrate("lover", seed=3, seconds=8)
    notices = []
    for i, row in enumerate(demo):
        f = studio(Frame(seq=i, t=100.0 + row[0], pucks=(Puck(1, *row[1:4]),
                                                       Puck(2, *row[4:7])),
                         commands=("designer.record",) if i in (40, len(demo) - 1) else ()))
        notices.append([n for fn in view.notices for n in fn()])
        assert said not in f.character("studio").label
    assert notices[0] == notices[39] == [said] and notices[40] == notices[-1] == [], notices
    studio.command("designer.discard")
    assert studio.state == "idle" and [n for fn in view.notices for n in fn()] == []
    take.unlink()                                   # taken away: not said
    view, studio = started()
    assert [n for fn in view.notices for n in fn()] == []
    # a replay's studio (in a temporary folder) neither says it nor saves the take again
    view, studio = started(replay=True)
    assert [n for fn in view.notices for n in fn()] == []
    for i, row in enumerate(demo):
        studio(Frame(seq=i, t=100.0 + row[0], pucks=(Puck(1, *row[1:4]), Puck(2, *row[4:7])),
                     commands=("designer.record",) if i in (40, len(demo) - 1) else ()))
    assert studio.state == "trying"
    studio.close()
    assert studio.tries[-1].outcome == "quit" and studio.tries[-1].take == ""
    assert not list(studio_dir.glob("*-take*")), list(studio_dir.iterdir())
    view, studio = started(replay=True)      # still recorded: why none, not "cancelled"
    for i, row in enumerate(demo[:140]):
        studio(Frame(seq=i, t=100.0 + row[0], pucks=(Puck(1, *row[1:4]), Puck(2, *row[4:7])),
                     commands=("designer.record",) if i == 40 else ()))
    with caplog.at_level("INFO", logger="tabletop"):
        studio.close()
    assert "studio: pet: take recorded, not tried, at quit; nothing saved: a replay saves no " \
        "takes (the run it replays did)" in caplog.text, caplog.text
    assert not list(studio_dir.glob("*-take*")), list(studio_dir.iterdir())


def test_a_missing_puck_is_not_said_once_the_recording_stopped(tmp_path):
    """Puck 2 unseen in a take's last frames: "recording: no puck 2" stayed on the status line
    for 0.2 s after the stop, beside "training the take..." and the trained take's "try it"."""
    (e,) = designer(tmp_path, background_training=True)
    bench = Bench([e], tmp_path)
    demo = designers.demonstrate("afraid", seed=8, seconds=6)
    labels = []
    for i, f in enumerate(demo_frames(demo, {5: ("designer.record",), 200: ("designer.record",)})):
        if 196 <= i <= 200:
            f = Frame(seq=f.seq, t=f.t, pucks=f.pucks[:1], commands=f.commands)
        studio = bench.step(f)[1]
        labels.append((studio.action, studio.label))
    assert "recording: no puck 2" in labels[199][1]
    after = labels[200:210]
    assert after[0][0] in ("training", "trying")
    assert not any("recording" in lab for _, lab in after), after
