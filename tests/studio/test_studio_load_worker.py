"""Library behaviours trained off the frame loop: a pick in the studio and a hot reload outside
it hand the folder to a worker; the tick that triggers it returns with no training in it, the
character plays on with its behaviour, and the new one plays from a tick boundary."""

import math
import shutil
import threading
from pathlib import Path

import pytest

from behaviors.puppet_master import designers
from behaviors.puppet_master.engine import Behavior
from tabletop import library
from tabletop.frames import Frame, Puck
from tests.studio.test_studio_keys import Bench, demo_frames, designer

SHIPPED = Path(__file__).resolve().parents[2] / "behaviors" / "library"


@pytest.fixture
def trainings(monkeypatch):
    """Behavior.train as it is, with the thread each call runs on; one in a worker thread waits
    for ``release`` (set: runs at once)."""
    real = Behavior.train.__func__
    calls: list[bool] = []       # True: trained on the loop's (main) thread
    release = threading.Event()

    def train(cls, *args, **kwargs):
        on_loop = threading.current_thread() is threading.main_thread()
        calls.append(on_loop)
        if not on_loop:
            assert release.wait(10.0)
        return real(cls, *args, **kwargs)

    monkeypatch.setattr(Behavior, "train", classmethod(train))
    return calls, release


def _library(tmp_path):
    """A designer engine training in workers, behind a studio, on a library of bully and
    lover: (engine, bench, library folder)."""
    lib = tmp_path / "lib"
    for name in ("bully", "lover"):
        shutil.copytree(SHIPPED / name, lib / name)
    (e,) = designer(tmp_path, background_training=True)
    return e, Bench([e], tmp_path), lib


def test_a_library_pick_trains_in_the_worker_and_plays_from_a_tick_boundary(tmp_path, trainings):
    calls, release = trainings
    e, bench, lib = _library(tmp_path)
    pucks = (Puck(1, 0.4, 0.3, 0.0),)
    bench.step(Frame(seq=0, t=10.0, pucks=pucks, commands=("designer.item_next",)))
    assert True not in calls and e.behavior is None     # returned while the worker trains
    release.set()
    bench.studio.targets["pet"].loader.wait()
    bench.step(Frame(seq=1, t=10.1, pucks=pucks))       # done, but LOAD_S is not over
    assert e.behavior is None
    out, _ = bench.step(Frame(seq=2, t=10.15, pucks=pucks))
    assert e.behavior_name == "bully" and e.behavior.samples > 100
    assert "playing bully" in out["pet"].label and calls == [False]
    bully = e.behavior                                  # broken after the library was read:
    (lib / "lover" / "demonstration.csv").write_text("t,x\n1,oops\n")   # found in the worker
    bench.step(Frame(seq=3, t=11.0, pucks=pucks, commands=("designer.item_next",)))
    bench.step(Frame(seq=4, t=11.2, pucks=pucks))
    bench.studio.poll()                                 # (the loop's hook: said once)
    out, studio = bench.step(Frame(seq=5, t=11.3, pucks=pucks))
    assert e.behavior is bully and "playing bully" in out["pet"].label
    assert "lover not played" in studio.label and "demonstration.csv" in studio.label


def test_a_hot_reload_trains_in_the_worker_and_a_bad_folder_keeps_the_old(tmp_path, trainings,
                                                                          caplog):
    from tabletop.config import validate_config
    from tabletop.plugins import puppet_master as pm
    from tabletop.registry import BuildContext
    from tabletop.studio.reloader import BehaviorReloader
    calls, release = trainings
    folder = library.save_behavior(tmp_path, "x", designers.demonstrate("lover", seconds=4), {})
    cfg = validate_config({"sources": [{"kind": "scripted"}], "engines": [
        {"kind": "puppet_master", "name": "pet", "behavior": str(folder)}]}, "t.yaml", tmp_path)
    engine = pm.build(cfg["engines"][0], BuildContext((1.2, 0.8), 60.0, cfg, tmp_path))
    hook = BehaviorReloader(engine)
    hook.poller.every_s = 0.0
    first, calls[:] = engine.behavior, []
    library.save_behavior(tmp_path, "x", designers.demonstrate("stalker", seconds=5), {},
                          replace=True)
    frame = Frame(seq=0, t=1.0, pucks=(Puck(1, 0.4, 0.3, 0.0),))
    hook(frame)
    assert True not in calls and engine.behavior is first and hook.loading
    assert "playing x" in engine.step(frame)[0].label    # plays on while the worker trains
    release.set()
    hook.wait()
    assert engine.behavior is not first and calls == [False]
    assert engine.behavior.samples == len(designers.demonstrate("stalker", seconds=5))
    good = engine.behavior
    (folder / "behavior.yaml").write_text("format: [\n")     # half-written: the old plays on
    hook(frame)
    hook.wait()
    hook(frame)
    assert engine.behavior is good and "behavior.yaml" in hook.problem
    assert "still playing" in engine.step(frame)[0].label
    assert caplog.text.count("behaviour not reloaded") == 1


def _studio(tmp_path):
    """A designer studio on a library of bully and lover, its trainings in workers, and
    bully picked and in play (frame time 1.2 s)."""
    e, bench, lib = _library(tmp_path)
    target = bench.studio.targets["pet"]
    pucks = (Puck(1, 0.4, 0.3, 0.0), Puck(2, 0.6, 0.3, 0.0))
    bench.step(Frame(seq=0, t=1.0, pucks=pucks, commands=("designer.item_next",)))
    target.loader.wait()
    bench.step(Frame(seq=1, t=1.2, pucks=pucks))
    assert e.behavior_name == "bully"
    target.play_poller.every_s = 0.0
    return e, bench, target, lib, pucks


def _edit(folder: Path) -> None:
    y = folder / "behavior.yaml"
    y.write_text(y.read_text() + "\n# edited\n")


def _take(bench, stop_at: int, edit_at: int | None = None, folder: Path | None = None):
    """Record a 12 s take from frame time 2 s and stop it at frame ``stop_at``; the playing
    folder edited (and the loop's poll hook run) after frame ``edit_at``. The stop's frame."""
    demo = designers.demonstrate("lover", seed=8, seconds=12)
    frames = list(demo_frames(demo, {10: ("designer.record",), stop_at: ("designer.record",)},
                              t0=2.0))[:stop_at + 1]
    for i, f in enumerate(frames):
        bench.step(f)
        if i == edit_at:
            _edit(folder)
            bench.studio.poll()
    return frames[-1]


def test_a_hot_reload_waits_while_a_take_trains(tmp_path, trainings):
    calls, release = trainings
    release.set()
    e, bench, target, lib, pucks = _studio(tmp_path)
    release.clear()                      # the take's training waits
    stop = _take(bench, 400)
    assert bench.studio.state == "training"
    _edit(lib / "bully")
    bench.studio.poll()                  # the tick after the stop: the take trains, blocked
    assert target._loading is None       # seen after the take
    release.set()
    target.trainer.wait()
    target.loader.wait()
    for k in range(1, 30):               # past the take's swap and a reload's LOAD_S
        bench.step(Frame(seq=500 + k, t=stop.t + 0.01 * k, pucks=pucks))
    assert bench.studio.state == "trying" and e.behavior is target.pending
    assert e.behavior_name == "new take"


def test_a_hot_reload_done_while_a_take_is_tried_is_what_a_discard_plays(tmp_path, trainings):
    calls, release = trainings
    release.set()
    e, bench, target, lib, pucks = _studio(tmp_path)
    old = e.behavior
    bench.studio.swap_s = 0.0            # the take swaps in before the reload's LOAD_S is over
    stop = _take(bench, 400, edit_at=398, folder=lib / "bully")
    assert target._loading == lib / "bully"
    target.trainer.wait()
    target.loader.wait()
    bench.step(Frame(seq=500, t=stop.t + 0.01, pucks=pucks))
    assert bench.studio.state == "trying" and e.behavior is target.pending
    bench.step(Frame(seq=501, t=stop.t + 0.3, pucks=pucks))
    assert e.behavior is target.pending and e.behavior_name == "new take"
    bench.step(Frame(seq=502, t=stop.t + 0.4, pucks=pucks, commands=("designer.discard",)))
    assert e.behavior_name == "bully" and e.behavior is not old and e.behavior is not None


def test_a_failed_pick_leaves_the_shelf_on_the_one_in_play(tmp_path, trainings):
    calls, release = trainings
    release.set()
    e, bench, target, lib, pucks = _studio(tmp_path)
    bully = e.behavior
    (lib / "lover" / "demonstration.csv").write_text("t,x\n1,oops\n")   # found in the worker
    bench.step(Frame(seq=2, t=2.0, pucks=pucks, commands=("designer.item_next",)))
    bench.step(Frame(seq=3, t=2.2, pucks=pucks))
    assert e.behavior is bully and target.current() == "bully"
    bench.step(Frame(seq=4, t=2.3, pucks=pucks, commands=("designer.rename:sweet",)))
    assert e.behavior_name == "sweet" and (lib / "sweet").is_dir()
    assert (lib / "lover").is_dir()
    bench.step(Frame(seq=5, t=2.4, pucks=pucks, commands=("designer.delete",)))
    assert e.behavior_name == "sweet (deleted)" and (lib / "lover").is_dir()


@pytest.mark.parametrize("command", ["designer.rename:sweet", "designer.delete"])
def test_a_rename_or_delete_while_a_pick_loads_acts_on_the_picked_one(tmp_path, trainings,
                                                                      command):
    calls, release = trainings
    release.set()
    e, bench, lib = _library(tmp_path)
    pucks = (Puck(1, 0.4, 0.3, 0.0),)
    bench.step(Frame(seq=0, t=10.0, pucks=pucks, commands=("designer.item_next",)))
    bench.step(Frame(seq=1, t=10.05, pucks=pucks, commands=(command,)))   # within LOAD_S
    bench.step(Frame(seq=2, t=10.3, pucks=pucks))
    bench.studio.poll()
    out, studio = bench.step(Frame(seq=3, t=10.4, pucks=pucks))
    assert e.behavior is not None and "not played" not in studio.label
    if command == "designer.delete":
        assert e.behavior_name == "bully (deleted)" and not (lib / "bully").exists()
    else:
        assert e.behavior_name == "sweet" and bench.studio.targets["pet"].current() == "sweet"


def test_a_hot_reload_started_in_a_takes_first_tick_plays(tmp_path, trainings):
    calls, release = trainings
    release.set()
    e, bench, target, lib, pucks = _studio(tmp_path)
    before = e.behavior
    _edit(lib / "bully")                  # the record's tick begins the take; the loop's poll
    bench.step(Frame(seq=2, t=1.3, pucks=pucks, commands=("designer.record",)))   # hook after
    bench.studio.poll()
    target.loader.wait()
    for i in range(3, 10):
        bench.step(Frame(seq=i, t=1.3 + 0.05 * (i - 2), pucks=pucks))
    assert target._loading is None and e.behavior is not before


def test_a_reload_that_fails_says_the_version_read_before_plays_on(tmp_path, trainings):
    calls, release = trainings
    release.set()
    e, bench, target, lib, pucks = _studio(tmp_path)
    bully = e.behavior
    (lib / "bully" / "behavior.yaml").write_text("format: [\n")
    bench.studio.poll()
    bench.step(Frame(seq=2, t=1.5, pucks=pucks))
    bench.studio.poll()
    _, studio = bench.step(Frame(seq=3, t=1.6, pucks=pucks))
    assert e.behavior is bully and target.current() == "bully"
    assert "bully not reloaded" in studio.label
    assert "the version read before plays on" in studio.label


def test_a_folder_edited_from_one_bad_value_to_another_is_said_once(tmp_path, trainings, caplog):
    """behavior.yaml of the behaviour in play edited from one bad value to another: the reload
    dropped the folder's problem as it began, before the worker read the file, so the log said
    the new error, then "no longer said (fixed or removed)" of it while it was still bad, then
    the same error again."""
    calls, release = trainings
    release.set()
    e, bench, target, lib, pucks = _studio(tmp_path)
    target.lib_poller.every_s = 0.0
    bully, y = e.behavior, lib / "bully" / "behavior.yaml"
    text = y.read_text()
    seq, t = 2, 1.5
    with caplog.at_level("INFO", logger="tabletop"):
        for bad in ("ratio: -1.0", "ratio: abc"):
            y.write_text(text.replace("  rate_hz:", f"  {bad}\n  rate_hz:"))
            # the library's listing looks first, the behaviour in play's poller a look later
            # (each looks once a second, on its own phase)
            target.play_poller._next = math.inf
            for i in range(4):       # the loop's looks, and the ticks the worker swaps in at
                bench.studio.poll()
                target.play_poller._next = 0.0
                target.loader.wait()
                seq, t = seq + 1, t + 0.1
                bench.step(Frame(seq=seq, t=t, pucks=pucks))
    said = [r.getMessage() for r in caplog.records if r.getMessage().startswith("library: ")]
    assert e.behavior is bully
    assert len(said) == 3, said
    assert "-1" in said[0] and "abc" in said[1] and "abc" not in said[2], said
    assert said[2].startswith("library: no longer said (fixed or removed): ") and "-1" in said[2]


def test_a_reload_that_took_is_said_as_one_refused_is(tmp_path, trainings, caplog):
    """A parameter edited in behavior.yaml of the behaviour in play: the studio said a reload
    it refused ("bully not reloaded: ...") but nothing of one that took, which outside the
    studio is logged ("behaviour ... reloaded")."""
    calls, release = trainings
    release.set()
    e, bench, target, lib, pucks = _studio(tmp_path)
    bully, y = e.behavior, lib / "bully" / "behavior.yaml"
    y.write_text(y.read_text().replace("  rate_hz:", "  ratio: 2.0\n  rate_hz:"))
    with caplog.at_level("INFO", logger="tabletop"):
        bench.studio.poll()
        target.loader.wait()
        bench.step(Frame(seq=2, t=1.5, pucks=pucks))
        bench.studio.poll()
        _, studio = bench.step(Frame(seq=3, t=1.6, pucks=pucks))
    assert e.behavior is not bully and e.behavior.params.ratio == 2.0
    assert "bully reloaded: its files changed" in studio.label, studio.label
    assert "studio: bully reloaded" in caplog.text
    # the item in play picked again (] on a library of one) is no edit: not said so
    caplog.clear()
    with caplog.at_level("INFO", logger="tabletop"):
        target.use("bully")
        target.loader.wait()
        bench.step(Frame(seq=4, t=2.0, pucks=pucks))
        bench.studio.poll()
    assert "reloaded" not in caplog.text, caplog.text
