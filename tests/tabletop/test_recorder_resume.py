"""A recording a full disk (or a disk that could not keep up) stopped resumes in a new part once
the disk takes one again.

The disk is full as the kernel says it: EFBIG from this process's file size limit
(RLIMIT_FSIZE, the soft limit only, so it can be raised again), real files, real writes; a disk
that cannot keep up: the real syncer thread, its fdatasync held until released."""

import os
import resource
import signal
import threading
import time

import numpy as np

from tabletop.frames import Frame
from tabletop.recorder import Recorder, read_frames, read_header
from tabletop.recorder_resume import RESUME_EVERY_S

HEADER = {"format": "tabletop-session", "version": 2, "config": {"note": "x" * 300}}


def frames(t0: float, seconds: float, rate: float = 10.0):
    """Frames every 1/rate s of frame time from ``t0`` (monotonic-like seconds), with a stream
    of 40 values so a line is about 1 KB."""
    for k in range(int(seconds * rate)):
        yield Frame(seq=k, t=t0 + k / rate, streams={"hand": np.arange(40) / 7.0})


def wait_caught_up(rec: Recorder, timeout_s: float = 30.0) -> None:
    """Wait (at most ``timeout_s`` s of real time) until the real syncer caught up."""
    end = time.monotonic() + timeout_s
    while not rec.caught_up and time.monotonic() < end:
        time.sleep(0.001)
    assert rec.caught_up


def test_a_recording_stopped_by_a_full_disk_resumes_in_a_new_part(tmp_path, caplog):
    """Tries on a disk still full leave nothing and say nothing (a kiosk's log said "recording
    resumes in FILE" at every failed try, FILE never made); the try that works says so once."""
    caplog.set_level("INFO", logger="tabletop")
    folder = tmp_path / "sessions"
    soft, hard = resource.getrlimit(resource.RLIMIT_FSIZE)
    old_handler = signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    rec = Recorder(folder=folder, header=HEADER)
    t = 5000.0
    try:
        resource.setrlimit(resource.RLIMIT_FSIZE, (16 * 1024, hard))   # the disk fills
        for f in frames(t, 10.0):
            rec.consume(f)
        assert rec.failed is not None and "File too large" in rec.failed
        assert rec.incomplete == rec.failed      # what run and replay --out say of it
        stopped_at = rec.frames
        assert 0 < stopped_at < 100
        resource.setrlimit(resource.RLIMIT_FSIZE, (200, hard))         # not even a header
        tries = []
        open_part = rec._open_part

        def counted(resumed=None):
            tries.append(resumed)
            open_part(resumed=resumed)

        rec._open_part = counted
        for f in frames(t + 10.0, 3 * RESUME_EVERY_S):                # three tries fail
            wait_caught_up(rec)     # a try waits for the syncer: frames come faster than it
            rec.consume(f)
        rec._open_part = open_part
        assert len(tries) == 3, tries
        assert rec.failed is not None and rec.frames == stopped_at
        assert [p.name for p in folder.iterdir()] == [rec.paths[0].name]   # no try left behind
        assert not [r for r in caplog.records if "resumes" in r.getMessage()]
        resource.setrlimit(resource.RLIMIT_FSIZE, (soft, hard))        # room again
        wait_caught_up(rec)   # the frames come faster than real time: the syncer closes the
                              # tries first, as it would in a try's 60 s
        for f in frames(t + 10.0 + 3 * RESUME_EVERY_S, RESUME_EVERY_S + 2.0):
            rec.consume(f)
    finally:
        resource.setrlimit(resource.RLIMIT_FSIZE, (soft, hard))
        signal.signal(signal.SIGXFSZ, old_handler)
        rec.close()
    assert rec.failed is None and len(rec.gaps) == 1 and "File too large" in rec.gaps[0]
    assert len(rec.paths) == 2 and sorted(folder.iterdir()) == sorted(rec.paths)
    # resumed, still not whole: the reason, the stop and the part the rest went on in
    said = rec.incomplete
    assert said is not None and said.startswith(rec.gaps[0]), said
    assert "stopped 1 time and went on in a new part" in said and rec.paths[1].name in said
    first, second = (list(read_frames(p, absolute=True)) for p in rec.paths)
    assert len(first) == stopped_at
    assert read_header(rec.paths[1])["part"] == 2
    # the second part starts at the first try after the room came back, times as they were
    resumed_at = second[0].t
    assert t + 10.0 + 3 * RESUME_EVERY_S <= resumed_at <= t + 10.0 + 4 * RESUME_EVERY_S + 1.0
    assert rec.frames == stopped_at + len(second) and len(second) > 10
    assert [f.t for f in second] == sorted(f.t for f in second)
    resumed = [r.getMessage() for r in caplog.records if "resumes" in r.getMessage()]
    assert len(resumed) == 1 and str(rec.paths[1]) in resumed[0], resumed


def test_a_line_the_full_disk_took_part_of_is_cut_off(tmp_path):
    """The disk takes the head of a line and refuses the rest: the head is cut off, so the part
    holds exactly the frames counted, also once the disk has room again (a buffered part kept
    the rest and wrote it on its close, completing a line counted as lost)."""
    folder = tmp_path / "sessions"
    soft, hard = resource.getrlimit(resource.RLIMIT_FSIZE)
    old_handler = signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    rec = Recorder(folder=folder, header=HEADER)
    try:
        resource.setrlimit(resource.RLIMIT_FSIZE, (16 * 1024 + 300, hard))   # mid-line
        for f in frames(5000.0, 10.0):
            rec.consume(f)
        assert rec.failed is not None and "File too large" in rec.failed
        on_disk = rec.paths[0].read_bytes()
        resource.setrlimit(resource.RLIMIT_FSIZE, (soft, hard))            # room again
    finally:
        resource.setrlimit(resource.RLIMIT_FSIZE, (soft, hard))
        signal.signal(signal.SIGXFSZ, old_handler)
        rec.close()
    assert on_disk.endswith(b"\n") and on_disk.count(b"\n") == rec.frames + 1
    closed = rec.paths[0].read_bytes()
    assert closed == on_disk and len(list(read_frames(rec.paths[0]))) == rec.frames


def test_a_recording_the_disk_could_not_keep_up_with_resumes_once_it_caught_up(
        tmp_path, monkeypatch, caplog):
    """The real syncer thread and real files, the disk's sync held until released (a stalled
    disk): past ``max_queue`` lines the recording stops; once the held syncs return and the
    syncer caught up, the next try opens a new part and the recording goes on there."""
    caplog.set_level("INFO", logger="tabletop")
    real, gate, syncing = os.fdatasync, threading.Event(), threading.Event()

    def stalled(fd):
        syncing.set()
        gate.wait(30)
        real(fd)

    folder = tmp_path / "sessions"
    rec = Recorder(folder=folder, header=HEADER, max_queue=20)
    monkeypatch.setattr(os, "fdatasync", stalled)
    stream = list(frames(5000.0, RESUME_EVERY_S + 20.0))
    try:
        rec.consume(stream[0])
        assert syncing.wait(10)                 # the syncer is held in the first line's sync
        for f in stream[1:60]:
            rec.consume(f)
        assert rec.failed is not None and "cannot keep up" in rec.failed
        stopped_at = rec.frames
        gate.set()                              # the disk answers again
        for f in stream[60:]:                   # and keeps up: each line synced before the next
            end = time.monotonic() + 30
            while not rec.caught_up and time.monotonic() < end:
                time.sleep(0.001)
            rec.consume(f)
    finally:
        gate.set()
        rec.close()
    assert rec.failed is None and len(rec.gaps) == 1 and "cannot keep up" in rec.gaps[0]
    assert len(rec.paths) == 2 and sorted(folder.iterdir()) == sorted(rec.paths)
    first, second = (list(read_frames(p, absolute=True)) for p in rec.paths)
    assert len(first) == stopped_at == 21       # one line in the held sync, 20 waiting
    assert read_header(rec.paths[1])["part"] == 2
    # resumed at the first frame RESUME_EVERY_S after the stop, every later frame recorded
    stop_t = stream[stopped_at].t          # the frame that found 20 lines waiting
    assert second[0].t == next(f.t for f in stream if f.t >= stop_t + RESUME_EVERY_S)
    assert [f.t for f in second] == [f.t for f in stream if f.t >= second[0].t]
    resumed = [r for r in caplog.records if "recording resumes" in r.getMessage()]
    assert len(resumed) == 1 and "cannot keep up" in resumed[0].getMessage()


def test_a_disk_that_stays_slow_is_logged_sparingly(tmp_path, caplog):
    """A disk slower than the frames for half an hour (every sync of the real syncer covering
    two lines that waited 1 s of the recorder's clock, a sync every 10 s): logged at once, then
    after 10, 20, 40 ... s up to every 600 s (LogGaps): 8 lines, where every 10 s wrote 180."""
    caplog.set_level("WARNING", logger="tabletop")
    now = [1000.0]
    rec = Recorder(folder=tmp_path / "sessions", header=HEADER, clock=lambda: now[0])
    stream = frames(5000.0, 3600.0)
    try:
        for _ in range(180):
            with rec._cv:                        # the syncer waits: one sync takes both lines
                rec.consume(next(stream))
                rec.consume(next(stream))
                now[0] += 1.0                    # read by the sync, once the lock is let go
            end = time.monotonic() + 30
            while not rec.caught_up and time.monotonic() < end:
                time.sleep(0.001)
            assert rec.caught_up
            now[0] += 9.0
    finally:
        rec.close()
    assert rec.durability.waited_max == 2 and rec.failed is None
    slow = [r for r in caplog.records if "slower than the frames" in r.getMessage()]
    assert len(slow) == 8                       # at 0, 10, 30, 70, 150, 310, 630 and 1230 s
    assert "2 lines waited 1000 ms for one sync" in slow[0].getMessage()


def test_a_disk_that_falls_behind_again_waits_twice_as_long(tmp_path, monkeypatch):
    """A disk slow for good stopped the recording every 77 s at 60 Hz (1,024 lines, then the
    60 s try), each time with an error line and a new part: each stop in a row now waits twice
    the last before its try (the real syncer, its syncs held while the disk falls behind)."""
    real, answers = os.fdatasync, threading.Event()
    answers.set()

    def sync(fd):
        answers.wait(30)
        real(fd)

    monkeypatch.setattr(os, "fdatasync", sync)
    rec = Recorder(folder=tmp_path / "sessions", header=HEADER, max_queue=20)
    stream = frames(5000.0, 9 * RESUME_EVERY_S)
    waits = []
    try:
        for _ in range(3):
            answers.clear()                          # the disk falls behind
            while rec.failed is None:
                last = next(stream)
                rec.consume(last)
            answers.set()                            # and keeps up again, a line a sync
            while rec.failed is not None:
                end = time.monotonic() + 30
                while not rec.caught_up and time.monotonic() < end:
                    time.sleep(0.001)
                f = next(stream)
                rec.consume(f)
            waits.append(f.t - last.t)
    finally:
        answers.set()
        rec.close()
    assert len(rec.gaps) == 3 and all("cannot keep up" in g for g in rec.gaps)
    assert [round(w / RESUME_EVERY_S) for w in waits] == [1, 2, 4], waits


def test_a_recording_stopped_by_any_write_error_resumes_once_the_folder_takes_parts(tmp_path):
    """Not only a full disk: a folder that stops taking files (here a file in its place, as an
    unmounted drive or a disk remounted read-only after an error leaves it) stopped the
    recording for the rest of the run; new parts are tried every RESUME_EVERY_S of frame time."""
    folder = tmp_path / "sessions"
    rec = Recorder(folder=folder, header=HEADER, max_mb=0.02)     # a part every ~20 lines
    t = 100.0
    try:
        for f in frames(t, 1.0):
            rec.consume(f)
        assert rec.failed is None and len(rec.paths) >= 1
        folder.rename(tmp_path / "moved")            # the parts so far, kept elsewhere
        folder.write_text("not a folder")            # the next part cannot be made
        for f in frames(t + 1.0, 5.0):
            rec.consume(f)
        assert rec.failed is not None and rec.failed.startswith(str(folder))
        why = rec.failed
        stopped_at = rec.frames
        folder.unlink()                              # the folder can be made again
        wait_caught_up(rec)
        for f in frames(t + 6.0, RESUME_EVERY_S + 2.0):
            rec.consume(f)
    finally:
        rec.close()
    assert rec.failed is None and rec.gaps == [why]
    assert rec.frames > stopped_at and sorted(folder.iterdir())
    for part in folder.iterdir():                    # the resumed parts read whole
        assert read_header(part)["format"] == "tabletop-session"
        assert len(list(read_frames(part))) > 0


def test_a_part_whose_folder_was_removed_goes_on_in_a_new_part(tmp_path, caplog):
    """The recordings folder removed while a part is written (a technician clearing the disk):
    within REMOVED_CHECK_S of frame time the recording goes on in a new part in the folder made
    again, the gap said in the log; the frames of the removed part since the last look are all
    that is lost, and the new part replays with its times."""
    import shutil

    from tabletop.recorder_resume import REMOVED_CHECK_S
    caplog.set_level("INFO", logger="tabletop")
    folder = tmp_path / "sessions"
    rec = Recorder(folder=folder, header=HEADER)
    t = 7000.0
    try:
        for f in frames(t, 5.0):
            rec.consume(f)
        wait_caught_up(rec)
        shutil.rmtree(folder)
        for f in frames(t + 5.0, 10.0):
            rec.consume(f)
            wait_caught_up(rec)
    finally:
        rec.close()
    parts = sorted(folder.glob("*.jsonl"))
    assert parts == [rec.path] and len(rec.paths) == 2, (parts, rec.paths)
    kept = list(read_frames(rec.path))
    assert read_header(rec.path)["part"] == 2
    # every frame from the first look after the removal on is on disk (times from the start)
    assert kept[0].t <= 5.0 + REMOVED_CHECK_S + 0.1, kept[0].t
    assert abs(kept[-1].t - 14.9) < 1e-6 and len(kept) >= 100 - 10 * REMOVED_CHECK_S
    assert rec.failed is None and len(rec.gaps) == 1 and "removed from disk, with its folder" \
        in rec.gaps[0], rec.gaps
    said = " ".join(r.getMessage() for r in caplog.records)
    assert "recording resumes in" in said and "removed from disk" in said
