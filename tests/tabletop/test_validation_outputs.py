"""Bad output paths on the command line: ``--out`` naming a folder, a symbolic link loop, a pipe or
a link through /proc (written through, never replaced), and ``run --record`` naming a device or
pipe (refused): one line and exit status 2 for the refused ones."""

import json
import os
import stat
import threading
from pathlib import Path

import numpy as np
import pytest

from tests.tabletop.test_validation import cli, one_line


@pytest.mark.parametrize("command", ["behave", "follow", "track", "replay"])
def test_out_naming_a_folder_names_that_folder(tmp_path, capfd, demo, command):
    out = tmp_path / "results"
    out.mkdir()
    args = {"behave": ["behave", "--train", demo, "--input", demo],
            "follow": ["follow", "--template", f"a={demo}", "--input", demo],
            "track": ["track", tmp_path],
            "replay": ["replay", tmp_path / "absent.jsonl"]}[command]
    if command == "track":
        import cv2
        cv2.imwrite(str(tmp_path / "f.png"), np.full((60, 80), 255, np.uint8))
    code, err = cli(capfd, *args, "--out", out)
    line = one_line(err)
    assert code == 2 and str(out) in line and "folder" in line and ".tmp" not in line
    # the file it suggests is of the kind the command writes (a CSV was suggested "out.jsonl")
    kind = {"behave": ".csv", "follow": ".csv", "track": ".jsonl", "replay": ".jsonl"}[command]
    assert line.endswith(kind), line


@pytest.mark.parametrize("where", ["--train", "--out"])
def test_a_symbolic_link_loop_is_one_line_not_an_internal_error(tmp_path, capfd, demo, where):
    """A path that is a symbolic link loop (a -> b -> a): Path.resolve raised RuntimeError in the
    output check, reported as "internal error: RuntimeError: Symlink loop" with exit status 1."""
    (tmp_path / "a").symlink_to(tmp_path / "b")
    (tmp_path / "b").symlink_to(tmp_path / "a")
    paths = {"--train": demo, "--out": tmp_path / "o.csv", where: tmp_path / "a"}
    code, err = cli(capfd, "behave", "--train", paths["--train"], "--input", demo,
                    "--out", paths["--out"])
    line = one_line(err)
    assert code == 2 and "internal error" not in line and str(tmp_path / "a") in line, line
    assert "symbolic links" in line and len(err.strip().splitlines()) == 1


def test_out_to_a_pipe_writes_through_it_and_keeps_it(tmp_path, capfd):
    """``--out`` naming a pipe (as ``/dev/stdout`` is when piped): the output goes through it
    and the pipe stays. The atomic write renamed a regular file over it: the reader got
    nothing and the pipe was gone (for /dev/stdout, run as root: the system's, until a boot)."""
    fifo = tmp_path / "poses.pipe"
    os.mkfifo(fifo)
    got: list[bytes] = []
    reader = threading.Thread(target=lambda: got.append(fifo.read_bytes()), daemon=True)
    reader.start()
    code, err = cli(capfd, "pose", "--describe", "--out", fifo)
    reader.join(10)
    if reader.is_alive():            # (the command never opened the pipe: let the reader go)
        try:
            os.close(os.open(fifo, os.O_WRONLY | os.O_NONBLOCK))
        except OSError:              # no reader left after all
            pass
        reader.join(10)
    assert code == 0, err
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)
    assert json.loads(got[0])["height_m"] == 0.3


def test_a_recording_to_a_device_or_pipe_is_refused(tmp_path, capfd):
    """``run --record`` naming a pipe (or /dev/null): one line, nothing started. A recording is
    never overwritten, so it went on beside it: to ``/dev/null-2``, a file in /dev."""
    fifo = tmp_path / "session.pipe"
    os.mkfifo(fifo)
    code, err = cli(capfd, "run", "--config", Path(__file__).resolve().parents[2] / "config.yaml",
                    "--headless", "--seconds", "0.5", "--record", fifo)
    line = one_line(err)
    assert code == 2 and f"{fifo}: is a device or pipe" in line, line
    assert sorted(p.name for p in tmp_path.iterdir()) == ["session.pipe"]


@pytest.mark.parametrize("command", ["run", "replay"])
def test_an_empty_output_path_is_said_to_be_empty(tmp_path, capfd, command):
    """``run --record ''`` and ``replay --out ''``: the path is empty (it was said to be the
    folder '.', which it never named), one line, exit status 2, nothing started."""
    args = {"run": ["run", "--config", Path(__file__).resolve().parents[2] / "config.yaml",
                    "--headless", "--seconds", "0.5", "--record", ""],
            "replay": ["replay", tmp_path / "absent.jsonl", "--out", ""]}[command]
    code, err = cli(capfd, *args)
    line = one_line(err)
    option = {"run": "--record", "replay": "--out"}[command]
    assert code == 2 and f"{option}: the path is empty" in line and "folder" not in line, line


@pytest.mark.parametrize("args, name", [
    (["run", "--config", "", "--seconds", "0.5"], "--config"),
    (["run", "--config=", "--seconds", "0.5"], "--config"),
    (["replay", ""], "SESSION.jsonl"),
    (["review", ""], "SESSION_LOG"),
    (["track", "", "--out", "o.jsonl"], "INPUT"),
])
def test_an_empty_input_is_said_to_be_empty(tmp_path, capfd, args, name):
    """A script's unset variable (``tabletop replay "$F"``): the path '' was the current
    folder, said as ".: is a folder", or "the folder holds no images" for ``track``."""
    code, err = cli(capfd, *args)
    line = one_line(err)
    assert code == 2 and line.endswith(f" error: {name}: the value is empty (an unset "
                                       "variable in a script?)"), line


def test_out_to_a_name_of_a_stream_leading_to_a_file_writes_through_it(tmp_path, capfd):
    """``--out /dev/stdout > poses.json``: /dev/stdout is a link (through /proc/self/fd/1) to a
    regular file, so it passed as one; the atomic write renamed a file over the link (run as
    root: the system's /dev/stdout, until a boot) and the redirected file got nothing. A link
    through /proc stands in for /dev/stdout; ``run --record`` of it is refused."""
    out = tmp_path / "poses.json"
    out.write_text("")
    fd = os.open(out, os.O_WRONLY)
    link = tmp_path / "stdout"
    link.symlink_to(f"/proc/self/fd/{fd}")
    try:
        code, err = cli(capfd, "pose", "--describe", "--out", link)
        assert code == 0, err
        assert link.is_symlink() and os.readlink(link) == f"/proc/self/fd/{fd}"
        assert json.loads(out.read_text())["height_m"] == 0.3
        assert sorted(p.name for p in tmp_path.iterdir()) == ["poses.json", "stdout"]
        code, err = cli(capfd, "run", "--config",
                        Path(__file__).resolve().parents[2] / "config.yaml",
                        "--headless", "--seconds", "0.5", "--record", link)
        assert code == 2 and f"{link}: is a device or pipe" in one_line(err), err
        assert sorted(p.name for p in tmp_path.iterdir()) == ["poses.json", "stdout"]
    finally:
        os.close(fd)


def test_replay_out_that_cannot_be_started_is_refused_before_it_plays(tmp_path, capfd):
    """``replay --out`` under a file: one line naming it and exit status 2, as ``run --record``
    is refused: nothing is replayed into no file (a replay is no table to keep running)."""
    cfg = tmp_path / "c.yaml"
    cfg.write_text("sources: [{kind: scripted, pucks: [1]}]\nview: {enabled: false}\n")
    rec = tmp_path / "rec.jsonl"
    code, err = cli(capfd, "run", "--config", cfg, "--seconds", "0.3", "--record", rec)
    assert code == 0, err
    (tmp_path / "notes.txt").write_text("")
    code, err = cli(capfd, "replay", rec, "--fast", "--out", tmp_path / "notes.txt" / "r.jsonl")
    line = one_line(err)
    assert code == 2 and "notes.txt is a file" in line and "keeps running" not in line, line


def test_replay_out_cut_short_by_a_full_disk_exits_3(tmp_path, capfd):
    """A replay whose --out stops part way (here a file size limit, RLIMIT_FSIZE) exits with
    status 3, as ``run`` does, naming --out: a script comparing replays must not take the part
    written for the whole."""
    import resource
    import signal
    import subprocess
    import sys

    cfg = tmp_path / "c.yaml"
    cfg.write_text("sources: [{kind: scripted, pucks: [1, 2]}]\nview: {enabled: false}\n")
    rec = tmp_path / "rec.jsonl"
    # 120 ticks (2 s of its 60 Hz loop: 72.6 kB), counted: a 2 s run given a sixth of the
    # machine recorded 36.0-36.7 kB, less than the three limits' worth --out must reach
    from tabletop.app import build_live
    from tabletop.config import load_config
    build_live(load_config(cfg), headless=True, record_path=rec).loop.run(seconds=300,
                                                                         max_ticks=120)
    assert rec.stat().st_size > 3 * 16384

    def limit() -> None:
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (16384, 16384))

    out = tmp_path / "again.jsonl"
    r = subprocess.run([sys.executable, "-m", "tabletop", "replay", str(rec), "--fast",
                        "--out", str(out)], capture_output=True, text=True, preexec_fn=limit,
                       timeout=60)
    assert r.returncode == 3, r.stderr
    assert "Traceback" not in r.stderr
    (said,) = [ln for ln in r.stderr.splitlines() if "is incomplete" in ln]
    assert f"--out {out} is incomplete" in said and "File too large" in said, said


def test_replay_out_on_a_full_disk_is_refused_before_it_plays(tmp_path):
    """A replay whose --out the disk cannot take even the header of (a file size limit,
    RLIMIT_FSIZE, as a full disk or quota refuses it) exits with status 2 at once, one line
    naming the folder and why, no file left: it played the whole session into no file, then
    exited 3."""
    import resource
    import signal
    import subprocess
    import sys

    cfg = tmp_path / "c.yaml"
    cfg.write_text("sources: [{kind: scripted, pucks: [1]}]\nview: {enabled: false}\n")
    rec = tmp_path / "rec.jsonl"
    r = subprocess.run([sys.executable, "-m", "tabletop", "run", "--config", str(cfg),
                        "--seconds", "0.3", "--record", str(rec)], capture_output=True,
                       text=True, timeout=60)
    assert r.returncode == 0, r.stderr

    def limit() -> None:
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (200, 200))   # less than a header

    out = tmp_path / "out" / "again.jsonl"
    r = subprocess.run([sys.executable, "-m", "tabletop", "replay", str(rec), "--fast",
                        "--out", str(out)], capture_output=True, text=True, preexec_fn=limit,
                       timeout=60)
    assert r.returncode == 2, r.stderr
    line = one_line(r.stderr)
    assert f"{out.parent}: cannot start a recording there: File too large" in line, line
    assert "replayed" not in r.stderr and list(out.parent.iterdir()) == []


@pytest.mark.parametrize("describe", [False, True])
def test_pose_out_naming_a_folder_suggests_the_file_it_writes(tmp_path, capfd, describe):
    """``pose --describe --out FOLDER`` suggested FOLDER/out.jsonl for the one JSON object it
    writes: it suggests describe.json there, poses.jsonl for the poses."""
    (tmp_path / "t.csv").write_text("t,id,x,y\n0,1,0.6,0.4\n")
    args = ["--describe"] if describe else ["--input", tmp_path / "t.csv"]
    code, err = cli(capfd, "pose", *args, "--out", tmp_path)
    line = one_line(err)
    want = "describe.json" if describe else "poses.jsonl"
    assert code == 2 and line.endswith(f"give a file name such as {tmp_path / want}"), line
