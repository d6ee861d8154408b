"""The kiosk's reload of MOP actions it started without (tabletop.kiosk.actions), on the stage of
bench/action_reload.py (walker: circle good, line and square unreadable; lone: line unreadable;
both lines read one template): only regular files are read, the actions fixed in one tick
retrain the followers once, and a replay refuses a damaged recorded entry in one line."""

import base64
import logging
import os
import threading
from pathlib import Path

from bench.action_reload import GESTURES, _stage
from tabletop.frames import Frame
from tabletop.kiosk.actions import ActionReloader, replay_actions


def _counting_builds(stage) -> list:
    """The stage's follower rebuilds, counted (each still builds)."""
    builds = []
    build = stage._build

    def counted(plan):
        builds.append(1)
        return build(plan)
    stage._build = counted
    return builds


def test_a_named_pipe_in_place_of_a_template_is_refused_without_holding_the_tick(tmp_path):
    stage = _stage(tmp_path)
    reloader = ActionReloader(stage, every_s=0.0)
    reloader(Frame(seq=0, t=1.0))
    line = tmp_path / "line.csv"
    line.unlink()
    os.mkfifo(line)
    def ticks():               # the change seen, then read once it stayed for a look
        reloader(Frame(seq=1, t=1.1))
        reloader(Frame(seq=2, t=1.2))
    tick = threading.Thread(target=ticks, daemon=True)
    tick.start()
    tick.join(30.0)
    if tick.is_alive():           # (let the blocked open go, so the process can end)
        os.close(os.open(line, os.O_WRONLY | os.O_NONBLOCK))
    assert not tick.is_alive(), "the frame filter waited on the named pipe"
    why = [m["why"] for m in stage.missing if m["action"]["name"] == "line"]
    assert len(why) == 2 and all(f"{line}: not a regular file" in w for w in why), why
    assert why == [e for e in stage.start_problems if "action 'line'" in e]


def test_actions_fixed_in_one_tick_retrain_the_followers_once(tmp_path):
    stage = _stage(tmp_path)
    reloader = ActionReloader(stage, every_s=0.0)
    reloader(Frame(seq=0, t=1.0))
    builds = _counting_builds(stage)
    (tmp_path / "line.csv").write_text((GESTURES / "line.csv").read_text())
    assert "reload" not in reloader(Frame(seq=1, t=1.1)).consumed   # read once it stays so
    frame = reloader(Frame(seq=2, t=1.2))
    assert [(e["character"], e["action"]) for e in frame.consumed["reload"]["actions"]["mop"]] \
        == [("walker", "line"), ("lone", "line")]
    assert {n: set(t) for n, t in stage.templates.items()} == {
        "walker": {"circle", "line"}, "lone": {"line"}}
    assert len(builds) == 1


def _entry(character: str, action: str, *files: Path) -> dict:
    return {"character": character, "action": action,
            "files": [base64.b64encode(f.read_bytes()).decode("ascii") for f in files]}


def test_a_file_touched_with_the_same_bytes_is_neither_retrained_nor_recorded(tmp_path):
    """A ``touch`` (or an rsync copying the same bytes) of a playing action's file: the
    followers are not retrained and the frame records nothing; changed bytes still are."""
    stage = _stage(tmp_path)
    reloader = ActionReloader(stage, every_s=0.0)
    reloader(Frame(seq=0, t=1.0))
    builds = _counting_builds(stage)
    line = tmp_path / "line.csv"
    line.write_text((GESTURES / "line.csv").read_text())     # fixed: followed once
    for k in (1, 2):
        reloader(Frame(seq=k, t=1.0 + k / 10))
    assert len(builds) == 1
    for name in ("circle.csv", "line.csv"):          # touched: mtime on, bytes alike
        st = (tmp_path / name).stat()
        os.utime(tmp_path / name, ns=(st.st_atime_ns, st.st_mtime_ns + 5_000_000_000))
    frames = [reloader(Frame(seq=k, t=1.0 + k / 10)) for k in (3, 4, 5)]
    assert len(builds) == 1 and all("reload" not in f.consumed for f in frames)
    assert not [e for e in stage.start_problems if "action 'line'" in e]
    (tmp_path / "circle.csv").write_text((GESTURES / "square.csv").read_text())
    frames = [reloader(Frame(seq=k, t=1.0 + k / 10)) for k in (6, 7)]
    assert len(builds) == 2
    assert [e["action"] for f in frames for e in f.consumed.get("reload", {}).get(
        "actions", {}).get("mop", [])] == ["circle"]


def test_a_replay_refuses_a_recorded_entry_with_a_wrong_number_of_files_in_one_line(
        tmp_path, caplog):
    """An entry with no file, or with the template alone for an action that reads a clip too,
    is logged and skipped (never an IndexError, never the config's own clip taken instead);
    the frame's other entries are followed, the followers retrained once."""
    stage = _stage(tmp_path)
    (tmp_path / "good.csv").write_text((GESTURES / "line.csv").read_text())
    builds = _counting_builds(stage)
    with caplog.at_level(logging.ERROR, logger="tabletop"):
        replay_actions(stage, [{"character": "walker", "action": "line", "files": []},
                               _entry("walker", "square", tmp_path / "square.csv"),
                               _entry("lone", "line", tmp_path / "good.csv")])
    said = [r.getMessage() for r in caplog.records if r.getMessage().startswith("replay:")]
    assert said == [
        "replay: recorded action 'line' of 'walker' skipped: its entry holds 0 file(s), expected "
        "the bytes of its 1 file(s) (line.csv)",
        "replay: recorded action 'square' of 'walker' skipped: its entry holds 1 file(s), "
        "expected the bytes of its 2 file(s) (square.csv, wag.json)"]
    assert {n: set(t) for n, t in stage.templates.items()} == {
        "walker": {"circle"}, "lone": {"line"}}
    assert len(builds) == 1 and len(stage.missing) == 2


class _LoadedClock:
    """A frame loop's clock (s): ``now`` set at each tick; while ``slow``, each read is 20 ms
    after the one before (a loaded machine: time passes between one action's look and the
    next's, a still-bad file read in between)."""

    def __init__(self) -> None:
        self.now, self.slow, self._reads = 0.0, False, 0

    def tick(self, now: float, slow: bool = False) -> None:
        self.now, self.slow, self._reads = now, slow, 0

    def __call__(self) -> float:
        self._reads += 1
        return self.now + (0.02 * (self._reads - 1) if self.slow else 0.0)


def test_actions_reading_one_file_are_followed_from_the_same_tick_whatever_a_slow_look_took(
        tmp_path):
    """Both characters' line actions read line.csv: fixed, they are followed from one frame,
    even after a tick in which the looks at the missing actions' files were 20 ms apart (were
    each action's look due a second after its own, the two fell on different ticks from then
    on, and the fix was followed by one character a frame before the other)."""
    stage = _stage(tmp_path)
    clock = _LoadedClock()
    reloader = ActionReloader(stage, every_s=1.0, clock=clock)
    clock.tick(0.0, slow=True)
    reloader(Frame(seq=0, t=0.0))
    (tmp_path / "line.csv").write_text((GESTURES / "line.csv").read_text())
    followed = []
    for k in range(1, 150):
        clock.tick(k / 30)
        frame = reloader(Frame(seq=k, t=k / 30))
        if "reload" in frame.consumed:
            followed.append([(e["character"], e["action"])
                             for e in frame.consumed["reload"]["actions"]["mop"]])
    assert followed == [[("walker", "line"), ("lone", "line")]]
