"""The camera and synthetic_camera sources as config.yaml builds them: frames on disk or rendered,
markers found by the tracking section's detector, pucks reported in table metres."""

import itertools
import math
import threading
import time
from pathlib import Path

import cv2
import numpy as np
import pytest

from calibration.files import Calibration, save_calibration
from tabletop.config import validate_config
from tabletop.frames import InputError
from tabletop.plugins import camera as camera_plugin
from tabletop.plugins import synthetic_camera
from tabletop.registry import BuildContext
from tracking import scenes
from tracking.synthetic import CameraSettings, SyntheticCamera, scripted_hands
from tracking.visitor import ScriptedVisitor

TABLE = (1.2, 0.8)


def build(entry: dict, tmp_path: Path, tracking: dict | None = None):
    cfg = validate_config({"sources": [entry], **({"tracking": tracking} if tracking else {})},
                          "test.yaml", tmp_path)
    ctx = BuildContext(TABLE, 60.0, cfg, tmp_path)
    module = {"camera": camera_plugin, "synthetic_camera": synthetic_camera}[entry["kind"]]
    return module.build(cfg["sources"][0], ctx), ctx


def wait_for(predicate, timeout: float = 10.0) -> bool:
    return scenes.wait_for(predicate, timeout)


def write_frames(folder: Path, cam: SyntheticCamera, n: int = 8):
    """n frames of 3 pucks moving on lines; returns the true poses per frame."""
    folder.mkdir()
    truth = []
    for k in range(n):
        poses = [(7, 0.2 + 0.005 * k, 0.3, 0.02 * k), (11, 0.9, 0.2 + 0.004 * k, -2.0),
                 (23, 0.6, 0.6, 3.0 - 0.03 * k)]
        f = cam.render(poses, t=k / 30.0)
        cv2.imwrite(str(folder / f"{k:04d}.png"), f.image)
        truth.append({p[0]: p[1:] for p in poses})
    return truth


def test_camera_on_a_folder_with_a_calibration_file(tmp_path):
    cam = SyntheticCamera(CameraSettings(tilt_deg=18.0, distortion=(-0.1, 0.02, 0, 0, 0)))
    truth = write_frames(tmp_path / "frames", cam)
    save_calibration(tmp_path / "calib.yaml",
                     Calibration(cam.image_to_table_homography(), None, cam.K, cam.dist))
    src, ctx = build({"kind": "camera", "name": "overhead", "device": "frames",
                      "calibration": "calib.yaml", "fps": 60.0}, tmp_path)
    seen = {}
    src.open()
    try:
        assert wait_for(lambda: src.frames >= 1)
        assert src.health().ok

        def collect():
            obs = src.latest()
            if obs is not None:
                seen[obs.seq] = obs
            return len(seen) >= 8 and src.frames >= 8
        assert wait_for(collect)
    finally:
        src.close()
    assert "calibration_dict" in ctx.shared  # the recorder's header gets it
    errors, headings = [], []
    for seq in range(1, 9):
        if seq not in seen:
            continue
        obs = seen[seq]
        assert obs.source == "overhead" and {m.id for m in obs.pucks} == {7, 11, 23}
        for m in obs.pucks:
            x, y, a = truth[seq - 1][m.id]
            errors.append(math.hypot(m.x - x, m.y - y))
            headings.append(abs(math.remainder(m.angle - a, math.tau)))
            assert m.t == obs.t
    assert len(errors) >= 12
    assert np.median(errors) <= 0.001 and max(errors) <= 0.003  # metres
    assert np.degrees(np.median(headings)) <= 1.0


def test_camera_without_calibration_stretches_the_image_over_the_table(tmp_path):
    cam = SyntheticCamera(CameraSettings(tilt_deg=0.0, margin=0.0, resolution=(640, 360)))
    write_frames(tmp_path / "frames", cam, n=2)
    src, _ = build({"kind": "camera", "device": str(tmp_path / "frames"), "fps": 60.0}, tmp_path)
    src.open()
    try:
        assert wait_for(lambda: src.latest() is not None and len(src.latest().pucks) == 3)
        pucks = {m.id: m for m in src.latest().pucks}
    finally:
        src.close()
    assert "uncalibrated" in src.health().message
    # Roughly in place (the table fills the image's height, not all of its width).
    assert all(0.0 <= m.x <= TABLE[0] and 0.0 <= m.y <= TABLE[1] for m in pucks.values())
    assert pucks[11].x > pucks[7].x and pucks[23].y > pucks[7].y


@pytest.mark.parametrize("device, message", [
    (-1, "expected a camera index"),
    ("missing.mp4", "does not exist"),
    (True, "expected a camera index"),
])
def test_bad_devices_are_refused_at_start(tmp_path, device, message):
    with pytest.raises(InputError, match=message) as info:
        build({"kind": "camera", "device": device}, tmp_path)
    assert "sources[0].device" in str(info.value)


@pytest.mark.parametrize("device, words", [
    ("notes.txt", "'notes.txt': not a video file OpenCV can read"),
    ("empty.mp4", "'empty.mp4': not a video file OpenCV can read"),
    ("empty", "'empty': the folder holds no images (.png, .jpg"),
    ("/dev/null", "/dev/null is not a video device (a camera is /dev/videoN)"),
])
def test_an_input_that_cannot_be_played_is_refused_at_start(tmp_path, device, words):
    (tmp_path / "notes.txt").write_text("hello")
    (tmp_path / "empty.mp4").write_bytes(b"")
    (tmp_path / "empty").mkdir()
    with pytest.raises(InputError) as info:
        validate_config({"sources": [{"kind": "camera", "device": device}]}, "t.yaml", tmp_path)
    assert str(info.value).startswith(f"t.yaml: sources[0].device: {words}")


def test_devices_may_be_absent_at_start(tmp_path):
    cfg = validate_config({"sources": [{"kind": "camera", "device": "/dev/video63"},
                                       {"kind": "camera", "name": "b", "device": "3"}]},
                          "t.yaml", tmp_path)
    assert cfg["sources"][0]["device"] == "/dev/video63" and cfg["sources"][1]["device"] == 3


@pytest.mark.parametrize("exposure, words", [
    (-5, "-5 is out of range: expected V4L2 units of 100 us from 1 to 10000 (-5 as DirectShow's "
         "log2 seconds is 312 here)"),
    (0, "expected a number in [1, 10000] (V4L2 units of 100 us), got 0.0 (out of range)"),
    (50_000, "expected a number in [1, 10000] (V4L2 units of 100 us), got 50000.0"),
])
def test_an_exposure_v4l2_does_not_take_is_refused_with_its_units(tmp_path, exposure, words):
    with pytest.raises(InputError) as info:
        validate_config({"sources": [{"kind": "camera", "exposure": exposure}]}, "t.yaml", tmp_path)
    assert str(info.value).startswith("t.yaml: sources[0].exposure: ") and words in str(info.value)
    cfg = validate_config({"sources": [{"kind": "camera", "exposure": 156}]}, "t.yaml", tmp_path)
    assert cfg["sources"][0]["exposure"] == 156.0


def test_synthetic_camera_reports_the_visitor_and_hides_covered_pucks(tmp_path):
    start = {pid: (x, y) for pid, x, y, _ in ScriptedVisitor(TABLE, [1, 2], seed=4).poses(0.0)}
    hand = {"x": start[2][0], "y": start[2][1], "size": 0.12}  # lying on puck 2
    src, _ = build({"kind": "synthetic_camera", "pucks": [1, 2], "seed": 4, "fps": 30.0,
                    "resolution": [960, 540], "occluders": [hand], "hands": {"every_s": 0}},
                   tmp_path, tracking={"dictionary": "DICT_APRILTAG_36h11"})
    src.open()
    try:
        assert wait_for(lambda: src.frames >= 5)
        obs, frame = src.truth()
        assert src.health().ok and "synthetic camera" in src.health().message
    finally:
        src.close()
    assert frame.visible.tolist() == [True, False]
    assert [m.id for m in obs.pucks] == [1]
    m = obs.pucks[0]
    assert math.hypot(m.x - frame.poses[0, 0], m.y - frame.poses[0, 1]) <= 0.002
    assert obs.t == frame.t


@pytest.mark.parametrize("marker, puck", [(0.4, 0.3), (0.06, 0.075)])
def test_synthetic_camera_refuses_a_marker_its_puck_cannot_carry(tmp_path, marker, puck):
    """A marker wider than its puck failed every render, for ever; one whose corners stick out
    was rendered cut and never found."""
    with pytest.raises(InputError) as info:
        build({"kind": "synthetic_camera", "marker_size": marker, "puck_diameter": puck}, tmp_path)
    assert str(info.value).startswith(f"test.yaml: sources[0].puck_diameter: a {puck:g} m puck "
                                      f"cannot carry a {marker:g} m marker (its corners stick "
                                      "out); give a puck_diameter of at least")


def test_synthetic_camera_refuses_an_unknown_dictionary(tmp_path):
    with pytest.raises(InputError, match="DICT_5X5_NOPE"):
        build({"kind": "synthetic_camera", "dictionary": "DICT_5X5_NOPE"}, tmp_path)


def test_scripted_hands_come_and_go():
    times = np.arange(0.0, 30.0, 0.05)
    present = np.array([bool(scripted_hands(t, TABLE, every_s=10.0, duration_s=2.0))
                        for t in times])
    assert 0.15 <= present.mean() <= 0.21  # 2 s in every 10 s
    assert not present[(times % 10.0) > 2.05].any()
    reach = [scripted_hands(t, TABLE, 10.0, 2.0)[0] for t in (10.0 + 0.01, 11.0)]
    assert reach[0].y < 0.0 <= reach[1].y <= TABLE[1]  # comes in over the near edge
    assert scripted_hands(11.0, TABLE, 10.0, 2.0) == scripted_hands(11.0, TABLE, 10.0, 2.0)
    assert scripted_hands(5.0, TABLE, every_s=0.0) == []


def test_calibration_for_another_resolution_is_reported(tmp_path):
    cam = SyntheticCamera(CameraSettings(resolution=(640, 360)))
    write_frames(tmp_path / "frames", cam, n=2)
    save_calibration(tmp_path / "c.yaml", Calibration(cam.image_to_table_homography(),
                                                      image_size=(1280, 720)))
    src, _ = build({"kind": "camera", "device": "frames", "calibration": "c.yaml"}, tmp_path)
    src.open()
    try:
        assert wait_for(lambda: src.frames >= 1)
        assert "calibrated for 1280x720 but frames are 640x360" in src.health().message
    finally:
        src.close()


def test_tracker_predictions_guide_the_detector_to_the_right_pixels(tmp_path):
    """The loop's tracker predicts each puck's table position; the camera turns it into pixel
    predictions for the detector's region-of-interest search, close to where the marker is."""
    from tabletop.plugins.tracking import build_tracker
    cfg = validate_config({"sources": [{"kind": "synthetic_camera", "pucks": [1, 2, 3],
                                        "seed": 2, "fps": 30.0, "tilt_deg": 20.0,
                                        "distortion": [-0.1, 0.02, 0, 0, 0],
                                        "hands": {"every_s": 0}}]}, "t.yaml", tmp_path)
    ctx = BuildContext(TABLE, 60.0, cfg, tmp_path)
    tracker = build_tracker(cfg["tracking"], ctx)
    ctx.shared["tracker"] = tracker
    src = synthetic_camera.build(cfg["sources"][0], ctx)
    real = src.measurer
    errors = []

    class Recording:
        def __init__(self, detector):
            self.detector = detector

        def detect(self, grey, predictions_px=None):
            frame = src.reader.frame
            for pid, (px, py) in (predictions_px or {}).items():
                j = frame.ids.tolist().index(pid)
                errors.append(float(np.hypot(px - frame.centres[j, 0], py - frame.centres[j, 1])))
            return self.detector.detect(grey, predictions_px)

    real.detector = Recording(real.detector)
    enough = threading.Event()

    def notify(t: float) -> None:
        """Each frame's observation is given to the tracker as it is announced, before the next
        frame is detected (as a loop ticking on the camera's frames does): each prediction is
        one frame ahead. (Fed from a thread polling at 60 Hz, a thread starved on a loaded
        machine left the tracker 0.3 s behind: p95 error 38 px.)"""
        obs = src.latest()
        if obs is not None and obs.t == t:
            tracker.update([obs], obs.t)
        if len(errors) >= 180:
            enough.set()

    src.notify = notify
    open_reader = src.opener

    def opener(settings):
        """Frame k's shutter is at k / 30 s on the reader's own clock, whenever the camera
        thread gets to render it: a prediction is always one 1/30 s frame ahead. (On the
        monotonic clock a starved camera thread spaced its frames further apart, each
        prediction reaching further ahead: at load 13 median 2.19 px, p95 12.16 px; a 0.15 s
        stall on 10% of the frames here gave 15 px on each frame after one.)"""
        reader = open_reader(settings)
        render, frames, now = reader.render, itertools.count(), [0.0]
        reader.t0, reader.clock = 0.0, lambda: now[0]

        def render_next(*args):
            now[0] = next(frames) / 30.0
            return render(*args)
        reader.render = render_next
        return reader

    src.opener = opener
    src.open()
    try:    # 60 frames of 3 pucks predicted (2 s of script)
        enough.wait(60.0)
    finally:
        src.close()
    assert len(errors) >= 180
    assert np.median(errors) <= 3.0 and np.percentile(errors, 95) <= 10.0  # pixels


def test_synthetic_frames_show_the_scene_at_their_shutter_and_are_never_early(tmp_path):
    """The synthetic camera's shutter is at the end of its render: each frame shows the script
    as it stands at the frame's capture time, is announced (``notify``) with that time once its
    observation is ready, and never before that time."""
    src, _ = build({"kind": "synthetic_camera", "pucks": [1, 2], "seed": 3, "fps": 30.0,
                    "resolution": [640, 360], "hands": {"every_s": 0}}, tmp_path)
    announced = []

    def notify(t):
        obs, frame = src.truth()
        announced.append((t, time.monotonic(), obs, frame))

    src.notify = notify
    started, open_reader = {}, src.opener

    def opener(settings):   # each frame's shutter time -> the reader's clock as its render began
        reader = open_reader(settings)
        clock, render = reader.clock, reader.render

        def timed_render(*args):
            stamps = []
            reader.clock = lambda: stamps.append(clock()) or stamps[-1]
            t = render(*args)
            started[t] = stamps[0]
            return t
        reader.render = timed_render
        return reader

    src.opener = opener
    src.open()
    try:
        assert wait_for(lambda: len(announced) >= 8)
    finally:
        src.close()
    reader = src.reader
    assert len(reader.render_s) >= 7 and min(reader.render_s) > 0.0
    for t, at, obs, frame in announced:
        assert obs.t == frame.t == t and at >= t
        assert t > started[t] or t == announced[0][0]  # the render's own time is not latency
        script = {p[0]: p[1:3] for p in reader.poses(t - reader.t0)}
        for pid, (x, y) in zip(frame.ids.tolist(), frame.poses[:, :2].tolist()):
            assert (x, y) == pytest.approx(script[pid], abs=1e-9)


def test_a_render_process_gives_the_same_scene_and_comes_back_when_it_dies(tmp_path):
    """``render_process``: frames rendered by a child process show the script at their
    shutter time, the pucks are found where they are, a child that dies is replaced (the
    camera reconnects, its script starting again) and closing the camera ends the child."""
    src, _ = build({"kind": "synthetic_camera", "pucks": [1, 2], "seed": 3, "fps": 30.0,
                    "resolution": [640, 360], "hands": {"every_s": 0},
                    "render_process": True}, tmp_path)
    announced = []
    src.notify = lambda t: announced.append((t, time.monotonic(), src.reader.t0, *src.truth()))
    src.open()
    try:
        assert wait_for(lambda: len(announced) >= 8, timeout=60.0)
        first = src.reader
        first.proc.kill()
        assert wait_for(lambda: src.reconnects >= 1 and src.reader is not first, timeout=60.0)
        assert wait_for(lambda: sum(a[2] == src.reader.t0 for a in announced) >= 8, timeout=60.0)
    finally:
        src.close()
    assert first.proc.poll() is not None and src.reader.proc.poll() is not None
    both = set()   # the scripts (before, after the reconnection) with both pucks found
    for t, at, t0, obs, frame in announced:
        assert obs.t == frame.t == t and at >= t
        script = {p[0]: p[1:3] for p in src.poses(t - t0)}
        truth = dict(zip(frame.ids.tolist(), frame.poses[:, :2].tolist()))
        for pid, (x, y) in truth.items():
            assert (x, y) == pytest.approx(script[pid], abs=1e-9)
        for m in obs.pucks:
            assert math.hypot(m.x - truth[m.id][0], m.y - truth[m.id][1]) <= 0.003
        if {m.id for m in obs.pucks} == {1, 2}:
            both.add(t0)
    assert len(both) == 2


def test_a_put_off_search_adds_a_puck_put_down_to_its_frame_in_table_metres():
    """The camera's measurer returns the frame's observation again with the puck the put-off
    full-frame search found (same time and seq, table metres), on the frame it was due for."""
    from tracking.roi import MarkerTracker
    cam = SyntheticCamera(CameraSettings(resolution=(1280, 720), seed=5))
    measurer = camera_plugin.MarkerMeasurer("cam", MarkerTracker(full_period=3, defer_full=True),
                                            synthetic_camera.true_calibration(cam), TABLE)
    base = [(1, 0.3, 0.3, 0.0), (2, 0.8, 0.5, 1.0)]
    added_at = None
    for k in range(8):
        poses = base + ([(9, 0.6, 0.6, 0.3)] if k >= 2 else [])
        obs = measurer(cam.render(poses, k / 30.0).image, k / 30.0, k + 1)
        more = measurer.after_publish()
        assert 9 not in {m.id for m in obs.pucks} or added_at is not None
        if more is not None:
            assert (more.t, more.seq, more.pucks[:len(obs.pucks)]) == (obs.t, obs.seq, obs.pucks)
            new = more.pucks[len(obs.pucks):]
            assert [m.id for m in new] == [9] and added_at is None
            assert math.hypot(new[0].x - 0.6, new[0].y - 0.6) <= 0.003
            added_at = k
    assert added_at == 3   # the first full-frame search after it was put down


def test_a_render_process_that_dies_is_logged_as_a_failure_each_time(tmp_path, caplog):
    """A killed render process is a warning naming it (how it ended), each time it happens,
    and the camera comes back. It was taken for a video file's end: one INFO line "ended;
    played again from its start whenever it ends (not logged again)", and later deaths were
    silent."""
    import logging
    caplog.set_level(logging.INFO)
    src, _ = build({"kind": "synthetic_camera", "pucks": [1], "fps": 30.0,
                    "resolution": [320, 180], "hands": {"every_s": 0},
                    "render_process": True}, tmp_path)
    frames = []
    src.notify = lambda t: frames.append(t)
    src.open()
    try:
        for death in range(2):
            assert wait_for(lambda: len(frames) >= 3, timeout=60.0)
            reader = src.reader
            reader.proc.kill()
            assert wait_for(lambda: src.reader is not reader and src.reconnects >= death + 1,
                            timeout=60.0)
            frames.clear()
        assert wait_for(lambda: len(frames) >= 3, timeout=60.0)
    finally:
        src.close()
    said = [r for r in caplog.records if "render process" in r.getMessage()]
    assert len(said) == 2, [r.getMessage() for r in caplog.records]
    assert all(r.levelno == logging.WARNING and "ended (killed by SIGKILL)" in r.getMessage()
               for r in said), [r.getMessage() for r in said]
    assert not [r for r in caplog.records if "played again" in r.getMessage()]
