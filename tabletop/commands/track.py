"""``tabletop track``: marker poses of every frame of a video, an image folder or a camera.

One JSON line per input frame: ``{"frame": i, "t": s, "pucks": [{"id", "x", "y", "angle",
"state"}]}``. Without ``--calibration`` positions are marker centres in image pixels and angles
``atan2(c1.y - c0.y, c1.x - c0.x)`` in the image; with one, table metres and table radians. A
``seen`` puck carries its measured pose (identity kept, outliers rejected, not smoothed unless
``--smooth``); a ``coasting`` one its prediction. ``t`` is frame index / fps, never the clock.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import re
import sys
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any, Iterator

from tabletop.commands import number_in_range, output_file
from tabletop.errors import InputError

if TYPE_CHECKING:
    import numpy as np

    from tabletop.frames import Puck

HELP = ("detect and track marker pucks in every frame of a video file, an image folder or a "
        "camera, writing one JSON line of puck poses per frame")

IMAGE_SUFFIXES = {".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff", ".pgm", ".ppm", ".webp"}


class TrackInputError(InputError):
    """A bad ``track`` input or argument."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("input", metavar="INPUT",
                        help="a video file, a folder of images (taken in name order) or a "
                             "camera index")
    parser.add_argument("--out", required=True, metavar="POSES.jsonl",
                        help="output: one JSON line per frame")
    parser.add_argument("--dictionary", default=None, metavar="NAME",
                        help="OpenCV marker dictionary, e.g. DICT_4X4_50 (default) or "
                             "DICT_APRILTAG_36h11")
    parser.add_argument("--calibration", default=None, metavar="FILE",
                        help="calibration YAML: report table metres and table angles "
                             "(default: camera pixels)")
    parser.add_argument("--fps", default=None, metavar="F",
                        help="frames per second for t (a folder: default 30; a video or camera: "
                             "its own rate)")
    parser.add_argument("--smooth", action="store_true",
                        help="apply the live installation's jitter filter to seen pucks")
    parser.add_argument("--config", default=None, metavar="FILE",
                        help="take the tracking section (detector, filter) from this config")


MAX_FPS = 10_000.0        # frames per second: beyond any camera or video
MAX_CAMERA_INDEX = 1023    # OpenCV's camera indices (V4L2 has /dev/video0 to /dev/video63)
# a video whose last frames, up to this share of its declared count (at least SHORT_MIN of
# them), are not there is taken as over-declared, with a warning (FrameReader._short_at_end)
SHORT_TOLERANCE = 0.05
SHORT_MIN = 3


def parse_fps(text: str | None) -> float | None:
    if text is None:
        return None
    return number_in_range(text, "--fps", "frames per second", 0.001, MAX_FPS, TrackInputError)


@contextlib.contextmanager
def _quiet_opencv(cv2: Any) -> Iterator[None]:
    """Silence OpenCV's and its video back-ends' own messages (written straight to stderr) while
    opening a device or file or reading an image: a failure is reported as one clear line
    instead."""
    from tabletop.quiet import quiet_stderr
    log = getattr(getattr(cv2, "utils", None), "logging", None)
    level = log.getLogLevel() if log is not None else None
    if log is not None:
        log.setLogLevel(log.LOG_LEVEL_SILENT)
    try:
        with quiet_stderr():
            yield
    finally:
        if log is not None:
            log.setLogLevel(level)


def folder_images(folder: Path) -> list[Path]:
    """The images of ``folder`` (a folder INPUT's frames), in name order."""
    return sorted(p for p in folder.iterdir() if p.is_file() and p.suffix.lower() in IMAGE_SUFFIXES)


class FrameReader:
    """Grey frames of INPUT in order: ``frames()`` yields them; ``total`` (None for a camera)
    and ``fps`` (None when the input does not say)."""

    def __init__(self, spec: str) -> None:
        import cv2
        self.cv2 = cv2
        self.spec = spec
        self.files: list[Path] | None = None
        self.capture = None
        self.total: int | None = None
        self.missing = 0          # declared frames that were not there at the end
        self.fps: float | None = None
        self.is_camera = False
        path = Path(spec)
        if spec.isdigit() and not path.exists():
            if int(spec) > MAX_CAMERA_INDEX:
                raise TrackInputError(f"INPUT {spec!r} is neither a file, a folder nor a camera "
                                      f"index (0 to {MAX_CAMERA_INDEX})")
            with _quiet_opencv(cv2):
                self.capture = cv2.VideoCapture(int(spec))
            if not self.capture.isOpened():
                raise TrackInputError(f"camera {spec} cannot be opened")
            self.is_camera = True
            fps = self.capture.get(cv2.CAP_PROP_FPS)
            self.fps = fps if fps and math.isfinite(fps) and fps > 0 else None
        elif path.is_dir():
            self.files = folder_images(path)
            if not self.files:
                raise TrackInputError(f"{spec}: the folder holds no images "
                                      f"({', '.join(sorted(IMAGE_SUFFIXES))})")
            self.total = len(self.files)
        elif path.is_file():
            with _quiet_opencv(cv2):
                self.capture = cv2.VideoCapture(str(path))
            if not self.capture.isOpened():
                raise TrackInputError(f"{spec}: not a video file OpenCV can read")
            n = int(self.capture.get(cv2.CAP_PROP_FRAME_COUNT) or 0)
            self.total = n if n > 0 else None
            fps = self.capture.get(cv2.CAP_PROP_FPS)
            self.fps = fps if fps and math.isfinite(fps) and fps > 0 else None
        elif path.exists():   # a device, a pipe or a socket: /dev/null, /dev/video0
            video = re.fullmatch(r"/dev/video(\d+)", str(path))
            hint = (f"; for this camera give its index, {video[1]}" if video else "")
            raise TrackInputError(f"{spec}: is a device or pipe, not a video file, a folder of "
                                  f"images or a camera index{hint}")
        else:
            raise TrackInputError(f"{spec}: no such file, folder or camera index")

    def frames(self) -> Iterator[np.ndarray]:
        """Every frame of the input in order, grey; TrackInputError for an unreadable image, a
        video without frames or one cut short before its declared frame count."""
        cv2 = self.cv2
        if self.files is not None:
            for p in self.files:
                with _quiet_opencv(cv2):
                    img = cv2.imread(str(p), cv2.IMREAD_GRAYSCALE)
                if img is None:
                    raise TrackInputError(f"{p}: not an image OpenCV can read")
                yield img
            return
        from tabletop.quiet import quiet_stderr
        read = 0
        while True:
            if self.is_camera:
                ok, img = self.capture.read()
            else:   # FFmpeg's own complaints about a damaged file ("[mjpeg @ 0x..] overread")
                with quiet_stderr():
                    ok, img = self.capture.read()
            if not ok or img is None:
                if read == 0 and not self.is_camera:
                    raise TrackInputError(f"{self.spec}: the video has no readable frames")
                if self.total is not None and read < self.total:
                    if self._short_at_end(read):
                        self.missing = self.total - read
                        return
                    # as a folder's unreadable image is: every frame of a file is processed,
                    # and a cut-short video wrote fewer lines than it has frames, saying nothing
                    raise TrackInputError(f"{self.spec}: frame {read} cannot be read; the video "
                                          f"declares {self.total} frames (damaged or cut short)")
                return
            read += 1
            yield cv2.cvtColor(img, cv2.COLOR_BGR2GRAY) if img.ndim == 3 else img

    def _short_at_end(self, read: int) -> bool:
        """Whether a video that ended after ``read`` of its declared frames only over-declared
        them: the shortfall is at most SHORT_TOLERANCE of them (at least SHORT_MIN) and no
        frame follows the failed one. The declared count is the container's estimate (OpenCV's
        CAP_PROP_FRAME_COUNT: nb_frames, or duration x fps), known to exceed intact files'
        decodable frames by a few, so such a file is not refused whole. A frame that cannot be
        decoded with frames after it is a damaged file, refused whatever the shortfall."""
        assert self.total is not None and self.capture is not None
        short = self.total - read
        if short > max(SHORT_MIN, int(self.total * SHORT_TOLERANCE)):
            return False
        from tabletop.quiet import quiet_stderr
        with quiet_stderr():
            return not any(self.capture.grab() for _ in range(short))

    def close(self) -> None:
        if self.capture is not None:
            self.capture.release()


class Progress:
    """A one-line progress bar on stderr (for files, where the frame count is known), only
    when stderr is a terminal: a script reading stderr gets the error line alone. :meth:`end`
    ends the bar's line, so an error is said on a line of its own."""

    def __init__(self, total: int | None, enabled: bool) -> None:
        self.total = total
        self.enabled = enabled and total is not None and sys.stderr.isatty()
        self._last = 0.0
        self._open = False      # the bar's line is on screen, not ended yet

    def update(self, done: int, force: bool = False) -> None:
        """Show ``done`` frames of the total (at most every 0.2 s unless ``force``)."""
        if not self.enabled:
            return
        now = time.monotonic()
        if not force and now - self._last < 0.2:
            return
        self._last = now
        frac = min(done / max(self.total or 1, 1), 1.0)
        bar = "#" * int(frac * 30)
        # open before the write: a Ctrl-C landing just after it (a signal is handled between
        # two statements) left the bar unended, and "interrupted" was glued to it
        self._open = True
        sys.stderr.write(f"\rtrack [{bar:<30}] {done}/{self.total} frames")
        if force:
            self.end()
        sys.stderr.flush()

    def end(self) -> None:
        if self._open:
            sys.stderr.write("\n")
            sys.stderr.flush()
            self._open = False


def _tracking_options(args: argparse.Namespace) -> dict[str, Any]:
    options: dict[str, Any] = {}
    if args.config:
        from tabletop.config import load_config
        options = dict(load_config(args.config).get("tracking") or {})
    if args.dictionary:
        options["dictionary"] = args.dictionary
    from tabletop.plugins import tracking as plugin
    from tabletop.schema import ConfigError
    try:
        return plugin.complete(options)
    except ConfigError as exc:
        if args.dictionary and "dictionary" in str(exc):
            raise TrackInputError(f"--dictionary {args.dictionary!r} is not an OpenCV marker "
                                  f"dictionary (e.g. DICT_4X4_50, DICT_APRILTAG_36h11)") from None
        raise


def _puck_json(p: Puck, smooth: bool) -> dict[str, Any]:
    """A puck's output record: x, y and angle as the puck carries them (table metres and
    radians, or image pixels and image radians without a calibration); a ``seen`` puck's
    measured pose unless ``smooth``."""
    if p.state == "seen" and not smooth:
        x, y, a = p.raw_x, p.raw_y, p.raw_angle
    else:
        x, y, a = p.x, p.y, p.angle
    return {"id": int(p.id), "x": round(float(x), 6), "y": round(float(y), 6),
            "angle": round(float(a), 6), "state": p.state}


def check_size(calibration: Any, grey: np.ndarray, args: argparse.Namespace) -> None:
    """Refuse frames of another size than the calibration's ``image_size``: their table
    positions were written without a word, all wrong (the live camera source warns of it)."""
    size = None if calibration is None else calibration.image_size
    h, w = grey.shape[:2]
    if size is not None and tuple(size) != (w, h):
        raise TrackInputError(f"{args.input}: frames are {w}x{h} pixels, but {args.calibration} "
                              f"is for {size[0]}x{size[1]}; their table positions would be "
                              "wrong (use frames at that size, or this camera's calibration)")


def main(args: argparse.Namespace) -> int:
    import numpy as np

    from tabletop.files import atomic_writer
    from tabletop.plugins import tracking as plugin
    from tracking.markers import marker_measurements, marker_side_lengths
    from tracking.pucks import PuckTracker

    fps_arg = parse_fps(args.fps)
    options = _tracking_options(args)
    calibration = None
    if args.calibration:
        from calibration.files import load_calibration
        calibration = load_calibration(args.calibration)
    # the images of a folder INPUT are inputs too: "--out frames/f000.png" overwrote the first
    # with the poses (and the next run called it "not an image OpenCV can read")
    folder = Path(args.input)
    images = folder_images(folder) if folder.is_dir() else []
    out = output_file(args.out, "--out", TrackInputError,
                      inputs=(args.input, args.calibration, args.config, *images))
    if folder.is_dir() and out.suffix.lower() in IMAGE_SUFFIXES \
            and out.absolute().parent.resolve() == folder.resolve():
        raise TrackInputError(f"--out {out}: is an image name in the INPUT folder, whose next "
                              "run would read the poses as a frame; give a .jsonl file name")
    reader = FrameReader(args.input)
    fps = fps_arg or reader.fps or 30.0
    detector = plugin.build_detector(options)
    to_table = calibration.image_to_table if calibration is not None else None
    id_map = plugin.puck_id_map(options)
    marker_of = {p: m for m, p in id_map.items()}
    tracker: PuckTracker | None = None
    progress = Progress(reader.total, enabled=not reader.is_camera)

    frames = 0
    try:
        with atomic_writer(out) as f:
            try:
                for i, grey in enumerate(reader.frames()):
                    if i == 0:
                        check_size(calibration, grey, args)
                    t = i / fps
                    preds = None
                    if tracker is not None:
                        p = {marker_of.get(k, k): xy for k, xy in tracker.predict(t).items()}
                        if p and calibration is not None:
                            ids = list(p)
                            px = calibration.table_to_image(np.array([p[k] for k in ids]))
                            preds = {k: (float(q[0]), float(q[1])) for k, q in zip(ids, px)}
                        elif p:
                            preds = p
                    ids, corners = detector.detect(grey, preds)
                    if tracker is None and len(ids):
                        # Tracker units: metres, or pixels scaled by the markers' size.
                        scale = 1.0 if calibration is not None else float(
                            np.median(marker_side_lengths(corners)) / options["marker_size"])
                        tracker = PuckTracker(plugin.tracker_settings(options, scale,
                                                                      smooth=True))
                    pucks = () if tracker is None else tracker.step(
                        marker_measurements(ids, corners, t, to_table, id_map), t)
                    line = {"frame": i, "t": round(t, 9),
                            "pucks": [_puck_json(p, args.smooth) for p in pucks]}
                    f.write(json.dumps(line, separators=(",", ":")) + "\n")
                    frames = i + 1
                    progress.update(frames)
            except KeyboardInterrupt:
                if not reader.is_camera:
                    raise
        progress.update(frames, force=True)
    finally:
        progress.end()
        reader.close()
    if reader.missing:
        print(f"tabletop track: warning: {args.input}: {frames} frames read; the video declares "
              f"{reader.total}, its last {reader.missing} are not there (an over-declared "
              "count; every frame there was tracked)", file=sys.stderr)
    return 0
