"""Recording and replay: a 2 s headless session replays frame by frame, and bad files are refused."""

import json
from pathlib import Path

import pytest

from tabletop.app import build_live, build_replay
from tabletop.config import validate_config
from tabletop.recorder import SessionError, read_frames, read_header

CONFIG = {
    "sources": [{"kind": "scripted", "name": "visitor", "pucks": [1, 2, 5], "seed": 4}],
    "view": {"headless": True, "size": [640, 360]},
}


def record(tmp_path: Path, seconds: float = 2.0) -> Path:
    cfg = validate_config(CONFIG, "test", tmp_path)
    path = tmp_path / "session.jsonl"
    build_live(cfg, headless=True, record_path=path).loop.run(seconds=seconds)
    return path


def test_record_then_replay_gives_the_same_frames(tmp_path):
    path = record(tmp_path)
    header = read_header(path)
    assert header["format"] == "tabletop-session" and header["version"] == 2
    assert header["config"]["sources"][0]["pucks"] == [1, 2, 5]
    recorded = list(read_frames(path))
    assert len(recorded) >= 100
    assert recorded[0].t == 0.0
    assert recorded[-1].t == pytest.approx(2.0, abs=0.1)

    out = tmp_path / "replayed.jsonl"
    cfg = validate_config(header["config"], "recorded", tmp_path)
    inst = build_replay(cfg, read_frames(path), fast=True, headless=True, record_path=out)
    assert inst.loop.run() == len(recorded)
    replayed = list(read_frames(out))
    assert len(replayed) == len(recorded)
    for a, b in zip(recorded, replayed):
        assert (a.seq, a.t) == (b.seq, b.t)
        assert a.pucks == b.pucks
        assert a.commands == b.commands


def test_replay_honours_recorded_times(tmp_path):
    import time

    path = record(tmp_path, seconds=1.0)
    cfg = validate_config(read_header(path)["config"], "recorded", tmp_path)
    inst = build_replay(cfg, read_frames(path), fast=False, view=False)
    t0 = time.monotonic()
    inst.loop.run()
    elapsed = time.monotonic() - t0
    span = list(read_frames(path))[-1].t
    assert elapsed == pytest.approx(span, abs=0.15)


def test_cut_short_last_line_is_skipped(tmp_path):
    path = record(tmp_path, seconds=0.5)
    full = list(read_frames(path))
    data = path.read_bytes()
    path.write_bytes(data[:-40])  # a power cut in the middle of the last line
    assert len(list(read_frames(path))) == len(full) - 1


def test_corrupt_middle_line_is_named(tmp_path):
    path = record(tmp_path, seconds=0.5)
    lines = path.read_text().splitlines(keepends=True)
    lines[3] = "{not json\n"
    path.write_text("".join(lines))
    with pytest.raises(SessionError, match="line 4"):
        list(read_frames(path))


def test_not_a_session(tmp_path):
    p = tmp_path / "x.jsonl"
    p.write_text(json.dumps({"format": "something-else"}) + "\n")
    with pytest.raises(SessionError, match="line 1"):
        read_header(p)
    with pytest.raises(SessionError, match="not found"):
        read_header(tmp_path / "absent.jsonl")


def test_recorder_never_overwrites(tmp_path):
    from tabletop.recorder import Recorder

    p = tmp_path / "s.jsonl"
    p.write_text("precious\n")
    rec = Recorder(p, header={"format": "tabletop-session", "version": 2})
    rec.close()
    assert p.read_text() == "precious\n"
    assert rec.path == tmp_path / "s-2.jsonl" and read_header(rec.path)["version"] == 2
