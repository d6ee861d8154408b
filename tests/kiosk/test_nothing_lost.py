"""Nothing lost: a process killed with SIGKILL while it saves behaviours leaves every saved
behaviour intact and loadable; a recording syncs each line before it writes the next (a power
cut or a SIGKILL loses at most the line in flight), never holding up the frame loop."""

import os
import random
import signal
import threading
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
    t0 = time.monotonic()
    library.save_behavior(lib, "pet", a, {"rate_hz": 40})
    library.save_behavior(lib, "pet", b, {"rate_hz": 40}, replace=True)
    window_s = max(0.25, 2.5 * (time.monotonic() - t0))   # a loaded machine saves slower
    rng = random.Random(15)
    counter = [0]

    def save_forever():
        i = 0
        while True:
            i += 1
            library.save_behavior(lib, "pet", b if i % 2 else a, {"rate_hz": 40}, replace=True)
            library.save_behavior(lib, f"new-{os.getpid()}-{i}", a, {})

    for _ in range(25):                  # kills land all along the saves
        pid = killed_while(save_forever, rng, window_s=window_s)
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


def test_kill_9_while_recording_loses_no_line_written(tmp_path):
    """Frames at 60 Hz; the child reports how many lines it has written; SIGKILL at random
    moments: those lines are all there, in order, and at most the last line is cut."""
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
                time.sleep(1 / 60)
                if i % 5 == 0:                  # acknowledged: written, so they survive the kill
                    os.write(w, rec.frames.to_bytes(4, "little"))

        killed_while(record_forever, rng, window_s=0.5)
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


def frame(i):
    return Frame(seq=i, t=100 + i / 60, pucks=(Puck(1, 0.01 * i, 0.2, 0.0),))


def test_a_line_written_alone_is_synced_alone(tmp_path, monkeypatch):
    """The real fdatasync, watched: lines written one at a time (the next once the previous is
    reported durable) are each synced alone, the file ending with that line."""
    real, sizes = os.fdatasync, []

    def watched(fd):
        real(fd)
        sizes.append(os.fstat(fd).st_size)

    monkeypatch.setattr(os, "fdatasync", watched)
    path = tmp_path / "s.jsonl"
    rec = Recorder(path, config={"loop": {"rate_hz": 60}})
    header_syncs = len(sizes)
    for i in range(30):
        rec.consume(frame(i))
        end = time.monotonic() + 10
        while rec.durability.lines < i + 1 and time.monotonic() < end:
            time.sleep(0.001)
    rec.close()
    data = path.read_bytes()
    ends = [k + 1 for k, b in enumerate(data) if b == ord("\n")]
    assert sizes[header_syncs - 1] == ends[0]                 # the header, synced alone first
    assert sizes[header_syncs:header_syncs + 30] == ends[1:]  # then each frame line alone
    assert rec.durability.syncs == 30 and rec.durability.waited_max == 1
    assert len(rec.durability.latencies_s) == 30


def test_a_disk_that_stops_never_holds_up_the_frame_loop(tmp_path, monkeypatch, caplog):
    """fdatasync blocked (a stalled disk): consume() keeps returning; past ``max_queue`` lines
    waiting the recording stops with one clear line; what waited is written once the disk
    answers; a slow disk that answers again gets lines written together, and says so."""
    real, gate = os.fdatasync, threading.Event()
    syncing = threading.Event()

    def stalled(fd):
        syncing.set()
        gate.wait(30)
        real(fd)

    path = tmp_path / "s.jsonl"
    rec = Recorder(path, config={}, max_queue=20)
    monkeypatch.setattr(os, "fdatasync", stalled)
    rec.consume(frame(0))
    assert syncing.wait(10)                   # the syncer is stuck in the first line's sync
    for i in range(1, 60):
        rec.consume(frame(i))                 # returns: the frame loop never waits for the disk
    assert rec.failed is not None and "cannot keep up (20 lines waited" in rec.failed
    stopped = [r for r in caplog.records if "recording stopped" in r.getMessage()]
    assert len(stopped) == 1 and str(path) in stopped[0].getMessage()
    time.sleep(Recorder.SLOW_S)               # the disk answers late
    gate.set()
    rec.close()
    assert [f.seq for f in read_frames(path)] == list(range(21))   # 1 in flight + 20 waiting
    slow = [r for r in caplog.records if "slower than the frames" in r.getMessage()]
    assert len(slow) == 1 and "20 lines waited" in slow[0].getMessage()

