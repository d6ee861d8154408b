"""Camera capture in its own thread: a device, a video file or a folder of images, newest frame
only.

``CameraSource`` grabs frames with ``cv2.VideoCapture`` (a device index such as ``0``, a device
path such as ``/dev/video2``, a video file) or reads a folder of images in name order, hands each
frame with its capture time (monotonic seconds) to a ``process`` callable (marker detection,
mapping to the table) in the same thread, and keeps only the newest result. When the input
vanishes (unplugged, file ended or removed, device error) the thread releases it and retries with
a growing back-off; ``health()`` says what happened ("camera lost; reconnecting in 2.0 s") and
the loop keeps running on the last observation. ``latest()`` never blocks and never raises.

Files and folders are played at their frame rate (``fps``, else the file's own, else 30), as a
camera would deliver them; when one ends it is opened again from its start after the back-off.
That loop is logged once, not as a failure and a return at every end: a 4 s video wrote two
lines each time (369 in a 28-minute gallery soak, a 1 MB x 5 kiosk log rotated in a day).
"""

from __future__ import annotations

import collections
import logging
import math
import os
import threading
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Protocol

import numpy as np

from tabletop.frames import Observation, SourceHealth
from tracking.badinput import BackgroundSource, RetryLog

log = logging.getLogger("tabletop.camera")

IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff", ".pgm", ".ppm", ".webp")

# process(image, capture time s, frame number) -> the observation to publish (or None: skip).
Process = Callable[[np.ndarray, float, int], "Observation | None"]


@dataclass(frozen=True)
class CameraSettings:
    """Where frames come from and how. ``device``: an int index, or a device path, video file or
    folder of images; ``resolution`` (width, height) px, ``fps`` and ``exposure`` (the driver's
    units; V4L2: 100 us steps) are requested from devices, None leaves the driver's choice;
    ``fps`` also paces files and folders. ``grey``: convert frames to 8-bit grey.
    ``retry_min_s``/``retry_max_s``: back-off between reconnection attempts (doubling).
    ``stall_s``: a device that delivers nothing for this long is reopened."""

    device: int | str = 0
    resolution: tuple[int, int] | None = None
    fps: float | None = None
    exposure: float | None = None
    grey: bool = True
    retry_min_s: float = 0.5
    retry_max_s: float = 8.0
    stall_s: float = 3.0


class FrameReader(Protocol):
    """An opened input: ``read()`` returns the next image, or None when it has ended or failed."""

    paced_fps: float | None  # files and folders: deliver at this rate; devices: None
    # A reader may also set ``capture_t`` (monotonic s) to the shutter time of the image it
    # returned; otherwise the time read() returned is taken.

    def read(self) -> np.ndarray | None: ...

    def release(self) -> None: ...


class InputLost(Exception):
    """The input cannot be opened (or is gone); the message says what an operator would check."""


def is_device(device: int | str) -> bool:
    """True for a camera (an index or a /dev path), False for a file or folder."""
    return isinstance(device, int) or str(device).startswith("/dev/")


def describe(device: int | str) -> str:
    return f"camera {device}" if isinstance(device, int) else str(device)


class VideoReader:
    """``cv2.VideoCapture`` on a device or a video file."""

    def __init__(self, settings: CameraSettings) -> None:
        import cv2
        self.cv2 = cv2
        dev = settings.device
        if not is_device(dev) and not Path(dev).is_file():
            raise InputLost(f"{dev} not found")
        self.cap = cv2.VideoCapture(dev) if isinstance(dev, int) else cv2.VideoCapture(str(dev))
        if not self.cap.isOpened():
            self.cap.release()
            what = "" if is_device(dev) else ": not a video file OpenCV can read"
            raise InputLost(f"cannot open {describe(dev)}{what}")
        self.paced_fps: float | None = None
        if is_device(dev):
            self._configure(settings)
        else:
            own = self.cap.get(cv2.CAP_PROP_FPS)
            self.paced_fps = settings.fps or (own if own and 0 < own < 1000 else 30.0)

    def _configure(self, s: CameraSettings) -> None:
        cv2, cap = self.cv2, self.cap
        cap.set(cv2.CAP_PROP_BUFFERSIZE, 1)  # the newest frame, not a queue of old ones
        if s.resolution is not None:
            cap.set(cv2.CAP_PROP_FRAME_WIDTH, int(s.resolution[0]))
            cap.set(cv2.CAP_PROP_FRAME_HEIGHT, int(s.resolution[1]))
        if s.fps is not None:
            cap.set(cv2.CAP_PROP_FPS, float(s.fps))
        if s.exposure is not None:
            cap.set(cv2.CAP_PROP_AUTO_EXPOSURE, 1)  # V4L2: 1 = manual, 3 = auto
            cap.set(cv2.CAP_PROP_EXPOSURE, float(s.exposure))

    def read(self) -> np.ndarray | None:
        ok, image = self.cap.read()
        return image if ok and image is not None else None

    def release(self) -> None:
        self.cap.release()


class FolderReader:
    """A folder of images taken in name order; ends after the last one."""

    def __init__(self, settings: CameraSettings) -> None:
        import cv2
        self.cv2 = cv2
        folder = Path(settings.device)
        if not folder.is_dir():
            raise InputLost(f"{folder} not found")
        self.files = sorted(p for p in folder.iterdir() if p.suffix.lower() in IMAGE_SUFFIXES)
        if not self.files:
            raise InputLost(f"{folder} has no images ({', '.join(IMAGE_SUFFIXES)})")
        self.index = 0
        self.paced_fps: float | None = settings.fps or 30.0

    def read(self) -> np.ndarray | None:
        while self.index < len(self.files):
            path = self.files[self.index]
            self.index += 1
            image = self.cv2.imread(str(path), self.cv2.IMREAD_UNCHANGED)
            if image is not None:
                return image
            if not path.exists():
                return None  # the folder is going away: treat as lost
            log.warning("%s: not a readable image; skipped", path)
        return None

    def release(self) -> None:
        pass


def open_reader(settings: CameraSettings) -> FrameReader:
    """The reader for ``settings.device``: a folder reader for folders, else VideoCapture."""
    dev = settings.device
    if isinstance(dev, str) and not is_device(dev) and Path(dev).is_dir():
        return FolderReader(settings)
    return VideoReader(settings)


def to_grey(image: np.ndarray) -> np.ndarray:
    """8-bit grey from grey, BGR or BGRA (16-bit images are scaled down)."""
    import cv2
    if image.dtype != np.uint8:
        image = cv2.convertScaleAbs(image, alpha=255.0 / max(float(image.max()), 1.0))
    if image.ndim == 2:
        return image
    if image.shape[2] == 4:
        return cv2.cvtColor(image, cv2.COLOR_BGRA2GRAY)
    return cv2.cvtColor(image, cv2.COLOR_BGR2GRAY)


class PhaseLock:
    """Times a paced input's frames to arrive just before the loop asks for them.

    A source whose shutter it controls (a synthetic camera, a file played back, a triggered
    camera) notes every ``latest()`` call and how long a frame takes from shutter to published;
    ``schedule(planned, period)`` moves the next shutter to finish ``margin_s`` before a loop
    tick, never sooner than half a frame period before ``planned``. This removes up to a whole
    loop period of waiting from the capture-to-render latency. Times in monotonic seconds.

    The lead is the slowest processing time of the last ``window`` frames, not a typical one:
    a frame that misses its tick is seen a whole tick later, so every miss adds a loop period
    to the latency. Measured on the default installation (1280x720, 60 Hz): leading by the
    90th percentile missed 2.5% of ticks (capture-to-tick p99 24 ms); leading by the maximum
    missed under 1% (p99 11 ms) for 0.5 ms more median latency.
    """

    def __init__(self, margin_s: float = 0.001, window: int = 30) -> None:
        self.margin_s = margin_s
        self._lock = threading.Lock()
        self.calls: collections.deque[float] = collections.deque(maxlen=window)
        self.processing: collections.deque[float] = collections.deque(maxlen=window)

    def note_call(self, t: float) -> None:
        with self._lock:
            self.calls.append(t)

    def note_processing(self, seconds: float) -> None:
        with self._lock:
            self.processing.append(seconds)

    def schedule(self, planned: float, period: float) -> float:
        """The shutter time for the frame planned at ``planned`` (unchanged when no steady loop
        is calling)."""
        with self._lock:
            calls, processing = list(self.calls), list(self.processing)
        if len(calls) < 4 or not processing or planned - calls[-1] > 1.0:
            return planned
        tick = float(np.median(np.diff(calls)))
        if not 1e-3 <= tick <= 1.0:
            return planned
        lead = float(np.max(processing)) + self.margin_s
        earliest = planned - 0.5 * period + lead
        last = calls[-1]
        k = math.ceil((earliest - last) / tick)
        return last + k * tick - lead


class CameraSource(BackgroundSource):
    """A ``Source`` whose thread grabs and processes frames, keeping only the newest observation.

    ``process(image, t, n)`` turns a frame (grey when ``settings.grey``) captured at ``t``
    (monotonic s) into an Observation; without it the observation carries just the image.
    ``process.after_publish()`` (optional) runs once the frame's observation is out and
    announced; an Observation it returns (the same capture time: what a put-off search added)
    replaces it, unless a newer frame did, and is announced again.
    ``opener`` opens the input (default :func:`open_reader`), ``clock`` gives monotonic seconds.
    Health: a camera starting (opening, or open with its first frame on its way) is healthy for
    ``settings.stall_s`` after ``open()``; a failure, or no frame for ``stall_s``, is not.
    """

    def __init__(self, name: str, settings: CameraSettings, process: Process | None = None,
                 opener: Callable[[CameraSettings], FrameReader] = open_reader,
                 clock: Callable[[], float] = time.monotonic,
                 phase_lock: PhaseLock | None = None) -> None:
        self.name, self.settings, self.clock = name, settings, clock
        self._retries = RetryLog(name, log, clock=clock)
        self.phase_lock = phase_lock
        self.process = process or (lambda image, t, n: Observation(name, t, n, image=image))
        self.opener = opener
        self._lock = threading.Lock()
        self._init_thread()
        self._latest: Observation | None = None
        self._last_frame_t = -math.inf
        self._frames = 0
        self._ok = False
        self._message = "starting"
        self._retry_at: float | None = None
        self._started_t = math.inf   # when open() started the thread (monotonic s)
        self._starting = True        # nothing has failed since open(), no frame came yet
        self.reconnects = 0  # successful reopenings after a loss (for the overlay and tests)
        self._said_loop = False   # a file or folder played to its end was logged
        # Called with the capture time of each new observation, from this source's thread (the
        # loop ticks on it: tabletop.loop.LiveInputs). A loop that follows the frames needs no
        # phase lock: the lock is only used while nothing is notified.
        self.notify: Callable[[float], None] | None = None

    # ------------------------------------------------------------------ Source protocol
    def open(self) -> None:
        """As :class:`BackgroundSource`'s, noting when the start began (health's grace)."""
        if self._thread is not None:
            return
        self._stop.clear()
        self._started_t, self._starting = self.clock(), True
        self._thread = threading.Thread(target=self._run, name=f"camera:{self.name}", daemon=True)
        self._thread.start()

    def latest(self) -> Observation | None:
        if self.phase_lock is not None:
            self.phase_lock.note_call(self.clock())
        with self._lock:
            return self._latest

    def health(self) -> SourceHealth:
        now = self.clock()
        with self._lock:
            age = now - self._last_frame_t
            ok, message, starting = self._ok, self._message, self._starting
            if self._retry_at is not None:
                message = f"{message}; reconnecting in {max(0.0, self._retry_at - now):.1f} s"
        if starting and math.isinf(age):
            # Starting: opening, or open with the first frame on its way. Nothing has failed,
            # so the table is not down (no "one moment", no unhealthy heartbeat) until the
            # start has taken the camera's stall_s.
            waited = now - self._started_t
            ok = waited <= self.settings.stall_s
            message = f"{message}, waiting for the first frame" if ok else "no frame yet"
        elif ok and age > self.settings.stall_s:
            ok, message = False, ("no frame yet" if math.isinf(age)
                                  else f"no frame for {age:.1f} s")
        note = getattr(self.process, "note", "")  # e.g. "uncalibrated" from the processing
        if note:
            message = f"{message} ({note})"
        return SourceHealth(self.name, ok, message, age)

    # ------------------------------------------------------------------ the capture thread
    def _set(self, ok: bool, message: str, retry_at: float | None = None) -> None:
        with self._lock:
            self._ok, self._message, self._retry_at = ok, message, retry_at
            self._starting = self._starting and ok

    def _run(self) -> None:
        delay = self.settings.retry_min_s
        opened_before = False
        while not self._stop.is_set():
            what = describe(self.settings.device)
            delivered = False
            try:
                reader = self.opener(self.settings)
            except InputLost as exc:
                reason = str(exc)
            except Exception as exc:  # a driver error must not end the thread
                reason = f"cannot open {what}: {exc}"
            else:
                if opened_before:
                    self.reconnects += 1
                opened_before = True
                self._set(True, f"{what} open")
                try:
                    reason, delivered = self._grab(reader)
                finally:
                    try:
                        reader.release()
                    except Exception:
                        log.exception("%s: release failed", what)
                if delivered:
                    delay = self.settings.retry_min_s
            if self._stop.is_set():
                break
            if delivered and reason == f"{what} ended":   # played to its end: it loops
                if not self._said_loop:
                    log.info("%s: %s ended; played again from its start whenever it ends (not "
                             "logged again)", self.name, what)
                    self._said_loop = True
                # at once and healthy: a wait marked unhealthy read as a failing camera in the
                # status a third of the time (a 1 s folder at 30 fps; 0.5 s without frames a loop)
                continue
            self._retries.failed(reason, delay)
            self._set(False, reason, self.clock() + delay)
            self._stop.wait(delay)
            delay = min(delay * 2.0, self.settings.retry_max_s)
        self._set(False, "closed")

    def _grab(self, reader: FrameReader) -> tuple[str, bool]:
        """Read until the input ends or fails; returns (why it stopped, whether frames came)."""
        what = describe(self.settings.device)
        period = 1.0 / reader.paced_fps if reader.paced_fps else 0.0
        next_t = self.clock()
        delivered = False
        last_good = self.clock()
        while not self._stop.is_set():
            if period:
                if self.phase_lock is not None and self.notify is None:
                    next_t = self.phase_lock.schedule(next_t, period)
                wait = next_t - self.clock()
                if wait > 0 and self._stop.wait(wait):
                    break
                next_t = max(next_t + period, self.clock() - period)
            try:
                image = reader.read()
            except Exception as exc:
                return f"{what} failed: {exc}", delivered
            t = self.clock()
            shutter = getattr(reader, "capture_t", None)  # a reader that knows its shutter time
            if image is None:
                if is_device(self.settings.device):
                    if t - last_good < self.settings.stall_s:
                        self._stop.wait(0.01)
                        continue
                    return f"{what} lost", delivered
                return f"{what} ended", delivered
            last_good = t
            if not delivered:
                self._retries.worked(what)
            delivered = True
            self._publish(image, t if shutter is None else shutter)
        return "closed", delivered

    def _publish(self, image: np.ndarray, t: float) -> None:
        if self.settings.grey:
            image = to_grey(image)
        n = self._frames + 1
        try:
            obs = self.process(image, t, n)
        except Exception as exc:  # keep grabbing: a bad frame must not stop the camera
            log.exception("%s: processing a frame failed", self.name)
            self._set(False, f"processing failed: {exc}")
            return
        if self.phase_lock is not None:
            self.phase_lock.note_processing(self.clock() - t)
        with self._lock:
            self._frames = n
            self._last_frame_t = t
            if obs is not None:
                self._latest = obs
            if not self._ok:
                self._ok, self._retry_at = True, None
                self._message = f"{describe(self.settings.device)} open"
        notify = self.notify
        if notify is not None and obs is not None:
            notify(t)
        # Work that may wait (a detector's full-frame search); what it adds to the frame's
        # observation (same capture time) is published and announced at once.
        after = getattr(self.process, "after_publish", None)
        if after is not None:
            try:
                more = after()
            except Exception:
                log.exception("%s: work after publishing a frame failed", self.name)
                more = None
            if isinstance(more, Observation) and obs is not None and more.t == obs.t:
                with self._lock:
                    fresh = self._latest is obs
                    if fresh:
                        self._latest = more
                if fresh and notify is not None:
                    notify(t)

    @property
    def frames(self) -> int:
        """Frames processed since opening."""
        return self._frames


def settings_from_options(options: dict[str, Any]) -> CameraSettings:
    """CameraSettings from a validated config mapping (keys as in CameraSettings)."""
    dev = options.get("device", 0)
    if isinstance(dev, str) and dev.isdigit():
        dev = int(dev)
    if isinstance(dev, os.PathLike):
        dev = str(dev)
    res = options.get("resolution")
    return CameraSettings(
        device=dev, resolution=None if res is None else (int(res[0]), int(res[1])),
        fps=options.get("fps"), exposure=options.get("exposure"), grey=options.get("grey", True),
        retry_min_s=options.get("retry_min_s", 0.5), retry_max_s=options.get("retry_max_s", 8.0),
        stall_s=options.get("stall_s", 3.0))
