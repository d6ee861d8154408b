"""The synthetic camera's rendering in a child process: images that cost the loop's process
nothing, as a real camera's do.

A real camera exposes and transfers its images in hardware; the installation's process only
receives them (``cv2.VideoCapture.read`` waits without Python's interpreter lock). The synthetic
camera simulates that hardware in Python: about 3 ms of CPU per 1280x720 frame, most of it
holding the interpreter lock, in the camera's thread, where it competes with the frame loop.
:class:`RenderProcessReader` renders in a child process instead (the same
:class:`~tabletop.plugins.synthetic_camera.SyntheticReader`, so the same images, shutter times
and ground truth) and hands each image over through shared memory; the camera's thread waits for
it without the lock, then detects markers as it would in a real camera's frames.

Measured (bench/loop.py's 4-reactor configuration in an X window, the bench at real-time
priority on a busy 2-core machine so that only the interpreter lock was shared, 4 interleaved
rounds of 5 s): capture-to-render 6.91 ms median / 10.31 ms p99 rendering in the camera's thread,
7.20 / 10.35 ms in a child process (the hand-over adds ~0.6 ms: 0.66 ms from shutter to the
image in the camera thread, 0.07 ms rendering there). The render's share of the lock is not
what delays frames, so the synthetic camera renders in its thread unless ``render_process``.

Protocol: the reader sends one request per frame (when the camera thread is due to read), the
child renders (the shutter at the end of the render, never delivered early), copies the image
into the shared buffer and answers with its capture time and ground truth. Times are
``time.monotonic`` seconds, the same clock in both processes.
"""

from __future__ import annotations

import collections
import logging
import mmap
import os
import pickle
import signal
import subprocess
import sys
import time
from multiprocessing.connection import Connection
from pathlib import Path
from typing import Callable

import numpy as np

from tracking.synthetic import (CameraSettings, Occluder, SyntheticCamera, SyntheticFrame,
                                scripted_hands)

log = logging.getLogger("tabletop.camera")

FIRST_FRAME_S = 30.0   # the child starts a Python interpreter and imports OpenCV first
FRAME_S = 2.0          # later frames: longer than this and the camera is treated as lost


class ScriptedHands:
    """``hands(s)``: fixed occluders plus a visitor's hand reaching over the table now and then
    (:func:`tracking.synthetic.scripted_hands`), at script time ``s`` seconds; picklable."""

    def __init__(self, fixed: list[Occluder], table: tuple[float, float], every_s: float,
                 duration_s: float, size: float, seed: int) -> None:
        self.fixed, self.table = list(fixed), table
        self.every_s, self.duration_s, self.size, self.seed = every_s, duration_s, size, seed

    def __call__(self, s: float) -> list[Occluder]:
        return self.fixed + scripted_hands(s, self.table, self.every_s, self.duration_s,
                                           self.size, self.seed)


class SyntheticReader:
    """A frame reader that renders the script as it stands at the frame's shutter time
    (``capture_t``, monotonic s).

    A camera's image exists when its exposure ends; rendering it here is a simulation of the
    world that costs time no real camera costs the installation. So the shutter is put at the
    end of the render: the scene is rendered as it will stand when the render is expected to be
    done (the median of the last ``LEAD_FRAMES`` renders), and the image is never delivered
    before its shutter time. A render that takes longer than expected delivers late, and that
    lateness counts in the capture-to-render latency like any other delay. (Waiting for the
    longest render instead would hold every frame that long: the camera's rate would fall.)
    """

    LEAD_FRAMES = 10
    shutter_at_end = True   # False: the shutter at the start of the render (its time counted)

    def __init__(self, camera: SyntheticCamera, poses: Callable[[float], list],
                 hands: Callable[[float], list[Occluder]], fps: float,
                 clock: Callable[[], float]) -> None:
        self.camera, self.poses, self.hands, self.clock = camera, poses, hands, clock
        self.paced_fps: float | None = fps
        self.t0 = clock()
        self.capture_t: float | None = None
        self.frame: SyntheticFrame | None = None
        self.render_s: collections.deque[float] = collections.deque(maxlen=self.LEAD_FRAMES)

    def read(self) -> np.ndarray:
        t = self.render()
        done = self.clock()
        if t > done:
            time.sleep(t - done)
        self.capture_t = t
        return self.frame.image

    def render(self, hand_over: Callable[[SyntheticFrame], object] | None = None) -> float:
        """Render the next frame into ``frame`` and return its shutter time (monotonic s),
        not waiting for it; ``hand_over(frame)`` (a copy to where it goes) counts as part of
        the render."""
        start = self.clock()
        lead = float(np.median(self.render_s)) if self.render_s and self.shutter_at_end else 0.0
        t = start + lead
        s = t - self.t0
        now = self.poses(s)
        dt = 0.005
        before = {p[0]: p for p in self.poses(s - dt)}
        velocities = [((p[1] - before[p[0]][1]) / dt, (p[2] - before[p[0]][2]) / dt)
                      if p[0] in before else (0.0, 0.0) for p in now]
        self.frame = self.camera.render(now, t, velocities, self.hands(s))
        if hand_over is not None:
            hand_over(self.frame)
        self.render_s.append(self.clock() - start)
        return t

    def release(self) -> None:
        pass


def _render_child(requests: Connection, answers: Connection, image_fd: int) -> None:
    """The child process: render a frame per request into the shared image until told to stop
    (None) or the parent is gone."""
    from tracking.synthetic import SyntheticCamera

    settings, poses, hands, fps = requests.recv()
    reader = SyntheticReader(SyntheticCamera(settings), poses, hands, fps, time.monotonic)
    w, h = reader.camera.w, reader.camera.h
    with mmap.mmap(image_fd, w * h) as shared:
        out = np.ndarray((h, w), np.uint8, buffer=shared)
        while True:
            try:
                request = requests.recv()
            except (EOFError, OSError):
                break
            if request is None:
                break
            reader.t0, reader.shutter_at_end = request
            answer: list[bytes] = []

            def hand_over(f: SyntheticFrame) -> None:   # before the shutter time, not after
                out[...] = f.image
                answer.append(pickle.dumps((f.t, f.ids, f.corners, f.centres, f.poses,
                                            f.visible, f.occluders)))

            t = reader.render(hand_over)
            wait = t - time.monotonic()
            if wait > 0:
                time.sleep(wait)
            answers.send_bytes(answer[0])
        del out


class RenderProcessLost(Exception):
    """The render process died or stopped answering (the camera source reconnects)."""


class RenderProcessReader:
    """A frame reader whose frames a child process renders (see the module's docstring).
    ``read()`` returns the image (a copy out of the shared buffer, 8-bit grey) with its shutter
    time in ``capture_t`` and its ground truth in ``frame``; it raises
    :class:`RenderProcessLost` when the child is gone or late (the camera source then logs why
    and reconnects with a new child)."""

    def __init__(self, settings: CameraSettings, poses: Callable[[float], list],
                 hands: Callable[[float], list[Occluder]], fps: float) -> None:
        self.paced_fps: float | None = fps
        self.capture_t: float | None = None
        self.frame: SyntheticFrame | None = None
        self.t0 = time.monotonic()   # script time 0 (the camera's opening), monotonic s
        w, h = int(settings.resolution[0]), int(settings.resolution[1])
        # The image travels through an anonymous shared file; requests and answers through
        # pipes. A plain child interpreter (not multiprocessing's fork, unsafe with the
        # parent's threads, nor its spawn, which imports the parent's main module again).
        fd = os.memfd_create("synthetic camera image")
        os.ftruncate(fd, w * h)
        self._shared = mmap.mmap(fd, w * h)
        self.view = np.ndarray((h, w), np.uint8, buffer=self._shared)
        req_r, req_w = os.pipe()
        ans_r, ans_w = os.pipe()
        root = str(Path(__file__).resolve().parents[2])
        env = dict(os.environ, PYTHONPATH=os.pathsep.join(
            p for p in (root, os.environ.get("PYTHONPATH")) if p))
        try:
            self.proc = subprocess.Popen(
                [sys.executable, "-m", "tabletop.plugins.synthetic_render", str(req_r),
                 str(ans_w), str(fd)], pass_fds=(req_r, ans_w, fd), env=env,
                stdin=subprocess.DEVNULL)
        finally:
            for k in (req_r, ans_w, fd):
                os.close(k)
        self.requests = Connection(req_w, readable=False)
        self.answers = Connection(ans_r, writable=False)
        self.requests.send((settings, poses, hands, fps))
        self._frames = 0

    def read(self) -> np.ndarray:
        """The next image; RenderProcessLost when the child died or did not answer (not None,
        which the camera takes for a video file's end: a killed render process would be logged
        as "ended; played again from its start ... (not logged again)", at INFO, and every
        later death not at all)."""
        wait_s = FIRST_FRAME_S if self._frames == 0 else FRAME_S
        try:
            self.requests.send((self.t0, SyntheticReader.shutter_at_end))
            if not self.answers.poll(wait_s):
                raise RenderProcessLost(f"the render process did not answer within "
                                        f"{wait_s:g} s")
            t, ids, corners, centres, poses, visible, occluders = self.answers.recv()
        except (EOFError, OSError):
            raise RenderProcessLost(self._gone()) from None
        image = self.view.copy()
        self._frames += 1
        self.capture_t = t
        self.frame = SyntheticFrame(image, t, ids, corners, centres, poses, visible, occluders)
        return image

    def _gone(self) -> str:
        """Why the child is gone, in an operator's words."""
        try:
            code = self.proc.wait(timeout=1.0)
        except subprocess.TimeoutExpired:
            return "the render process stopped answering"
        how = (f"killed by {signal.Signals(-code).name}" if code < 0 and -code in
               signal.valid_signals() else f"exit status {code}")
        return f"the render process ended ({how})"

    def release(self) -> None:
        try:
            self.requests.send(None)
        except (OSError, ValueError):
            pass
        try:
            self.proc.wait(timeout=2.0)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait(timeout=2.0)
        self.requests.close()
        self.answers.close()
        del self.view
        self._shared.close()


if __name__ == "__main__":
    _render_child(Connection(int(sys.argv[1]), writable=False),
                  Connection(int(sys.argv[2]), readable=False), int(sys.argv[3]))
