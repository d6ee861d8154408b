"""A recording's parts and the recordings a folder keeps: ``recorder.max_mb`` continues a session
in new parts, ``recorder.keep`` removes the oldest by the headers' order, never another run's
recording being written nor a file of another naming."""

import os
from pathlib import Path

from tabletop.app import build_live, build_replay
from tabletop.config import validate_config
from tabletop.frames import Frame
from tabletop.recorder import Recorder, read_frames, read_header
from tests import children
from tests.tabletop.test_recorder import kiosk_config


def close_with_a_frame(rec: Recorder) -> None:
    """Record one frame, then close (a recording closed without a frame is removed)."""
    rec.consume(Frame(seq=0, t=1.0))
    rec.close()


def test_max_mb_continues_in_new_parts_and_keep_removes_the_oldest(tmp_path, caplog):
    """A kiosk running as one session with a small ``max_mb``: the folder holds at most
    ``keep`` parts (the disk bound keep x max_mb); the older tabletop's file goes first, then
    the running session's oldest parts, said once; each part kept replays on its own."""
    import logging
    caplog.set_level(logging.INFO, logger="tabletop")
    old = tmp_path / "sessions" / "session-20000101-000000-000000.jsonl"
    old.parent.mkdir()
    old.write_text('{"format": "tabletop-session", "version": 1}\n')   # an older tabletop's
    os.utime(old, (1e9, 1e9))
    cfg = kiosk_config(tmp_path, max_mb=0.01, keep=2)
    inst = build_live(cfg)
    inst.loop.run(seconds=1.5)
    rec = inst.recorder
    assert len(rec.paths) >= 4, "a 10 kB limit makes several parts of 1.5 s of frames"
    kept = sorted((tmp_path / "sessions").iterdir())
    assert kept == sorted(rec.paths[-2:]) and not old.exists()
    assert len({read_header(p)["session"] for p in kept}) == 1   # one session's parts
    said = [r.getMessage() for r in caplog.records if r.levelname == "WARNING"
            and "recorder.keep" in r.getMessage()]
    assert len(said) == 1 and f"its part {rec.paths[0]} removed" in said[0], said
    t_prev = -1.0
    for p in rec.paths[-2:]:
        assert p.stat().st_size <= 0.01 * 2**20
        header = read_header(p)
        assert header["config"]["sources"][0]["pucks"] == [1, 2, 5]
        frames = list(read_frames(p))
        assert frames[0].t > t_prev  # times run on from part to part
        t_prev = frames[-1].t
        # each part replays on its own
        replay_cfg = validate_config(header["config"], "recorded", tmp_path)
        assert build_replay(replay_cfg, read_frames(p, absolute=True), fast=True,
                            view=False).loop.run() == len(frames)


def test_keep_removes_the_oldest_by_order_not_by_the_clock(tmp_path):
    """Recordings made while the clock was a day ahead, then the clock set back (a dead RTC
    battery, a time server's correction): the new recordings have the oldest modification
    times. ``keep`` removes by the headers' ``order``: the stale ones go, not the new ones
    (by the clock, the one just made would go at the next start)."""
    import time
    header = {"format": "tabletop-session", "version": 2}

    def one() -> Path:
        rec = Recorder(folder=tmp_path, header=header, keep=3)
        close_with_a_frame(rec)
        return rec.path

    ahead = [one() for _ in range(3)]
    day = time.time() + 86400
    for p in ahead:
        os.utime(p, (day, day))
    newer = [one(), one()]
    assert sorted(tmp_path.iterdir()) == sorted([ahead[2], *newer])
    assert [read_header(p)["order"] for p in (ahead[2], *newer)] == [3, 4, 5]


def test_keep_removes_only_recordings_of_the_naming(tmp_path):
    """``recorder.path: notes.txt`` beside the technician's notes.txt and notes-7.txt: keep 1
    removed both ("removed old recording"), they had no header ``order``. A recording of an
    older tabletop (its format, no order) and an empty one still count and go first."""
    header = {"format": "tabletop-session", "version": 2}
    (tmp_path / "notes.txt").write_text("my notes\n")
    (tmp_path / "notes-7.txt").write_text('{"format": "not ours"}\n')
    (tmp_path / "notes-3.txt").write_text('{"format": "tabletop-session", "version": 1}\n')
    (tmp_path / "notes-4.txt").write_bytes(b"")
    made = []
    for _ in range(2):
        rec = Recorder(path=tmp_path / "notes.txt", header=header, keep=1)
        close_with_a_frame(rec)
        made.append(rec.path)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["notes-7.txt", "notes-9.txt",
                                                           "notes.txt"]
    assert made == [tmp_path / "notes-8.txt", tmp_path / "notes-9.txt"]   # numbered past all
    assert (tmp_path / "notes.txt").read_text() == "my notes\n"
    assert read_header(made[1])["order"] == 2


def test_an_order_in_the_given_header_is_not_kept(tmp_path):
    """A header copied from another recording (``tabletop replay --out``) carries that one's
    ``order``: the new recording's own is written, else ``keep`` ages it by the other's."""
    rec = Recorder(folder=tmp_path, header={"format": "tabletop-session", "version": 2,
                                             "order": 99})
    close_with_a_frame(rec)
    assert read_header(rec.path)["order"] == 1


def test_a_recording_another_run_is_writing_is_never_pruned(tmp_path):
    """Two runs recording into one folder with ``keep: 1``: the second's start leaves the
    first's recording, being written, alone (removing it would lose the whole session);
    once the first closed it, the next prune removes it."""
    import subprocess
    import sys
    import time
    cfg = tmp_path / "config.yaml"
    cfg.write_text("sources: [{kind: scripted, pucks: [1, 2]}]\n"
                   "view: {size: [320, 180], headless: true}\n"
                   "recorder: {enabled: true, folder: sessions, keep: 1}\n")
    folder = tmp_path / "sessions"
    env = dict(os.environ, SDL_VIDEODRIVER="dummy")
    p = children.popen([sys.executable, "-m", "tabletop", "run", "--config", str(cfg),
                        "--seconds", "60"], env=env, stderr=subprocess.PIPE, text=True)
    def recording() -> bool:
        return folder.exists() and any(f.read_bytes().count(b"\n") > 30
                                       for f in folder.iterdir())

    try:
        # the run's file is made before its engines and view are built: under a full suite at
        # load 10+ that start took over 55 s, and a test that went on after 60 s found a
        # header alone, which the run rightly removed when stopped before its first frame
        deadline = time.monotonic() + 240
        while time.monotonic() < deadline and not recording():
            time.sleep(0.1)
        assert recording(), "the first run recorded no 30 frames in 240 s"
        (first,) = folder.iterdir()
        second = Recorder(folder=folder, keep=1, header={"config": {}})
        close_with_a_frame(second)
        assert first.exists() and second.path.exists()
    finally:
        p.terminate()
        _, err = p.communicate(timeout=60)
    assert p.returncode == 0, err
    assert len(list(read_frames(first))) >= 30   # (its header and 30 frames were seen)
    third = Recorder(folder=folder, keep=1, header={"config": {}})
    close_with_a_frame(third)
    assert sorted(folder.iterdir()) == [third.path]


def test_a_recording_a_slow_disk_stopped_is_never_pruned_while_its_run_goes_on(
        tmp_path, monkeypatch):
    """A run whose recording stopped as the disk could not keep up goes on, and resumes its
    session in a new part once the disk caught up: another run's start with ``keep: 1`` leaves
    the stopped part, as it leaves one being written (it removed it: a disk stalled at load
    20+ past 1,024 lines lost a running session); once the run closed, the next prune takes
    it. The real syncer thread, its fdatasync held until released."""
    import threading
    real, gate, syncing = os.fdatasync, threading.Event(), threading.Event()

    def stalled(fd: int) -> None:
        if threading.current_thread().name == "recorder-sync":   # the first's, then the second's
            syncing.set()
            gate.wait(30)
        real(fd)

    folder = tmp_path / "sessions"
    header = {"format": "tabletop-session", "version": 2}
    first = Recorder(folder=folder, keep=1, header=header, max_queue=5)
    monkeypatch.setattr(os, "fdatasync", stalled)
    try:
        first.consume(Frame(seq=0, t=1.0))
        assert syncing.wait(10)                 # the syncer is held in the first line's sync
        for k in range(1, 10):
            first.consume(Frame(seq=k, t=1.0 + k / 60))
        assert first.failed is not None and "cannot keep up" in first.failed
        second = Recorder(folder=folder, keep=1, header=header)
        assert first.path.exists() and second.path.exists()
        gate.set()
        close_with_a_frame(second)
    finally:
        gate.set()
        first.close()
    assert len(list(read_frames(first.path))) == first.frames == 6   # 1 synced, 5 waited
    third = Recorder(folder=folder, keep=1, header=header)
    close_with_a_frame(third)
    assert sorted(folder.iterdir()) == [third.path]


def test_a_new_part_names_max_mb_as_configured(tmp_path, caplog):
    """"recording continues in ... (... reached 0.3 MB)" for max_mb 0.3, not the 0.299999 of
    its whole bytes divided back."""
    import numpy as np

    from tabletop.frames import Frame
    caplog.set_level("INFO", logger="tabletop")
    rec = Recorder(folder=tmp_path, header={"format": "tabletop-session", "version": 2},
                   max_mb=0.3)
    try:
        k = 0
        while len(rec.paths) < 2 and k < 5000:
            rec.consume(Frame(seq=k, t=k / 60, streams={"hand": np.arange(60) / 7.0}))
            k += 1
    finally:
        rec.close()
    said = [r.getMessage() for r in caplog.records if "recording continues" in r.getMessage()]
    assert len(said) == 1 and said[0].endswith("reached 0.3 MB)"), said
