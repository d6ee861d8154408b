"""The designer studio as a designer drives it by keys: the status line speaks of the state and
target on screen, and the library keys stay sound after the item in play is deleted."""

from behaviors.puppet_master import designers
from tabletop import library
from tabletop.frames import Frame, Puck
from tabletop.studio.machine import Studio
from tabletop.studio.targets import PuppetMasterTarget

from tests.studio.test_studio_keys import Bench, build, designer


def test_a_message_ends_with_the_state_or_the_target_it_was_said_for(tmp_path):
    """"R records the reaction ..." said between the parts of a sequential take must not stay
    on while the reaction's countdown and recording run (a designer reading it presses R again
    and stops the take), and "take discarded" of one target is not shown under the next."""
    a, b = build([{"kind": "puppet_master", "name": n,
                   "designer": {"enabled": True, "library": str(tmp_path / n),
                                "sequential": n == "a", "background_training": False}}
                  for n in ("a", "b")])
    studio = Studio([PuppetMasterTarget(a), PuppetMasterTarget(b)], countdown_s=1.0)
    demo = designers.demonstrate("lover", seed=2, seconds=12)
    labels, states = [], []
    keys = {10: "designer.record", 200: "designer.record", 230: "designer.record"}
    for i, row in enumerate(demo[:400]):
        f = Frame(seq=i, t=100.0 + row[0], pucks=(Puck(1, *row[1:4]), Puck(2, *row[4:7])),
                  commands=(keys[i],) if i in keys else (), focus="a")
        c = studio(f).character("studio")
        labels.append(c.label)
        states.append(c.action)
    assert states[229] == "ready" and "R records the reaction" in labels[229]
    assert states[11] == "countdown" and "get ready: puck 1 the main" in labels[11]
    # the reaction's countdown names the reactor's puck, not the main's again
    assert states[231] == "countdown" and "get ready: puck 2 reacts" in labels[231]
    after = [lab for s, lab in zip(states[231:], labels[231:]) if s in ("countdown", "recording")]
    assert len(after) > 100
    assert not any("R records the reaction" in lab for lab in after)
    # the reaction part lasts as long as the main take's playback: said, as REC counts up
    assert "R records the reaction against the main's playback (3.7 s)" in \
        labels[229], labels[229]
    assert any("recording the reaction against the main's playback (3.7 s): R stop" in lab
               for lab in after)
    # a message said in a state stays while that state lasts (up to its five seconds)
    studio.command("designer.discard")          # the take is cancelled: idle, "take cancelled"
    t = studio._t
    assert "take cancelled" in studio(Frame(seq=500, t=t + 0.1, focus="a")).character(
        "studio").label
    assert "take cancelled" in studio(Frame(seq=501, t=t + 1.0, focus="a")).character(
        "studio").label
    # Tab: the next target's own line, not the last target's message
    label = studio(Frame(seq=502, t=t + 1.5, focus="b")).character("studio").label
    assert label.startswith("[b]") and "cancelled" not in label and "R record" in label


def playing_a(tmp_path):
    """A designer engine's studio playing library behaviour "a"; (engine, studio, library)."""
    lib = tmp_path / "lib"
    library.save_behavior(lib, "a", designers.demonstrate("lover", seconds=4), {})
    (e,) = designer(tmp_path)
    s = Bench([e], tmp_path).studio
    s.command("designer.item_next")
    assert e.behavior_name == "a"
    return e, s, lib


def test_deleting_the_behaviour_in_play_leaves_nothing_to_delete_rename_or_report(tmp_path):
    e, s, lib = playing_a(tmp_path)
    s.command("designer.delete")
    assert library.list_behaviors(lib) == [] and "deleted a" in s.message
    s.targets["pet"].lib_poller.every_s = 0.0     # looks at every poll (the loop: once a second)
    s.poll()
    assert s.problems == []                       # a deletion is no bad file
    assert "deleted" in e.behavior_name           # it plays on from memory, said so
    s.command("designer.delete")                  # pressed twice: it was a FileNotFoundError
    assert s.message == "nothing to delete"
    s.command("designer.rename:b")
    assert s.message == "nothing to rename" and library.list_behaviors(lib) == []
    s.command("designer.undo")                    # back in the library, in play again
    assert library.list_behaviors(lib) == ["a"] and e.behavior_name == "a"
    s.command("designer.rename:b")
    assert library.list_behaviors(lib) == ["b"] and e.behavior_name == "b"


def test_a_folder_gone_under_the_studio_is_said_not_raised(tmp_path):
    _, s, lib = playing_a(tmp_path)
    (lib / "a").rename(tmp_path / "elsewhere")    # moved away by hand
    s.command("designer.rename:b")
    assert s.message.startswith("cannot: ") and "No such file" in s.message


def test_a_bad_library_file_is_counted_once_however_often_the_library_changes(tmp_path):
    lib = tmp_path / "lib"
    library.save_behavior(lib, "a", designers.demonstrate("lover", seconds=4), {})
    (e,) = designer(tmp_path)                     # a designer engine with no behaviour yet
    s = Bench([e], tmp_path).studio
    (lib / "bad").mkdir()
    (lib / "bad" / "behavior.yaml").write_text("{{{")
    s.targets["pet"].lib_poller.every_s = 0.0    # looks at every poll (the loop: once a second)
    counts = []
    for i in range(3):
        s.poll()
        counts.append(len(s.problems))
        (lib / f"new{i}").mkdir()
        (lib / f"new{i}" / "notes.txt").write_text("x")
    assert counts == [1, 1, 1], counts


def test_the_assign_key_on_a_behaviour_says_why_it_does_nothing(tmp_path):
    _, s, _ = playing_a(tmp_path)
    s.command("designer.assign")
    assert s.message == "A: a behaviour has no motion to assign (MOP actions do)"
    assert s.state == "idle"


def test_tab_with_one_designer_target_says_so(tmp_path):
    """Tab with a single designer target says so on the status line ("Tab: pet is the only
    designer target"; without it, nothing visible happened, as for a broken key)."""
    from tabletop.loop import DesignerFocus
    from tests.studio.test_studio_keys import build

    def tab(engines) -> str:
        studio = Studio([PuppetMasterTarget(e) for e in engines], countdown_s=1.0)
        focus = DesignerFocus([])
        focus.extra.append(studio)
        commands, chosen = focus.apply(("designer.next",))
        frame = studio(Frame(seq=0, t=100.0, commands=commands, focus=chosen))
        assert frame.commands == ()                 # the studio's to say, no engine's
        return frame.character("studio").label

    one = build([{"kind": "puppet_master", "name": "pet",
                  "designer": {"enabled": True, "library": str(tmp_path / "lib")}}])
    assert "Tab: pet is the only designer target" in tab(one)
    two = build([{"kind": "puppet_master", "name": n,
                  "designer": {"enabled": True, "library": str(tmp_path / n)}} for n in "ab"])
    label = tab(two)
    assert label.startswith("[b]") and "only" not in label, label
