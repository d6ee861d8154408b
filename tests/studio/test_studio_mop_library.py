"""Two studio runs on one MOP library (a take named as the other run's keep, keeps at once), and a
keep in an engine without a library."""

from pathlib import Path

import numpy as np
import yaml

from tabletop.plugins.mop_table import build, designer_config
from tabletop.studio.mop_table import StudioTable
from tests.studio.mop_table import face_take, kept_line, kept_without_library


def two_takes(tmp_path):
    """Two runs (A and B) on one library, each with a pending take of the face named take1;
    A keeps its take and B's watcher sees it. Returns (A's table, B's table, B's engine, B's
    take's samples)."""
    (engine_a, a), (engine_b, b) = (face_take(tmp_path, g) for g in ("line", "square"))
    assert "take1 -> " in a.status and "take1 -> " in b.status
    engines = [engine_a, engine_b]
    own = engines[1].templates["face"]["take1"][1].copy()
    a.tick(["designer.keep"])
    assert "kept as take1" in a.status
    b.studio.poll()
    return a, b, engines[1], own


def test_a_take_whose_name_another_run_kept_meanwhile_is_kept_under_the_next_name(tmp_path):
    """Another run on the library kept its take1 while this run's take1 was tried: the
    watcher put that take1 over the one tried here, and K was refused ("'take1' is in the
    library already") for as long as the take was tried, so it could not be kept."""
    a, b, engine, own = two_takes(tmp_path)
    assert np.array_equal(engine.templates["face"]["take1"][1], own)   # still its own take
    b.tick(["designer.keep"])
    assert "kept as take2" in b.status and b.studio.state == "idle", b.status
    folder = tmp_path / "lib" / "face"
    entries = yaml.safe_load((folder / "actions.yaml").read_text())["actions"]
    assert [e["name"] for e in entries] == ["take1", "take2"]
    theirs = a.engine.templates["face"]["take1"][1]
    assert np.array_equal(engine.templates["face"]["take2"][1], own)
    assert np.array_equal(engine.templates["face"]["take1"][1], theirs)   # the other's, followed
    assert set(engine.puppets["face"].actions) == {"circle", "take1", "take2"}
    again = build(designer_config(tmp_path), tmp_path)
    assert again.templates["face"]["take2"][1].shape == own.shape


def test_a_discarded_take_gives_way_to_the_other_runs_action_of_its_name(tmp_path):
    a, b, engine, own = two_takes(tmp_path)
    b.tick(["designer.discard"])
    assert np.array_equal(engine.templates["face"]["take1"][1],
                          a.engine.templates["face"]["take1"][1])
    assert "take1" in engine.puppets["face"].actions


KEEPER = """
import sys
from pathlib import Path
import numpy as np
sys.path.insert(0, {root!r})
from tabletop.plugins.mop_library import save_to_library
for i in range(40):
    save_to_library(Path({lib!r}), "face", "{who}%d" % i, np.zeros((5, 2)), ("dx", "dy"),
                    "talk", 30.0)
"""


def test_two_runs_keeping_into_one_library_at_once_keep_every_take(tmp_path):
    """Each keep read actions.yaml, wrote its template and wrote the entries it had read with
    its own: two processes keeping 40 takes each into one character's library left 43 entries
    of 80 (the others' templates on disk, named by no entry)."""
    import subprocess
    import sys
    from tabletop.plugins.mop_library import read_library
    root = str(Path(__file__).resolve().parents[2])
    runs = [subprocess.Popen([sys.executable, "-c", KEEPER.format(root=root, lib=str(tmp_path),
                                                                  who=who)]) for who in "ab"]
    assert [r.wait(timeout=120) for r in runs] == [0, 0]
    names = sorted(a["name"] for a in read_library(tmp_path, "face"))
    assert names == sorted(f"{who}{i}" for who in "ab" for i in range(40))


def test_a_keep_without_a_library_says_it_is_for_this_run_only(tmp_path):
    """An engine without a library said "kept as take1" like a saved keep; nothing was
    written and the take was gone at the next start."""
    engine, table, _ = kept_without_library(tmp_path)
    assert table.status == ("[mop/face] kept as take1 for this run only: engine 'mop' has no "
                            "library to save it in (give it library: FOLDER in the config)")
    assert "take1" in engine.puppets["face"].actions and not any(tmp_path.iterdir())
    _, saved = kept_line(tmp_path)                # with a library: saved, said where
    assert saved.status == f"[mop/face] kept as take1 in {tmp_path / 'lib' / 'face'}/"
    assert (tmp_path / "lib" / "face" / "take1.csv").is_file()


HOLDER = """
import sys, time
sys.path.insert(0, {root!r})
from pathlib import Path
from tabletop.plugins.mop_library import library_lock
with library_lock(Path({lib!r}), "face"):
    print("held", flush=True)
    time.sleep(600)
"""


def test_a_keep_while_another_run_holds_the_library_is_refused_and_the_take_stays(tmp_path):
    """K waited without limit, in the frame loop's thread, for another run holding the
    library's lock (a run stopped with Ctrl-Z): the installation froze until that run died."""
    import subprocess
    import sys
    root = str(Path(__file__).resolve().parents[2])
    engine, table = face_take(tmp_path, "line")
    holder = subprocess.Popen([sys.executable, "-c", HOLDER.format(root=root,
                                                                   lib=str(tmp_path / "lib"))],
                              stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == "held"
        table.tick(["designer.keep"])
        assert "busy, another run is saving" in table.status, table.status
        assert table.studio.state == "trying" and "take1" in engine.puppets["face"].actions
    finally:
        holder.kill()
        holder.wait()
    table.tick(["designer.keep"])
    assert table.status == f"[mop/face] kept as take1 in {tmp_path / 'lib' / 'face'}/"
    assert (tmp_path / "lib" / "face" / "take1.csv").is_file()


def test_another_runs_keep_just_before_this_runs_keep_is_followed(tmp_path):
    """This run's keep marked the library as seen: another run's keep made since the watcher
    last looked (within its second) was never followed."""
    engine_b = build(designer_config(tmp_path), tmp_path)     # B starts on an empty library
    b = StudioTable(engine_b, tmp_path / "lib")
    b.targets[0]._poller.every_s = 1e9                          # B's watcher does not look
    _, a = face_take(tmp_path, "line")
    a.tick(["designer.keep"])                                   # A keeps take1
    b.rest(1.0)
    b.tick(["designer.record"])
    b.perform("square")
    b.tick(["designer.record"])
    b.tick(["designer.keep"])
    assert b.status.startswith("[mop/face] kept as take2 in "), b.status
    b.targets[0]._poller.every_s = 0.0
    for _ in range(3):
        b.studio.poll()
        b.tick()
    assert set(engine_b.puppets["face"].actions) == {"circle", "take1", "take2"}


def test_a_config_edit_saves_the_takes_kept_for_this_run_only_into_its_new_library(tmp_path):
    """The keep says "give it library: FOLDER in the config"; doing so rebuilt the installation
    and dropped every take kept for this run only, without a word. An edit that gives the
    engine a library saves them into it; one that gives none says which it dropped."""
    from tabletop.config import validate_config
    from tabletop.kiosk.runner import Runner
    engine, table, cfg = kept_without_library(tmp_path)
    path = tmp_path / "config.yaml"
    path.write_text(yaml.safe_dump(cfg))
    runner = Runner(path, validate_config(cfg, str(path), tmp_path), headless=True)
    runner.studio = table.studio
    runner._save_run_only(validate_config(cfg, str(path), tmp_path))   # still no library
    assert runner._notes == ["config edit dropped mop/face's takes kept for this run only: "
                             "take1 (engine 'mop' has no library)"]
    assert table.targets[0].run_only == []
    table.targets[0].run_only = ["take1"]
    runner._notes = []
    with_lib = designer_config(tmp_path)                               # library: lib
    runner._save_run_only(validate_config(with_lib, str(path), tmp_path))
    assert runner._notes == [f"kept take1 -> laugh in {tmp_path / 'lib' / 'face'}"]
    rebuilt = build(with_lib, tmp_path)
    assert set(rebuilt.puppets["face"].actions) == {"circle", "take1"}
    assert np.allclose(rebuilt.templates["face"]["take1"][1], engine.templates["face"]["take1"][1])


def test_a_config_edit_saves_a_take_kept_for_this_run_only_under_a_free_name(tmp_path):
    """Takes kept without a library are take1, take2...; the library a config edit gives often
    has a take1 from an earlier session: the take is saved as the next free takeN, not dropped."""
    from tabletop.config import validate_config
    from tabletop.kiosk.runner import Runner
    from tabletop.plugins.mop_library import save_to_library
    engine, table, cfg = kept_without_library(tmp_path)
    performer, samples = engine.templates["face"]["take1"]
    earlier = samples[::-1].copy()
    save_to_library(tmp_path / "lib", "face", "take1", earlier,
                    engine.performers[performer].names, "laugh", engine.rate_hz)
    path = tmp_path / "config.yaml"
    path.write_text(yaml.safe_dump(cfg))
    runner = Runner(path, validate_config(cfg, str(path), tmp_path), headless=True)
    runner.studio = table.studio
    with_lib = designer_config(tmp_path)
    runner._save_run_only(validate_config(with_lib, str(path), tmp_path))
    (note,) = runner._notes
    assert note.startswith("face/take1 renamed take2 (take1 is in the library already): kept take2")
    rebuilt = build(with_lib, tmp_path)
    assert set(rebuilt.puppets["face"].actions) == {"circle", "take1", "take2"}
    assert np.allclose(rebuilt.templates["face"]["take2"][1], samples)
    assert np.allclose(rebuilt.templates["face"]["take1"][1], earlier)


def test_a_take_kept_for_this_run_only_is_saved_with_its_motion_as_the_config_names_it(tmp_path):
    """A face whose motion is a designer's file (grin.json, clip named "grin"): the take saved
    at a config edit names grin.json, so the rebuilt engine loads it."""
    import json
    from behaviors.motion.clips import clip_to_mapping
    from tabletop.config import validate_config
    from tabletop.kiosk.runner import Runner
    from tabletop.plugins.mop_files import MotionLoader
    clip = clip_to_mapping(MotionLoader("face", tmp_path)("laugh"))
    clip["name"] = "grin"
    (tmp_path / "grin.json").write_text(json.dumps(clip))
    cfg = designer_config(tmp_path)
    cfg["engines"][0]["characters"][0]["motions"] = ["grin.json"]
    engine, table, cfg = kept_without_library(tmp_path, cfg)
    path = tmp_path / "config.yaml"
    path.write_text(yaml.safe_dump(cfg))
    runner = Runner(path, validate_config(cfg, str(path), tmp_path), headless=True)
    runner.studio = table.studio
    with_lib = designer_config(tmp_path)
    with_lib["engines"][0]["characters"][0]["motions"] = ["grin.json"]
    runner._save_run_only(validate_config(with_lib, str(path), tmp_path))
    rebuilt = build(with_lib, tmp_path)
    assert rebuilt.library_problems.get("face", []) == []
    assert set(rebuilt.puppets["face"].actions) == {"circle", "take1"}
    assert rebuilt.puppets["face"].actions["take1"].clip.name == "grin"


def test_keeps_while_another_run_stalls_on_the_library_leave_one_waiter(tmp_path):
    """Each keep refused while another run held the library left one more thread blocked in
    flock, with its open descriptor, until that run let go; one waiter per lock file now, and
    a keep once the holder is gone takes the lock."""
    import os
    import subprocess
    import sys
    import threading
    from tabletop.frames import InputError
    from tabletop.plugins.mop_library import library_lock
    root = str(Path(__file__).resolve().parents[2])
    lib = tmp_path / "lib"
    (lib / "face").mkdir(parents=True)

    def waiters() -> int:
        return sum(t.name == "lock-wait" for t in threading.enumerate())

    fds = len(os.listdir("/proc/self/fd"))
    holder = subprocess.Popen([sys.executable, "-c", HOLDER.format(root=root, lib=str(lib))],
                              stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == "held"
        for _ in range(4):
            try:
                with library_lock(lib, "face"):
                    raise AssertionError("locked while another run holds it")
            except InputError as exc:
                assert "busy, another run is saving" in str(exc)
        assert waiters() == 1
        assert len(os.listdir("/proc/self/fd")) - fds <= 2    # the waiter's, the pipe's
    finally:
        holder.kill()
        holder.wait()
        holder.stdout.close()
    with library_lock(lib, "face"):
        pass
    for t in threading.enumerate():
        if t.name == "lock-wait":
            t.join(5.0)
    assert waiters() == 0 and len(os.listdir("/proc/self/fd")) == fds


def test_a_lock_call_that_fails_raises_its_own_error():
    """A flock that fails (ENOLCK on a mount without locks; here EBADF, a descriptor no file
    has) raised in the helper thread, which died; the wait ran out and said "busy"."""
    import errno
    import os
    import pytest
    from tabletop.swap import _flock_within
    fd = 4000
    with pytest.raises(OSError):
        os.fstat(fd)
    with pytest.raises(OSError) as err:
        _flock_within(fd, 30.0, "no-such-lock")
    assert err.value.errno == errno.EBADF


def test_a_keep_whose_actions_file_cannot_be_written_leaves_no_template_behind(tmp_path,
                                                                               monkeypatch):
    """A full disk at the keep's actions.yaml: the library is as it was (its entries and
    files), so the take is kept again under its own name once the disk takes it."""
    import errno
    import os

    import pytest

    from tabletop.plugins.mop_library import read_library, save_to_library
    lib, x = tmp_path / "lib", np.cumsum(np.full((40, 2), 0.01), axis=0)
    save_to_library(lib, "face", "take1", x, ("dx", "dy"), "laugh", 30.0)
    before = {p.name: p.read_bytes() for p in (lib / "face").iterdir()}
    replace = os.replace

    def full(src, dst):
        if str(dst).endswith("actions.yaml"):
            raise OSError(errno.ENOSPC, "No space left on device")
        return replace(src, dst)

    monkeypatch.setattr(os, "replace", full)
    with pytest.raises(Exception, match="actions.yaml"):
        save_to_library(lib, "face", "take2", x, ("dx", "dy"), "talk", 30.0)
    assert {p.name: p.read_bytes() for p in (lib / "face").iterdir()} == before
    monkeypatch.setattr(os, "replace", replace)
    assert save_to_library(lib, "face", "take2", x, ("dx", "dy"), "talk", 30.0).startswith(
        "kept take2 -> talk")
    assert [e["name"] for e in read_library(lib, "face")] == ["take1", "take2"]
