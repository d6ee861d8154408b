"""A recordings folder that grows for weeks (``recorder.keep: null``): the work of starting a new
part must not grow with the recordings kept. Counted with Python's audit events (every file
opened, every directory listed by the recorder's own code), on real files."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest

from tabletop.frames import Frame
from tabletop.recorder import Recorder, read_header

KEPT = 1500          # recordings already in the folder

_counting: list[dict[str, int]] = []


def _hook(event: str, args: tuple) -> None:
    if _counting and event in ("open", "os.listdir", "os.scandir"):
        _counting[-1][event] = _counting[-1].get(event, 0) + 1


sys.addaudithook(_hook)


class Count:
    """Counts the audit events named in ``_hook`` within its ``with`` block."""

    def __enter__(self) -> dict[str, int]:
        _counting.append({})
        return _counting[-1]

    def __exit__(self, *exc) -> None:
        _counting.pop()


def fill(folder: Path, stem: str | None) -> None:
    folder.mkdir(parents=True, exist_ok=True)
    for i in range(KEPT):
        if stem is None:
            name = f"session-20260101-000000-{i:06d}.jsonl"
        else:
            name = f"{stem}.jsonl" if i == 0 else f"{stem}-{i + 1}.jsonl"
        (folder / name).write_text(json.dumps({"format": "tabletop-session", "version": 3,
                                               "order": i + 1}, separators=(",", ":")) + "\n")


@pytest.mark.parametrize("stem", [None, "kiosk"], ids=["folder", "path"])
def test_a_new_part_costs_the_same_however_many_recordings_are_kept(tmp_path, stem):
    """keep: null with 1,500 recordings kept: each new part (``max_mb`` reached) opens its own
    file and lists nothing; the start opens each header once and no more. Listing the folder
    and stat()ing every recording twice in the frame loop costs 160-250 ms per part at 20,000
    recordings, and a ``path`` naming that tries NAME, NAME-2, ... one open() each costs
    1,501 opens beyond the headers at start and 1,500 at every part."""
    fill(tmp_path, stem)
    where = dict(folder=tmp_path) if stem is None else dict(path=tmp_path / f"{stem}.jsonl")
    with Count() as start:
        rec = Recorder(header={"config": {}}, keep=None, max_mb=0.002, max_queue=10**6, **where)
    try:
        assert start.get("open", 0) <= KEPT + 2, start
        with Count() as parts:
            for i in range(400):
                rec.consume(Frame(i, i / 60.0))
    finally:
        rec.close()
    new_parts = len(rec.paths) - 1
    assert new_parts >= 5, rec.paths
    assert parts.get("os.listdir", 0) + parts.get("os.scandir", 0) == 0, parts
    assert parts.get("open", 0) <= 2 * new_parts, parts
    orders = [read_header(p)["order"] for p in rec.paths]
    assert orders == list(range(KEPT + 1, KEPT + 2 + new_parts))
    if stem is not None:
        assert [p.name for p in rec.paths] == [f"{stem}-{KEPT + 1 + k}.jsonl"
                                               for k in range(new_parts + 1)]


def test_keep_still_lists_the_folder_and_prunes_at_each_part(tmp_path):
    """With ``keep`` the folder is listed at every part (unlike ``keep: null``): recordings
    another run added meanwhile are counted, and the oldest removed down to ``keep`` files."""
    fill(tmp_path, None)
    rec = Recorder(folder=tmp_path, header={"config": {}}, keep=10, max_mb=0.002,
                   max_queue=10**6)
    try:
        for i in range(100):
            rec.consume(Frame(i, i / 60.0))
    finally:
        rec.close()
    assert 3 <= len(rec.paths) <= 9
    left = sorted(tmp_path.iterdir())   # the newest older sessions and every running part
    assert len(left) == 10 and set(rec.paths) <= set(left)
    assert read_header(rec.path)["order"] == KEPT + len(rec.paths)


def test_the_closing_line_counts_the_frames_of_every_part(tmp_path, caplog):
    """A session in several parts ends with one line giving its frames and its parts, first
    to last. It named the last part beside the session's frame count ("recording
    session-...-3.jsonl: 2425 frames" for a file holding 270): frames looked lost."""
    import logging
    from tabletop.recorder import read_frames
    caplog.set_level(logging.INFO, logger="tabletop")
    rec = Recorder(folder=tmp_path, header={"config": {}}, max_mb=0.002, max_queue=10**6)
    for i in range(200):
        rec.consume(Frame(i, i / 60.0))
    rec.close()
    assert len(rec.paths) >= 3
    assert sum(len(list(read_frames(p))) for p in rec.paths) == 200
    line = [r.getMessage() for r in caplog.records if "200 frames" in r.getMessage()]
    assert line == [f"recording {rec.paths[0]}: 200 frames in {len(rec.paths)} parts, "
                    f"{rec.paths[0].name} to {rec.paths[-1].name}"], line


def test_a_path_naming_numbers_on_past_any_number_found(tmp_path):
    """A copy named with a huge number (``kiosk-1000000000.jsonl``) beside the recordings: the
    next recording is the number after it, never an error (the names tried ran out)."""
    (tmp_path / "kiosk.jsonl").write_text("{}\n")
    (tmp_path / "kiosk-1000000000.jsonl").write_text("{}\n")
    rec = Recorder(path=tmp_path / "kiosk.jsonl", header={"config": {}})
    rec.close()
    assert rec.path.name == "kiosk-1000000001.jsonl"


def record(folder: Path, keep: int | None, frames: int) -> list[Path]:
    """One session of ``frames`` frames in parts of 2 kB; its parts."""
    rec = Recorder(folder=folder, header={"config": {}}, keep=keep, max_mb=0.002,
                   max_queue=10**6)
    try:
        for i in range(frames):
            rec.consume(Frame(i, i / 60.0))
    finally:
        rec.close()
    return list(rec.paths)


def test_keep_removes_closed_sessions_whole_first(tmp_path):
    """Closed sessions of several parts each, then a new one with ``keep`` one file short of
    the last closed session + the second last's parts: the two oldest sessions go whole (not
    one part of the second), the last closed one stays whole beside the running part."""
    sessions = [record(tmp_path, None, 60) for _ in range(3)]
    assert all(len(s) >= 3 for s in sessions)
    new = record(tmp_path, len(sessions[2]) + 2, 1)
    assert sorted(tmp_path.iterdir()) == sorted(sessions[2] + new)


def test_a_long_session_keeps_at_most_keep_parts(tmp_path, caplog):
    """One session far longer than ``keep`` parts (a kiosk running for weeks): at most
    ``keep`` files at every part, its newest; the first removal said once, naming it."""
    import logging
    caplog.set_level(logging.INFO, logger="tabletop")
    rec = Recorder(folder=tmp_path, header={"config": {}}, keep=3, max_mb=0.002,
                   max_queue=10**6)
    most = 0
    try:
        for i in range(400):
            rec.consume(Frame(i, i / 60.0))
            most = max(most, len(list(tmp_path.iterdir())))
    finally:
        rec.close()
    assert len(rec.paths) >= 8
    assert most <= 3 and sorted(tmp_path.iterdir()) == sorted(rec.paths[-3:])
    # (a loaded machine may add the recorder's "the disk is slower than the frames" warning)
    said = [r.getMessage() for r in caplog.records
            if r.levelname == "WARNING" and "removed" in r.getMessage()]
    assert len(said) == 1 and f"its part {rec.paths[0]} removed" in said[0], said
    # the closing line counts what stays, not only what was written
    done = [r.getMessage() for r in caplog.records if "frames in" in r.getMessage()]
    assert len(done) == 1 and f"the first {len(rec.paths) - 3} removed" in done[0], done
    assert done[0].endswith("; 3 kept)"), done


def test_two_runs_with_one_order_keep_each_others_parts(tmp_path, monkeypatch):
    """Two runs start together in one folder and read the same highest order (the second's
    listing made before the first's file existed), each with ``max_mb`` 2 kB and ``keep`` 3,
    their frames interleaved: neither run's part removal ever takes a part of the other (its
    current one included), each keeps its own newest parts, and each session's kept parts
    replay in order, with one ``session`` id per run."""
    import tabletop.recordings as recordings_module
    from tabletop.commands.replay import session_frames
    a = Recorder(folder=tmp_path, header={"config": {}}, keep=3, max_mb=0.002, max_queue=10**6)
    listing = recordings_module.recordings
    monkeypatch.setattr(recordings_module, "recordings", lambda *args: {})   # the race
    b = Recorder(folder=tmp_path, header={"config": {}}, keep=3, max_mb=0.002, max_queue=10**6)
    monkeypatch.setattr(recordings_module, "recordings", listing)
    assert read_header(a.path)["order"] == read_header(b.path)["order"]
    try:
        for i in range(300):
            for rec in (a, b):
                rec.consume(Frame(i, i / 60.0))
                for other in (a, b):
                    assert other.path.exists(), f"{other.path} removed while written"
    finally:
        a.close()
        b.close()
    assert len(a.paths) >= 6 and len(b.paths) >= 6
    for rec in (a, b):
        kept = [p for p in rec.paths if p.exists()]
        assert kept == rec.paths[-3:], (rec.paths, kept)
        sessions = {read_header(p)["session"] for p in kept}
        assert len(sessions) == 1, sessions
        times = [f.t for f in session_frames(kept, read_header(kept[0]))]
        assert times == sorted(times) and len(times) > 30
    assert read_header(a.path)["session"] != read_header(b.path)["session"]
