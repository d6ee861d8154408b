"""Nothing lost: a process killed with SIGKILL while it saves behaviours leaves every saved
behaviour intact and loadable; a recording cut the same way loses at most its last line."""

import os
import random
import signal
import time

import numpy as np

from behaviors.puppet_master import designers
from tabletop import library
from tabletop.frames import Frame, Puck
from tabletop.recorder import Recorder, read_frames


def killed_while(work, rng, window_s=0.03):
    """Fork a process running ``work()`` forever, SIGKILL it at a random moment once it has
    started, and reap it."""
    r, w = os.pipe()
    pid = os.fork()
    if pid == 0:                                   # the child: never returns to pytest
        try:
            os.close(r)
            os.write(w, b"go")
            work()
        finally:
            os._exit(0)
    os.close(w)
    assert os.read(r, 2) == b"go"
    os.close(r)
    time.sleep(rng.uniform(0.0, window_s))
    os.kill(pid, signal.SIGKILL)
    _, status = os.waitpid(pid, 0)
    assert os.WIFSIGNALED(status) and os.WTERMSIG(status) == signal.SIGKILL
    return pid


def test_kill_9_during_library_saves_leaves_the_previous_behaviour_intact(tmp_path):
    lib = tmp_path / "lib"
    a = designers.demonstrate("lover", seed=1, seconds=10)
    b = designers.demonstrate("afraid", seed=2, seconds=12)
    library.save_behavior(lib, "pet", a, {"rate_hz": 40})
    rng = random.Random(15)
    counter = [0]

    def save_forever():
        i = 0
        while True:
            i += 1
            library.save_behavior(lib, "pet", b if i % 2 else a, {"rate_hz": 40}, replace=True)
            library.save_behavior(lib, f"new-{os.getpid()}-{i}", a, {})

    for _ in range(25):                  # a save of both takes ~0.1 s here: kills land all along
        pid = killed_while(save_forever, rng, window_s=0.25)
        counter[0] += 1
        pet = library.load_behavior(lib / "pet")
        same_a = pet.demonstration.shape == a.shape and np.allclose(pet.demonstration, a)
        same_b = pet.demonstration.shape == b.shape and np.allclose(pet.demonstration, b)
        assert same_a or same_b
        # a new behaviour appears whole or not at all (a half-written one stays hidden)
        for name in library.list_behaviors(lib):
            if f"-{pid}-" in name:
                assert len(library.load_behavior(lib / name).demonstration) in (len(a), len(b))
        visible = [p for p in lib.iterdir() if not p.name.startswith(".")]
        assert all((p / "behavior.yaml").is_file() for p in visible)
    assert counter[0] == 25 and len(library.list_behaviors(lib)) > 3


def test_kill_9_while_recording_loses_at_most_the_last_line(tmp_path):
    rng = random.Random(7)
    for k in range(12):
        path = tmp_path / f"session-{k}.jsonl"
        r, w = os.pipe()

        def record_forever():
            rec = Recorder(path, config={"loop": {"rate_hz": 60}})
            i = 0
            while True:
                rec.consume(Frame(seq=i, t=100 + i / 60, pucks=(Puck(1, 0.1 * (i % 9), 0.2, 0.0),)))
                i += 1
                if i % 25 == 0:
                    os.write(w, i.to_bytes(4, "little"))  # acknowledged: these are written

        killed_while(record_forever, rng, window_s=0.3)
        os.close(w)
        acked = 0
        while chunk := os.read(r, 4096):
            acked = int.from_bytes(chunk[-4:], "little")
        os.close(r)
        if acked == 0 and (not path.exists() or path.stat().st_size == 0):
            continue                                  # killed before it wrote anything
        frames = list(read_frames(path))
        assert len(frames) >= acked
        assert [f.seq for f in frames] == list(range(len(frames)))
        lines = path.read_bytes().split(b"\n")
        assert len(lines) - 2 <= len(frames) + 1      # only the last line may be incomplete
