"""A behaviour saved over an existing one is whole or not at all: a real process killed at every
file-system step of the save leaves the old behaviour or the new one (never the new
demonstration beside the old behavior.yaml), loses nothing, and leaves no hidden folder after
the next read; a reader never loads a mix while another process saves."""

import os
import subprocess
import sys
from pathlib import Path

import numpy as np

from tabletop import library, swap

ROOT = Path(__file__).resolve().parents[2]

# run in a child: save VERSION over LIB/bully, dying (os._exit) at the K-th call of a
# file-system function (K = 0: never), or saving versions 0 and 1 alternately COUNT times;
# K = -1: for each K read on stdin, a process forked from this one (imports done) saves once,
# dying at its K-th call, and its exit status is written back (one interpreter start, not one
# a step: 0.3-0.4 CPU s each)
CHILD = """
import os, sys
sys.path.insert(0, {root!r})
from tabletop import library, swap
from tests.puppet_master.test_library_swap import _version as version
lib, k, count = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
steps = {{os.rename, os.replace, os.fsync, os.unlink, os.rmdir, os.mkdir, os.chmod, os.open}}
calls = [0]
def die_at_k(frame, event, arg):
    if event == "c_call" and arg in steps:
        calls[0] += 1
        if calls[0] == k:
            os._exit(9)
def save():
    for i in range(count):
        demo, params = version((i + 1) % 2)
        if k:
            sys.setprofile(die_at_k)
        library.save_behavior(lib, "bully", demo, params, replace=True)
        sys.setprofile(None)
    os._exit(0)
if k >= 0:
    save()
for line in sys.stdin:
    k = int(line)
    pid = os.fork()
    if pid == 0:
        save()
    print(os.waitstatus_to_exitcode(os.waitpid(pid, 0)[1]), flush=True)
os._exit(0)
"""


def _version(v: int) -> tuple[np.ndarray, dict]:
    t = np.arange(20 + 10 * v) / 10.0
    demo = np.column_stack([t, 0.5 + 0.01 * t, 0.5 + 0 * t, 0 * t, 0.3 + v * 0.1 + 0 * t,
                            0.4 + 0 * t, 0 * t])
    return demo, {"ratio": 1.0 + v, "window": 40 + v}


def _which(stored: library.StoredBehavior) -> int:
    """0 or 1: the whole version ``stored`` is; fails on a mix of the two."""
    for v in (0, 1):
        demo, params = _version(v)
        if stored.demonstration.tobytes() == demo.tobytes():
            assert stored.parameters == params, "new demonstration beside the old behavior.yaml"
            assert stored.extra["samples"] == len(demo)
            return v
    raise AssertionError(f"neither version: {stored}")


def _kept(lib: Path) -> list[str]:
    """The names in ``lib`` but the save locks' files (kept: removing one races its waiters)."""
    return sorted(p.name for p in lib.iterdir() if not p.name.endswith(swap.LOCK_SUFFIX))


def _child(tmp_path: Path, lib: Path, k: int, count: int = 1, **popen) -> subprocess.Popen:
    script = tmp_path / "child.py"
    script.write_text(CHILD.format(root=str(ROOT)))
    return subprocess.Popen([sys.executable, str(script), str(lib), str(k), str(count)], **popen)


def test_a_save_killed_at_every_step_leaves_the_old_or_the_new_behaviour(tmp_path):
    lib = tmp_path / "library"
    seen = []
    saver = _child(tmp_path, lib, -1, stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
    try:
        for k in range(1, 200):
            demo, params = _version(0)
            folder = library.save_behavior(lib, "bully", demo, params, replace=True)
            (folder / "notes.txt").write_text("the designer's notes")      # not the library's
            saver.stdin.write(f"{k}\n")
            saver.stdin.flush()
            rc = int(saver.stdout.readline())         # the forked save's exit status
            stored = library.load_behavior(folder)                         # recovers first
            seen.append((rc, _which(stored)))
            assert (folder / "notes.txt").read_text() == "the designer's notes"
            assert _kept(lib) == ["bully"]                                  # nothing left over
            assert library.list_behaviors(lib) == ["bully"]
            if rc == 0:
                break
    finally:
        saver.stdin.close()
        assert saver.wait(30) == 0
    assert seen[-1] == (0, 1)                          # the save finished: the new one
    killed = [v for rc, v in seen if rc == 9]
    assert killed.count(0) > 3 and killed.count(1) > 0   # killed before and after the swap


def test_a_reader_never_loads_a_mix_while_another_process_saves(tmp_path):
    lib = tmp_path / "library"
    demo, params = _version(0)
    folder = library.save_behavior(lib, "bully", demo, params)
    child = _child(tmp_path, lib, 0, count=50)
    versions = set()
    while child.poll() is None:
        versions.add(_which(library.load_behavior(folder)))
    assert child.wait() == 0
    assert _which(library.load_behavior(folder)) == 0 and versions <= {0, 1}
    assert 1 in versions                                # a read overlapped the saves
    assert _kept(lib) == ["bully"]


def test_leftovers_of_ended_saves_are_recovered_and_logged(tmp_path, caplog):
    lib = tmp_path / "library"
    demo, params = _version(0)
    folder = library.save_behavior(lib, "bully", demo, params)
    os.rename(folder, lib / ".bully.tabletop-swap-a1.old")    # killed between the renames
    (lib / ".bully.tabletop-swap-a1.new").mkdir()             # (its new one unfinished)
    (lib / ".bully.tabletop-swap-k2x_9.tmp").mkdir()          # a first save killed
    (lib / ".bully.1.tabletop-swap-b2.old").mkdir()           # another behaviour's, "bully.1"
    assert library.list_behaviors(lib) == ["bully"]
    assert _which(library.load_behavior(folder)) == 0
    assert _kept(lib) == ["bully", "bully.1"]
    assert "previous version is restored" in caplog.text and "unfinished save" in caplog.text


def test_the_running_installation_reloads_only_whole_behaviours(tmp_path):
    from tabletop.config import validate_config
    from tabletop.plugins import puppet_master as pm
    from tabletop.registry import BuildContext
    from tabletop.studio.reloader import BehaviorReloader
    lib = tmp_path / "library"
    demo, params = _version(0)
    folder = library.save_behavior(lib, "bully", demo, params)
    cfg = validate_config({"sources": [{"kind": "scripted"}], "engines": [
        {"kind": "puppet_master", "name": "pet", "behavior": str(folder)}]}, "t.yaml", tmp_path)
    engine = pm.build(cfg["engines"][0], BuildContext((1.2, 0.8), 60.0, cfg, tmp_path))
    hook = BehaviorReloader(engine)
    hook.poller.every_s = 0.0                   # looks at every call (the loop: once a second)
    child = _child(tmp_path, lib, 0, count=60)
    played = set()
    while child.poll() is None:
        hook()
        hook.wait()                             # each read trained and played (the loop: later)
        assert not hook.problem
        b = engine.behavior
        played.add(_which(library.StoredBehavior(folder, "bully", "puppet_master",
                                                 {"ratio": b.params.ratio,
                                                  "window": b.params.window}, b.demo,
                                                 extra={"samples": len(b.demo)})))
    assert child.wait() == 0 and played <= {0, 1}
    assert 1 in played                          # the new version was reloaded and played
