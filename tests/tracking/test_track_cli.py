"""``tabletop track`` on folders of synthetic frames, against their ground truth."""

from __future__ import annotations

import json
import math
import subprocess
import sys

import cv2
import numpy as np
import pytest

from tabletop import cli
from tests import children
from tracking.markers import marker_headings
from tracking.scenes import moving_scene
from tracking.synthetic import CameraSettings, Occluder, SyntheticCamera

FRAMES = 24


@pytest.fixture(scope="module")
def scene(tmp_path_factory):
    folder = tmp_path_factory.mktemp("frames")
    cam = SyntheticCamera(CameraSettings(resolution=(1280, 720), seed=21))
    truth = []
    for k, (t, poses, vels) in enumerate(moving_scene(4, FRAMES, 30.0, speed=0.3, seed=5)):
        # A hand covers puck 0 for frames 8..13.
        occ = [Occluder(poses[0][1] - 0.03, poses[0][2], 0.0, 0.13)] if 8 <= k < 14 else []
        f = cam.render(poses, t, vels, occluders=occ)
        cv2.imwrite(str(folder / f"frame_{k:04d}.png"), f.image)
        truth.append(f)
    return folder, cam, truth


def _read(path):
    return [json.loads(line) for line in path.read_text().splitlines()]


def test_pixels_one_line_per_frame_matching_ground_truth(scene, tmp_path):
    folder, _, truth = scene
    out = tmp_path / "poses.jsonl"
    assert cli.main(["track", str(folder), "--out", str(out)]) == 0
    lines = _read(out)
    assert [ln["frame"] for ln in lines] == list(range(FRAMES))
    assert [ln["t"] for ln in lines] == pytest.approx([k / 30.0 for k in range(FRAMES)])
    errs, heads = [], []
    for ln, f in zip(lines, truth):
        by_id = {p["id"]: p for p in ln["pucks"]}
        heading = marker_headings(f.corners)
        for i, pid in enumerate(f.ids):
            p = by_id.get(int(pid))
            if f.visible[i]:
                assert p is not None and p["state"] == "seen"
                errs.append(math.hypot(p["x"] - f.centres[i, 0], p["y"] - f.centres[i, 1]))
                heads.append(abs(math.remainder(p["angle"] - heading[i], math.tau)))
            else:
                assert p is None or p["state"] == "coasting"
        assert set(by_id) <= set(f.ids.tolist())
    assert np.median(errs) <= 0.5 and np.percentile(errs, 95) <= 1.5
    assert math.degrees(np.median(heads)) <= 1.0
    hidden = [ln for ln, f in zip(lines, truth) if not f.visible[0]]
    assert hidden and all(any(p["id"] == 0 and p["state"] == "coasting" for p in ln["pucks"])
                          for ln in hidden[:5])


def test_calibration_gives_table_metres_and_smooth_stays_close(scene, tmp_path):
    from calibration.files import Calibration, save_calibration
    folder, cam, truth = scene
    calib = tmp_path / "calibration.yaml"
    save_calibration(calib, Calibration(cam.image_to_table_homography(), image_size=(1280, 720)))
    for smooth in (False, True):
        out = tmp_path / f"poses_{smooth}.jsonl"
        argv = ["track", str(folder), "--out", str(out), "--calibration", str(calib),
                "--fps", "30"] + (["--smooth"] if smooth else [])
        assert cli.main(argv) == 0
        errs, heads = [], []
        for ln, f in zip(_read(out), truth):
            by_id = {p["id"]: p for p in ln["pucks"]}
            for i, pid in enumerate(f.ids):
                if f.visible[i]:
                    p = by_id[int(pid)]
                    errs.append(math.hypot(p["x"] - f.poses[i, 0], p["y"] - f.poses[i, 1]))
                    heads.append(abs(math.remainder(p["angle"] - f.poses[i, 2], math.tau)))
        limit = 0.01 if smooth else 0.001  # metres: smoothing lags a moving puck a little
        assert np.median(errs) <= limit
        assert math.degrees(np.median(heads)) <= (3.0 if smooth else 1.0)


def test_bad_inputs_give_one_line_errors(tmp_path, capsys):
    out = tmp_path / "o.jsonl"
    (tmp_path / "bad.png").write_bytes(b"not a png")
    (tmp_path / "video.mp4").write_bytes(b"not a video")
    empty = tmp_path / "empty"
    empty.mkdir()
    cases = [
        ([str(tmp_path / "missing"), "--out", str(out)], "no such file"),
        # a device exists: "no such file" would send the user looking for a missing path
        (["/dev/null", "--out", str(out)], "/dev/null: is a device or pipe, not a video file"),
        ([str(empty), "--out", str(out)], "no images"),
        ([str(empty), "--out", str(out), "--fps", "-3"], "--fps"),
        ([str(tmp_path), "--out", str(out)], "bad.png"),
        ([str(tmp_path / "video.mp4"), "--out", str(out)], "video.mp4"),
        ([str(empty), "--out", str(out), "--dictionary", "DICT_NOPE"], "DICT_NOPE"),
        ([str(empty), "--out", str(out), "--calibration", str(tmp_path / "nope.yaml")],
         "nope.yaml"),
    ]
    for argv, expect in cases:
        assert cli.main(["track"] + argv) == 2
        err = capsys.readouterr().err.strip()
        assert len(err.splitlines()) == 1 and expect in err and "Traceback" not in err
    assert not out.exists()


def test_config_tracking_section_maps_marker_ids(scene, tmp_path):
    folder, _, truth = scene
    cfg = tmp_path / "config.yaml"
    cfg.write_text("sources:\n  - kind: scripted\ntracking:\n  puck_ids: {'0': 40}\n")
    out = tmp_path / "poses.jsonl"
    assert cli.main(["track", str(folder), "--out", str(out), "--config", str(cfg)]) == 0
    first = {p["id"] for p in _read(out)[0]["pucks"]}
    assert first == ({int(i) for i in truth[0].ids} - {0}) | {40}
    bad = tmp_path / "bad.yaml"
    bad.write_text("sources:\n  - kind: scripted\ntracking:\n  coast_s: -1\n")
    assert cli.main(["track", str(folder), "--out", str(out), "--config", str(bad)]) == 2


def test_video_file_every_frame_at_the_video_rate(scene, tmp_path):
    folder, _, truth = scene
    video = tmp_path / "clip.avi"
    writer = cv2.VideoWriter(str(video), cv2.VideoWriter_fourcc(*"MJPG"), 25.0, (1280, 720))
    assert writer.isOpened()
    for f in truth[:10]:
        writer.write(cv2.cvtColor(f.image, cv2.COLOR_GRAY2BGR))
    writer.release()
    out = tmp_path / "poses.jsonl"
    assert cli.main(["track", str(video), "--out", str(out)]) == 0
    lines = _read(out)
    assert [ln["frame"] for ln in lines] == list(range(10))
    assert [ln["t"] for ln in lines] == pytest.approx([k / 25.0 for k in range(10)])
    for ln, f in zip(lines, truth):
        seen = {p["id"] for p in ln["pucks"] if p["state"] == "seen"}
        assert seen == {int(i) for i, v in zip(f.ids, f.visible) if v}


def test_a_script_reading_stderr_gets_the_error_line_alone(scene, tmp_path):
    # a frame that cannot be read, mid-folder: the error was appended to the progress bar
    # ("\rtrack [####...] 1/3 frames" + the error on one line); stderr not being a terminal,
    # no bar is drawn at all
    import shutil
    folder, _, _ = scene
    broken = tmp_path / "frames"
    broken.mkdir()
    for src in sorted(folder.iterdir())[:3]:
        shutil.copy(src, broken / src.name)
    sorted(broken.iterdir())[1].write_bytes(b"not a png")
    r = subprocess.run([sys.executable, "-m", "tabletop", "track", str(broken), "--out",
                        str(tmp_path / "p.jsonl")], capture_output=True, text=True, timeout=120)
    assert r.returncode == 2
    assert r.stderr.splitlines() == [f"tabletop track: error: {sorted(broken.iterdir())[1]}: "
                                     "not an image OpenCV can read"], r.stderr


def without_pygame(folder) -> dict:
    """This environment with a ``pygame`` first on the import path whose import ends the
    process at once (status 97, one line): a command that imports pygame fails."""
    import os
    blocker = folder / "no-pygame" / "pygame"
    blocker.mkdir(parents=True)
    (blocker / "__init__.py").write_text(
        "import os\nos.write(2, b'pygame imported\\n')\nos._exit(97)\n")
    path = os.pathsep.join(p for p in (str(blocker.parent), os.environ.get("PYTHONPATH")) if p)
    return {**os.environ, "PYTHONPATH": path}


def test_a_folder_in_name_order_at_its_fps_no_config_unless_given_and_no_pygame(scene,
                                                                                 tmp_path):
    """As outside scripts call it (a process): a folder's images are taken in name order
    (whatever order they were written in), ``t`` is frame index / ``--fps``, and ``track``
    reads no configuration unless ``--config`` is given, not even a config.yaml where it runs
    (that one would map marker 0 to puck 40). Nor does it import pygame (the process would
    end: :func:`without_pygame`)."""
    import shutil
    folder, _, truth = scene
    frames = tmp_path / "frames"
    frames.mkdir()
    sources = sorted(folder.iterdir())[:6]
    for k in reversed(range(6)):               # written last to first
        shutil.copy(sources[k], frames / f"view-{k:02d}.png")
    (tmp_path / "config.yaml").write_text(
        "sources:\n  - kind: scripted\ntracking:\n  puck_ids: {'0': 40}\n")
    out = tmp_path / "poses.jsonl"
    r = subprocess.run([sys.executable, "-m", "tabletop", "track", str(frames), "--out",
                        str(out), "--fps", "12.5"], capture_output=True, text=True,
                       timeout=120, cwd=tmp_path, env=without_pygame(tmp_path))
    assert r.returncode == 0 and r.stderr == "" and r.stdout == "", r.stderr
    lines = _read(out)
    assert [ln["frame"] for ln in lines] == list(range(6))
    assert [ln["t"] for ln in lines] == pytest.approx([k / 12.5 for k in range(6)], abs=1e-9)
    for ln, f in zip(lines, truth):
        assert set(ln) == {"frame", "t", "pucks"}
        by_id = {p["id"]: p for p in ln["pucks"]}
        assert set(by_id) == {int(i) for i, v in zip(f.ids, f.visible) if v}   # no puck 40
        for i, pid in enumerate(f.ids):
            if f.visible[i]:
                p = by_id[int(pid)]
                assert set(p) == {"id", "x", "y", "angle", "state"} and p["state"] == "seen"
                assert math.hypot(p["x"] - f.centres[i, 0], p["y"] - f.centres[i, 1]) <= 1.5


def test_ctrl_c_mid_file_exits_130_with_one_line_and_leaves_no_output(scene, tmp_path):
    """README: exit status 130 when interrupted, one line, never a traceback; the output is
    written atomically, so an interrupted run leaves no POSES.jsonl at all. stderr is a
    pseudo-terminal, so the progress bar says when frames are being tracked."""
    import os
    import select
    import signal
    folder, _, _ = scene
    frames = tmp_path / "frames"
    frames.mkdir()
    first = sorted(folder.iterdir())[0]
    for k in range(2000):                      # far more than are tracked before the Ctrl-C
        (frames / f"f{k:05d}.png").symlink_to(first)
    out = tmp_path / "poses.jsonl"
    master, slave = os.openpty()
    proc = children.popen([sys.executable, "-m", "tabletop", "track", str(frames), "--out",
                           str(out)], stdout=subprocess.DEVNULL, stderr=slave)
    # the slave stays open here until the end: once every slave is closed a read of the master
    # may fail (EIO) before the kernel has passed on the process's last writes
    seen = b""
    try:
        while b"frames" not in seen:           # the bar: "track [###   ] k/2000 frames"
            ready, _, _ = select.select([master], [], [], 120)
            assert ready, seen
            seen += os.read(master, 4096)
        proc.send_signal(signal.SIGINT)
        assert proc.wait(timeout=120) == 130
        while select.select([master], [], [], 1)[0]:
            try:
                chunk = os.read(master, 4096)
            except OSError:                    # the terminal closed with the process
                break
            if not chunk:
                break
            seen += chunk
    finally:
        if proc.poll() is None:
            proc.kill()
        os.close(slave)
        os.close(master)
    lines = [ln for ln in seen.decode().replace("\r", "\n").splitlines() if ln.strip()]
    assert lines[-1] == "tabletop track: interrupted" and b"Traceback" not in seen, seen
    assert not out.exists() and not [p for p in tmp_path.iterdir() if p.name.startswith(".")]


def test_a_cut_short_video_is_one_line_and_writes_nothing(scene, tmp_path):
    """DESIGN: every frame of a file is processed, and bad input is one clear line. A video cut
    in half (a copy that did not finish) wrote the lines of the frames before the cut, said
    nothing, exited 0, and FFmpeg's own "[mjpeg @ 0x...] overread" came on stderr: now it is
    refused as a folder with an unreadable image is, in one line of ours, as a process."""
    folder, _, truth = scene
    video = tmp_path / "clip.avi"
    writer = cv2.VideoWriter(str(video), cv2.VideoWriter_fourcc(*"MJPG"), 25.0, (1280, 720))
    for f in truth[:12]:
        writer.write(cv2.cvtColor(f.image, cv2.COLOR_GRAY2BGR))
    writer.release()
    data = video.read_bytes()
    cut = tmp_path / "cut.avi"
    cut.write_bytes(data[:len(data) // 2])
    out = tmp_path / "poses.jsonl"
    r = subprocess.run([sys.executable, "-m", "tabletop", "track", str(cut), "--out", str(out)],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 2
    (line,) = r.stderr.splitlines()
    assert line.startswith(f"tabletop track: error: {cut}: frame ") and "declares 12" in line
    assert not out.exists()
    r = subprocess.run([sys.executable, "-m", "tabletop", "track", str(video), "--out", str(out)],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0 and r.stderr == "", r.stderr
    assert len(out.read_text().splitlines()) == 12


def _mjpg_avi(path, n: int, declared: int | None = None, wiped: int | None = None) -> None:
    """An MJPG AVI of ``n`` small numbered frames; its header declaring ``declared`` frames
    (AVI's avih total and strh length), and frame ``wiped``'s JPEG data zeroed (undecodable)."""
    import struct
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"MJPG"), 30.0, (160, 120))
    for i in range(n):
        img = np.full((120, 160, 3), (i * 7) % 255, np.uint8)
        cv2.putText(img, str(i), (10, 60), 0, 1, (255, 255, 255))
        writer.write(img)
    writer.release()
    b = bytearray(path.read_bytes())
    if declared is not None:
        struct.pack_into("<I", b, b.find(b"avih") + 8 + 16, declared)
        struct.pack_into("<I", b, b.find(b"strh") + 8 + 32, declared)
    if wiped is not None:
        pos, k = -1, -1
        while k < wiped:
            pos = b.find(b"00dc", pos + 1)
            size = struct.unpack_from("<I", b, pos + 4)[0]
            k += size > 100          # (the index's entries are small)
        b[pos + 8:pos + 8 + size] = bytes(size)
    path.write_bytes(b)


def test_a_video_declaring_a_few_frames_too_many_is_tracked_with_a_warning(tmp_path):
    """The declared frame count is the container's estimate and intact files can decode a few
    frames fewer: 40 frames declared as 42 give every frame's line, status 0 and one warning
    (not "frame 40 cannot be read", status 2 and no output); a frame that cannot be decoded
    with frames after it (near the end, within the same shortfall) is still refused."""
    video, out = tmp_path / "h42.avi", tmp_path / "poses.jsonl"
    _mjpg_avi(video, 40, declared=42)
    assert int(cv2.VideoCapture(str(video)).get(cv2.CAP_PROP_FRAME_COUNT)) == 42
    r = subprocess.run([sys.executable, "-m", "tabletop", "track", str(video), "--out", str(out)],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert r.stderr.splitlines() == [
        f"tabletop track: warning: {video}: 40 frames read; the video declares 42, its last 2 "
        "are not there (an over-declared count; every frame there was tracked)"], r.stderr
    assert [json.loads(ln)["frame"] for ln in out.read_text().splitlines()] == list(range(40))
    for wiped in (38, 20):
        damaged = tmp_path / f"wiped{wiped}.avi"
        _mjpg_avi(damaged, 40, wiped=wiped)
        out = tmp_path / f"poses{wiped}.jsonl"
        r = subprocess.run([sys.executable, "-m", "tabletop", "track", str(damaged), "--out",
                            str(out)], capture_output=True, text=True, timeout=120)
        assert r.returncode == 2 and r.stderr.splitlines() == [
            f"tabletop track: error: {damaged}: frame {wiped} cannot be read; the video "
            "declares 40 frames (damaged or cut short)"], r.stderr
        assert not out.exists()


def test_an_out_on_an_input_s_image_or_config_is_refused_before_any_frame(scene, tmp_path,
                                                                          capsys):
    """``--out frames/f.png`` wrote the poses over the folder's first image (the next run:
    "not an image OpenCV can read"); a new image name there poisoned the next run the same
    way; ``--out`` on ``--config`` or ``--calibration`` overwrote it. Each is one line, and
    every file stays as it was."""
    import shutil
    folder, _, _ = scene
    frames = tmp_path / "frames"
    frames.mkdir()
    for src in sorted(folder.iterdir())[:2]:
        shutil.copy(src, frames / src.name)
    first = sorted(frames.iterdir())[0]
    before = first.read_bytes()
    config = tmp_path / "c.yaml"
    config.write_text(text := "sources:\n  - kind: scripted\n")
    cases = [(first, [], f"is the input file {first}"),
             (frames / ".." / frames.name / first.name, [], "is the input file"),
             (frames / "new.PNG", [], "is an image name in the INPUT folder"),
             (config, ["--config", str(config)], f"is the input file {config}")]
    for out, extra, expect in cases:
        assert cli.main(["track", str(frames), "--out", str(out), *extra]) == 2
        err = capsys.readouterr().err.strip()
        assert len(err.splitlines()) == 1 and expect in err, err
    assert first.read_bytes() == before and config.read_text() == text
    assert sorted(p.name for p in frames.iterdir()) == sorted(p.name for p in
                                                             sorted(folder.iterdir())[:2])
    assert cli.main(["track", str(frames), "--out", str(frames / "poses.jsonl")]) == 0


def test_frames_of_another_size_than_the_calibration_are_refused(scene, tmp_path, capsys):
    """Frames at half the calibrated size were tracked without a word, every table position
    wrong (a puck at 0.5, 0.3 m written at 0.31, 0.15); the live camera warns of it."""
    from calibration.files import Calibration, save_calibration
    folder, cam, _ = scene
    small = tmp_path / "small"
    small.mkdir()
    first = sorted(folder.iterdir())[0]
    cv2.imwrite(str(small / first.name), cv2.resize(cv2.imread(str(first)), (640, 360)))
    calib = tmp_path / "calibration.yaml"
    save_calibration(calib, Calibration(cam.image_to_table_homography(), image_size=(1280, 720)))
    out = tmp_path / "o.jsonl"
    assert cli.main(["track", str(small), "--out", str(out), "--calibration", str(calib)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and f"{small}: frames are 640x360 pixels, but {calib} is " \
        "for 1280x720" in err, err
    assert not out.exists()
