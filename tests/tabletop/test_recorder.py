"""Recording and replay: a 2 s headless session replays frame by frame, and bad files are
refused."""

import json
from pathlib import Path

import pytest

from tabletop.app import build_live, build_replay
from tabletop.config import validate_config
from tabletop.recorder import Recorder, SessionError, read_frames, read_header

CONFIG = {
    "sources": [{"kind": "scripted", "name": "visitor", "pucks": [1, 2, 5], "seed": 4}],
    "view": {"headless": True, "size": [640, 360]},
}


def record(tmp_path: Path, seconds: float = 2.0) -> Path:
    cfg = validate_config(CONFIG, "test", tmp_path)
    path = tmp_path / "session.jsonl"
    build_live(cfg, headless=True, record_path=path).loop.run(seconds=seconds)
    return path


class Collect:
    """A sink beside the recorder keeping every frame the loop completed."""

    name = "collect"

    def __init__(self) -> None:
        self.frames: list = []

    def consume(self, frame) -> None:
        self.frames.append(frame)

    def close(self) -> None:
        pass


def test_record_then_replay_gives_the_same_frames(tmp_path):
    """Every frame of a 2 s run is recorded, with its very time and pucks, and replays the same.
    The count is judged against the ticks that ran (a loaded machine skips ticks: the loop
    accounts for each skipped slot), not against the nominal 60 Hz."""
    cfg = validate_config(CONFIG, "test", tmp_path)
    path = tmp_path / "session.jsonl"
    live = build_live(cfg, headless=True, record_path=path)
    seen = Collect()
    live.loop.sinks.append(seen)
    ran = live.loop.run(seconds=2.0)
    assert live.loop.ran_s >= 2.0
    header = read_header(path)
    assert header["format"] == "tabletop-session" and header["version"] == 2
    assert header["config"]["sources"][0]["pucks"] == [1, 2, 5]
    recorded = list(read_frames(path))
    assert len(recorded) == ran == len(seen.frames) >= 10
    assert recorded[0].t == 0.0
    assert [f.t for f in read_frames(path, absolute=True)] == [f.t for f in seen.frames]
    assert [f.pucks for f in recorded] == [f.pucks for f in seen.frames]
    assert recorded[-1].t <= live.loop.ran_s   # the frames of that run, none after it

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
    """Each frame is played no earlier than its recorded time after the first, and lateness
    does not pile up: in the second half some frame is on time within a quarter of the span
    (measured: the best 0.1 ms late, the worst 8 ms, at load 15-20; a replay that waits each
    recorded offset again from the previous frame: 3.8 s late; one played 17 ms early fails
    the first check). Judged on the best frame, not on each, so a loaded machine's late ticks
    do not fail it (no wall-clock bound on the run)."""
    import time

    class Stamp(Collect):
        def consume(self, frame) -> None:
            self.frames.append((frame.t, time.monotonic()))

    path = record(tmp_path, seconds=1.0)
    cfg = validate_config(read_header(path)["config"], "recorded", tmp_path)
    inst = build_replay(cfg, read_frames(path), fast=False, view=False)
    stamp = Stamp()
    inst.loop.sinks.append(stamp)
    before = time.monotonic()    # no later than the replay's clock starts (its first frame)
    inst.loop.run()
    (t0, wall0), span = stamp.frames[0], stamp.frames[-1][0] - stamp.frames[0][0]
    ahead = [(t - t0) - (wall - before) for t, wall in stamp.frames]
    assert len(ahead) == len(list(read_frames(path))) and span >= 0.9
    assert max(ahead) <= 0.0, max(ahead)                      # never ahead of the recording
    late = [(wall - wall0) - (t - t0) for t, wall in stamp.frames]
    assert min(late[len(late) // 2:]) < 0.25 * span, late     # and no lateness piling up


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


@pytest.mark.parametrize("cut", ["header only", "first frame cut short", "bad first frame"])
def test_replay_of_a_session_without_a_frame_is_one_line_and_writes_nothing(tmp_path, capfd,
                                                                            cut):
    # (it replayed nothing, said "replayed 0 frames" and exited 0 with an empty --out file)
    from tabletop.cli import main as tabletop
    path = record(tmp_path, seconds=0.2)
    lines = path.read_text().splitlines(keepends=True)
    tail = {"header only": "", "first frame cut short": lines[1][:30],
            "bad first frame": '{"seq": -1}\n'}[cut]
    path.write_text(lines[0] + tail)
    out = tmp_path / "out.jsonl"
    code = tabletop(["replay", str(path), "--fast", "--no-view", "--out", str(out)])
    err = [ln for ln in capfd.readouterr().err.splitlines() if ln.strip()]
    assert code == 2 and len(err) == 1 and not out.exists()
    assert ("line 2: not a valid frame" if cut == "bad first frame"
            else "no complete frame after the header line") in err[0]


@pytest.mark.parametrize("reloaded, words", [
    (5, "line 1: reloaded: expected a mapping of behaviors, notes, actions, libraries"),
    ({"behaviors": {"lover": 5}}, "line 1: reloaded: behaviors: expected a mapping of engines"),
])
def test_a_part_header_s_bad_reloaded_is_named_as_the_header_s(tmp_path, capfd, reloaded,
                                                               words):
    # (it was said as the frame's "consumed: expected a mapping of filters to {pucks,
    # commands}", a key the header does not have)
    from tabletop.cli import main as tabletop
    path = record(tmp_path, seconds=0.2)
    head, rest = path.read_text().split("\n", 1)
    path.write_text(json.dumps({**json.loads(head), "reloaded": reloaded}) + "\n" + rest)
    assert tabletop(["replay", str(path), "--fast", "--no-view"]) == 2
    err = [ln for ln in capfd.readouterr().err.splitlines() if ln.strip()]
    assert len(err) == 1 and f"{path}: {words}" in err[0] and "consumed" not in err[0], err


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
    assert rec.path == tmp_path / "s-2.jsonl" and read_header(rec.path)["version"] == 2
    rec.close()
    assert p.read_text() == "precious\n"


# --- kiosk safety ------------------------------------------------------------------------------

def kiosk_config(tmp_path: Path, **recorder) -> dict:
    cfg = dict(CONFIG, view={"enabled": False}, recorder={"enabled": True, **recorder})
    return validate_config(cfg, str(tmp_path / "kiosk.yaml"), tmp_path)


def test_a_recorder_path_that_exists_continues_under_a_free_name(tmp_path):
    cfg = kiosk_config(tmp_path, path="sessions/kiosk.jsonl")
    for _ in range(3):  # three starts, as after reboots
        build_live(cfg).loop.run(seconds=0.2)
    names = sorted(p.name for p in (tmp_path / "sessions").iterdir())
    assert names == ["kiosk-2.jsonl", "kiosk-3.jsonl", "kiosk.jsonl"]
    assert all(len(list(read_frames(tmp_path / "sessions" / n))) > 3 for n in names)


def test_a_live_build_refuses_an_unwritable_recording_folder_unless_told_to_run_on(tmp_path):
    """Strict is the default of a live build (someone reads the error); only a caller that
    says so (a kiosk's start, which may be a restart) runs on without recording."""
    from tabletop.schema import ConfigError
    (tmp_path / "blocked").write_text("not a folder")    # (root: permission bits refuse nothing)
    cfg = kiosk_config(tmp_path, folder="blocked/sessions")
    with pytest.raises(ConfigError, match=r"recorder\.folder: .*cannot start a recording there"):
        build_live(cfg)
    inst = build_live(cfg, strict=False)
    sink = Collect()
    inst.loop.sinks.insert(0, sink)
    ran = inst.loop.run(max_ticks=5)                                         # runs on,
    assert "blocked" in (inst.recorder.failed or ""), inst.recorder.failed   # says where
    assert ran == 5
    assert len(sink.frames) == 5 and sink.frames[-1].pucks
    assert list(tmp_path.iterdir()) == [tmp_path / "blocked"]               # nothing written


def test_two_recorders_started_at_once_never_collide(tmp_path):
    from tabletop.recorder import Recorder

    header = {"format": "tabletop-session", "version": 2}
    recs = [Recorder(folder=tmp_path, header=header) for _ in range(5)]
    assert len({r.path for r in recs}) == 5
    for r in recs:
        assert read_header(r.path)["part"] == 1
        r.close()


@pytest.mark.parametrize("limit_kb", [64, 1], ids=["while running", "at start-up"])
def test_a_full_disk_stops_recording_with_one_line_and_the_run_goes_on(tmp_path, limit_kb):
    """A real write failure: the process may not grow a file beyond ``limit_kb`` (RLIMIT_FSIZE).
    At 1 kB not even the header fits."""
    import resource
    import signal
    import subprocess
    import sys

    def limit() -> None:
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit_kb * 1024, limit_kb * 1024))

    gesture = tmp_path / "g.csv"  # 10 kB, embedded in the header
    gesture.write_text("t,dx,dy\n" + "".join(f"{i / 100},{i / 1e4:.6f},0.0\n" for i in range(500)))
    cfg = tmp_path / "kiosk.yaml"
    cfg.write_text("sources: [{kind: scripted, pucks: [1, 2, 5], performers: [{puck: 3, "
                   "home: [0.5, 0.4], gestures: [g.csv]}]}]\nview: {enabled: false}\n")
    out = tmp_path / "full.jsonl"
    r = subprocess.run([sys.executable, "-m", "tabletop", "run", "--config", str(cfg),
                        "--seconds", "2", "--record", str(out)], capture_output=True, text=True,
                       preexec_fn=limit, timeout=60)
    assert r.returncode == 3, r.stderr
    assert "Traceback" not in r.stderr
    stopped = [ln for ln in r.stderr.splitlines() if "recording stopped" in ln]
    assert len(stopped) == 1 and str(out) in stopped[0] and "File too large" in stopped[0]
    (ran,) = [ln for ln in r.stderr.splitlines() if "ran " in ln and " ticks in " in ln]
    assert float(ran.split(" ticks in ")[1].split()[0]) >= 2.0   # it ran the whole 2 s
    if limit_kb == 1:
        assert not out.exists()  # a file without a single frame is not left behind, and the
        assert "(it held no frame: removed)" in stopped[0]   # line naming it says so
    else:
        assert 0 < len(list(read_frames(out))) < 100  # what was written before is readable


@pytest.mark.parametrize("line, words", [
    (b"\xff\xfe\x00binary\n", ["line 3", "not UTF-8"]),
    (b'{"seq": 1, "t": 1e12}\n', ["line 3", "t is 1000000000000.0"]),
    (b'{"seq": 1, "t": NaN}\n', ["line 3", "t is nan"]),
    (b'{"seq": 1, "t": -5.0}\n', ["line 3", "goes back in time"]),
    (b'{"seq": 1, "t": 0.1, "pucks": [{"id": 1, "x": "far", "y": 0, "angle": 0}]}\n',
     ["line 3", "not a valid frame (x is 'far', expected a finite number)"]),
    (b'{"seq": 1, "t": "zz"}\n', ["line 3", "(t is 'zz', expected a finite number)"]),
    (b'{"seq": 1, "t": 0.1, "touches": [{"id": "a", "x": 0, "y": 0}]}\n',
     ["line 3", "(touch id is 'a', expected a whole number)"]),
    (b'{"seq": 1, "t": 0.1, "streams": {"hand": [1, "b"]}}\n',
     ["line 3", "(streams.hand is 'b', expected a finite number)"]),
    (b'{"seq": 1, "t": 0.1, "characters": [{"name": "c", "x": 0, "y": [1], "heading": 0}]}\n',
     ["line 3", "(y is [1], expected a finite number)"]),
    # finite but no table's: replayed, the TUIO sink failed on every frame (no OSC float holds it)
    (b'{"seq": 1, "t": 0.1, "pucks": [{"id": 1, "x": 1e300, "y": 0, "angle": 0}]}\n',
     ["line 3", "(x is 1e+300 m, beyond 1000 m of the table)"]),
    (b'{"seq": 1, "t": 0.1, "touches": [{"id": 1, "x": 0, "y": 0, "vy": -1e300}]}\n',
     ["line 3", "(vy is -1e+300 per second, beyond 1e+06)"]),
    # lists and objects of the wrong kind (a recording edited by hand or by another program)
    # are said in the recording's terms, not Python's ("'NoneType' object is not iterable")
    (b'{"seq": 1, "t": 0.1, "pucks": null}\n', ["line 3", "(pucks: expected a list of objects)"]),
    (b'{"seq": 1, "t": 0.1, "pucks": [{"x": 0, "y": 0, "angle": 0}]}\n',
     ["line 3", "(pucks[0]: missing 'id')"]),
    (b'{"seq": 1, "t": 0.1, "touches": [5]}\n', ["(touches: expected a list of objects)"]),
    (b'{"seq": 1, "t": 0.1, "streams": [1, 2]}\n',
     ["(streams: expected a mapping of names to lists of numbers)"]),
    (b'{"seq": 1, "t": 0.1, "characters": ["lover"]}\n',
     ["(characters: expected a list of objects)"]),
    (b'{"seq": 1, "t": 0.1, "characters": [{"x": 0, "y": 0, "heading": 0}]}\n',
     ["(characters[0]: missing 'name')"]),
    (b'{"seq": 1, "t": 0.1, "characters": [{"name": "c", "x": 0, "y": 0, "heading": 0, '
     b'"color": 5}]}\n', ["(character color: expected a list of numbers)"]),
    (b'{"seq": 1, "t": 0.1, "characters": [{"name": "c", "x": 0, "y": 0, "heading": 0, '
     b'"color": [1]}]}\n', ["line 3", "(character color: expected [r, g, b])"]),
    (b'{"seq": 1, "t": 0.1, "characters": [{"name": "c", "x": 0, "y": 0, "heading": 0, '
     b'"bones": [[1, 2, 3]]}]}\n', ["line 3", "(character bones: expected a list of [i, j])"]),
    (b'{"seq": 1, "t": 0.1, "characters": [{"name": "c", "x": 0, "y": 0, "heading": 0, '
     b'"points": [[1], [1, 2]]}]}\n', ["(character points: expected a list of [x, y])"]),
    (b'{"seq": 1, "t": 0.1, "characters": [{"name": "c", "x": 0, "y": 0, "heading": 0, '
     b'"progress": "q"}]}\n', ["(progress is 'q', expected a finite number)"]),
    (b'{"seq": 1, "t": 0.1, "consumed": {"studio": {"pucks": 3}}}\n',
     ["(consumed.studio.pucks: expected a list of objects)"]),
])
def test_damaged_frame_lines_are_named(tmp_path, line, words):
    p = tmp_path / "s.jsonl"
    p.write_bytes(json.dumps({"format": "tabletop-session", "version": 2}).encode() + b"\n"
                  + b'{"seq": 0, "t": 0.0}\n' + line + b'{"seq": 2, "t": 0.2}\n')
    with pytest.raises(SessionError) as info:
        list(read_frames(p))
    for w in words:
        assert w in str(info.value)


def test_replay_feeds_the_engines_the_live_times_exactly(tmp_path):
    path = record(tmp_path, seconds=0.5)
    relative = list(read_frames(path))
    absolute = list(read_frames(path, absolute=True))
    assert relative[0].t == 0.0 and absolute[0].t > 0.0
    t0 = absolute[0].t
    assert all(a.t - t0 == r.t for a, r in zip(absolute, relative))
    header = read_header(path)
    inst = build_replay(validate_config(header["config"], "recorded", tmp_path),
                        iter(absolute), fast=True, view=False, header=header)
    inst.loop.run()
    assert "capture_age" not in inst.loop.stats.summary_ms()  # no latency from another clock


def test_a_stop_ends_a_replay_waiting_for_a_distant_frame(tmp_path):
    """The second frame is 11 days after the first: a stop during that wait ends the run, its
    one tick run (judged by the run ending, with a liveness bound only, however slow)."""
    import threading

    p = tmp_path / "gap.jsonl"
    p.write_text(json.dumps({"format": "tabletop-session", "version": 2}) + "\n"
                 '{"seq": 0, "t": 0.0}\n{"seq": 1, "t": 1e6}\n')
    cfg = validate_config(CONFIG, "test", tmp_path)
    inst = build_replay(cfg, read_frames(p, absolute=True), fast=False, view=False)
    ran: list[int] = []
    th = threading.Thread(target=lambda: ran.append(inst.loop.run()), daemon=True)
    th.start()
    threading.Timer(0.3, inst.loop.stop.set).start()
    th.join(30.0)
    assert not th.is_alive() and ran == [1]


def test_a_recording_under_a_file_names_that_file(tmp_path):
    """``--record notes.txt/s.jsonl``: the system says only "File exists" (or "Not a
    directory"); the refusal names the file standing where a folder must be."""
    (tmp_path / "notes.txt").write_text("")
    for path in (tmp_path / "notes.txt" / "s.jsonl", tmp_path / "notes.txt" / "sub" / "s.jsonl"):
        with pytest.raises(SessionError) as info:
            Recorder(path, header={"format": "tabletop-session", "version": 2})
        assert str(info.value) == (f"{path.parent}: cannot start a recording there: "
                                   f"{tmp_path / 'notes.txt'} is a file")


def test_a_bad_file_in_a_recording_is_named_as_the_recordings_not_by_a_temporary_path(
        tmp_path, capfd):
    """The files a recording carries are unpacked into a temporary folder that is gone when
    the replay ends: an error in one names the recording and the file as it was recorded; one
    in the recording's calibration names the recording too."""
    from tabletop import cli
    root = Path(__file__).resolve().parents[2]
    cfg = dict(CONFIG, engines=[{"kind": "puppet_master", "name": "lover", "main": {"puck": 1},
                                 "behavior": str(root / "behaviors/library/lover")}])
    cfg["view"] = {"enabled": False}
    path = tmp_path / "session.jsonl"
    build_live(validate_config(cfg, "test", tmp_path), headless=True,
               record_path=path).loop.run(seconds=0.3)
    lines = path.read_text().splitlines()
    header = json.loads(lines[0])
    key = next(k for k in header["files"] if k.endswith("demonstration.csv"))
    header["files"][key] = {"text": "t,main_x\n0,1\n"}
    bad = tmp_path / "bad.jsonl"
    bad.write_text("\n".join([json.dumps(header)] + lines[1:]) + "\n")
    capfd.readouterr()
    assert cli.main(["replay", str(bad), "--fast", "--no-view"]) == 2
    err = capfd.readouterr().err.strip()
    assert len(err.splitlines()) == 1, err
    # (named at the recorded config's key, as a corrupt behavior.yaml is)
    assert err.startswith(f"tabletop replay: error: {bad} (recorded config): engines[0].behavior: "
                          f"the recording's {key}: line 1: missing column(s)"), err
    assert "tabletop-replay-" not in err
    header["files"][key] = json.loads(lines[0])["files"][key]
    header["calibration"] = {"format": "tabletop-calibration"}
    bad.write_text("\n".join([json.dumps(header)] + lines[1:]) + "\n")
    assert cli.main(["replay", str(bad), "--fast", "--no-view"]) == 2
    err = capfd.readouterr().err.strip()
    assert err.startswith(f"tabletop replay: error: {bad}: the recording's calibration: "
                          "version"), err


@pytest.mark.parametrize("tail, code, words", [
    ("\n", 0, None),                       # an editor's newline after the last frame
    ("\n   \n\t\r\n", 0, None),            # whitespace lines
    ("CUT\n\n", 2, "line LAST: not valid JSON"),   # a cut frame, then a blank line: refused
    ("MIDDLE", 2, "line 3: a blank line between frames"),
])
def test_blank_lines_after_the_last_frame_are_no_frame(tmp_path, capfd, tail, code, words):
    # (a trailing blank line was refused: "line N: not valid JSON (Expecting value)")
    from tabletop.cli import main as tabletop
    path = record(tmp_path, seconds=0.3)
    lines = path.read_text().splitlines(keepends=True)
    frames = len(lines) - 1
    if tail == "MIDDLE":
        lines.insert(2, "\n")
    elif tail.startswith("CUT"):
        lines[-1] = lines[-1][:25] + tail[3:]
    else:
        lines.append(tail)
    path.write_text("".join(lines))
    out = tmp_path / "out.jsonl"
    status = tabletop(["replay", str(path), "--fast", "--no-view", "--out", str(out)])
    err = [ln for ln in capfd.readouterr().err.splitlines() if "replay" in ln]
    assert status == code, err
    if words is None:
        assert len(out.read_text().splitlines()) - 1 == frames
    else:
        assert len(err) == 1 and str(path) in err[0], err
        assert words.replace("LAST", str(len(lines))) in err[0]


def test_a_header_cut_short_is_named_so(tmp_path):
    """A recording whose header line was cut (a power cut while it was written): JSON's
    "line 1: not valid JSON (Unterminated string starting at)" told nothing of what happened."""
    path = record(tmp_path, seconds=0.3)
    data = path.read_bytes()
    for cut in (40, data.index(b"\n") // 2):
        path.write_bytes(data[:cut])
        with pytest.raises(SessionError) as info:
            read_header(path)
        assert str(info.value) == (f"{path}: line 1: its header is cut short (the recording "
                                   "was interrupted while it was written): nothing to replay")
    path.write_bytes(b'{"format":"tabletop-session", oops}\n')   # whole but damaged: as before
    with pytest.raises(SessionError, match="line 1: not valid JSON"):
        read_header(path)
