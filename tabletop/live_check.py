"""The morning check measured during ``tabletop run`` and shown on the operator overlay.

With ``view.calibration_check: true`` the running installation is itself the projector-camera
pair: for a moment the view (the projector) shows the check's images instead of the show, and
the camera source's own frames are measured (:func:`tabletop.procam.run_check`). With a
``synthetic_camera`` source, a simulated projector of the view's size throws what the view
shows onto the synthetic table, so the same path runs without hardware.
"""

from __future__ import annotations

import logging
import threading
import time
from typing import Any, Callable, Sequence

import numpy as np

from calibration.charuco import CalibrationInputError
from tabletop.drawing.images import image_surface
from tabletop.procam import check_inputs, check_lines, run_check

log = logging.getLogger("tabletop")

CHECK_EVERY_S = 10.0  # a check every 10 s of the run
SETTLE_S = 0.3        # camera frames this long after the view showed an image see it


class Showing:
    """Wraps the view's renderer: while an image is set, the view draws it (the projector
    shows it) instead of the frame; ``shown`` is (token, monotonic s) of its first drawing.
    The image covers the whole window, so the renderer is told to present all of it and to
    repaint the whole table when the show comes back (its dirty tiles know nothing of it)."""

    def __init__(self, renderer: Any, clock: Callable[[], float]) -> None:
        self.inner, self.clock = renderer, clock
        self.current: tuple[int, Any] | None = None  # (token, pygame surface)
        self.shown: tuple[int, float] | None = None

    def draw(self, target: Any, frame: Any, overlay: Sequence[str] | None = None) -> None:
        current = self.current
        if current is None:
            self.inner.draw(target, frame, overlay)
            return
        target.blit(current[1], (0, 0))
        self.inner.invalidate()
        if self.shown is None or self.shown[0] != current[0]:
            self.shown = (current[0], self.clock())

    def __getattr__(self, name: str) -> Any:
        return getattr(self.inner, name)


class RunProCam:
    """The running view and camera ``source`` as a ProCam (``size``, ``show``, ``grab``).
    ``projector``: a simulated projector that throws what is shown onto a synthetic source's
    table (None for a real camera, which sees the real projector)."""

    def __init__(self, view: Any, source: Any, projector: Any = None,
                 settle_s: float = SETTLE_S, timeout_s: float = 10.0,
                 clock: Callable[[], float] = time.monotonic) -> None:
        self.view, self.source, self.projector = view, source, projector
        # the projector's pixels of the calibration (view.size); a window of another size
        # shows every image scaled to it, as the view draws the show (shown_surface)
        self.size = tuple(getattr(view, "size", None) or view.screen.get_size())
        self.showing = Showing(view.renderer, clock)
        view.renderer = self.showing
        self.measurer = getattr(source, "measurer", None) or source.process
        self.settle_s, self.timeout_s, self.clock = settle_s, timeout_s, clock
        self._token = 0
        self._kept = bool(getattr(self.measurer, "keep_image", False))
        self.closed = threading.Event()  # the run is ending: a grab gives up at once

    def show(self, image: np.ndarray | None) -> None:
        """Show ``image`` (grey or BGR, the view's size; None: black) instead of the show."""
        w, h = self.size
        shown = np.zeros((h, w), np.uint8) if image is None else image
        surface = shown_surface(shown, tuple(self.view.screen.get_size()))
        self.measurer.keep_image = True  # the camera's frames, for the check
        if self.projector is not None:
            self.projector.throw(self.source.camera, image)
        self._token += 1
        self.showing.current = (self._token, surface)

    def grab(self) -> np.ndarray:
        """The first camera frame captured ``settle_s`` after the view showed the image."""
        deadline = self.clock() + self.timeout_s
        while self.clock() < deadline and not self.closed.is_set():
            shown = self.showing.shown
            if shown is not None and shown[0] == self._token:
                obs = self.source.latest()
                if obs is not None and obs.image is not None and obs.t >= shown[1] + self.settle_s:
                    return obs.image
            time.sleep(0.01)
        raise CalibrationInputError(f"the camera delivered no frame of the check's image in "
                                    f"{self.timeout_s:g} s")

    def release(self) -> None:
        """Back to the show."""
        self.showing.current = None
        self.measurer.keep_image = self._kept
        if self.projector is not None:
            self.projector.throw(self.source.camera, None)


def shown_surface(image: np.ndarray, window: tuple[int, int]) -> Any:
    """``image`` (grey or BGR, projector pixels of the calibration) as a surface of the
    window's ``window`` (W, H) pixels: scaled when the window is another size (a fullscreen
    window at the desktop's size, or one shrunk to fit the screen), so a cross lands where
    the view draws that table point."""
    import pygame
    surface = image_surface(image)
    if surface.get_size() != tuple(window):
        surface = pygame.transform.smoothscale(surface, window)
    return surface


class LiveCheck:
    """Sink: the check every ``every_s`` seconds of the run (in a thread: the loop never waits)
    once pucks are tracked; ``lines()`` is the text for the operator overlay
    (:func:`tabletop.procam.check_lines`). ``procam`` None: no live camera (a replay)."""

    name = "calibration-check"

    def __init__(self, procam: Any, calibration: Any, detector: Any,
                 tolerance_mm: float | None = None, every_s: float = CHECK_EVERY_S) -> None:
        from calibration.fits import CHECK_MM
        self.procam, self.calibration, self.detector = procam, calibration, detector
        self.tolerance = CHECK_MM if tolerance_mm is None else tolerance_mm
        self.every_s, self._next_t = every_s, None
        self._lock = threading.Lock()
        self._thread: threading.Thread | None = None
        self.measured = 0  # checks completed
        self._lines = ["calibration check: waiting for the first measurement"]
        if procam is None:
            self._lines = ["calibration check: needs the live camera (not in a replay)"]

    def lines(self) -> list[str]:
        """The newest check as overlay lines (a heading, one per puck, then PASS/FAIL)."""
        with self._lock:
            return list(self._lines)

    def consume(self, frame: Any) -> None:
        if self.procam is None or (self._thread is not None and self._thread.is_alive()):
            return
        if self._next_t is not None and frame.t < self._next_t:
            return
        if not frame.pucks:
            with self._lock:
                self._lines = ["calibration check: no puck tracked yet (put pucks on the "
                               "table, a few near its corners)"]
            return
        self._next_t = frame.t + self.every_s
        self._thread = threading.Thread(target=self._measure, name="calibration-check",
                                        daemon=True)
        self._thread.start()

    def _measure(self) -> None:
        when = time.strftime("%H:%M:%S")
        try:
            result = run_check(self.procam, self.calibration, self.detector)
            lines, _ = check_lines(result, self.tolerance)
            lines = [f"calibration check at {when}:"] + lines
        except CalibrationInputError as exc:
            lines = [f"calibration check at {when}: {exc}"]
        except Exception as exc:  # the running installation never crashes over its check
            log.exception("calibration check failed")
            lines = [f"calibration check at {when} failed: {exc}"]
        finally:
            release = getattr(self.procam, "release", None)
            if release is not None:
                release()
        closed = getattr(self.procam, "closed", None)
        if closed is not None and closed.is_set():
            return  # cut short by the end of the run: the last full check stays shown
        with self._lock:
            self._lines, self.measured = lines, self.measured + 1

    def close(self) -> None:
        closed = getattr(self.procam, "closed", None)
        if closed is not None:
            closed.set()
        if self._thread is not None:
            self._thread.join(timeout=15.0)


def live_check(cfg: dict, view: Any, sources: Sequence[Any]) -> LiveCheck:
    """The check of a run (``view.calibration_check: true``): through the config's first
    camera source among the running ``sources`` and the running ``view``, whose overlay it
    switches on and fills."""
    cal, detector, src = check_inputs(cfg, "config")
    source = next((s for s in sources if getattr(s, "name", None) == src["name"]), None)
    procam = None
    if source is not None:
        projector = None
        if src["kind"] == "synthetic_camera":
            from tracking.rig import ProjectorSettings, SimulatedProjector
            table = (cfg["table"]["width"], cfg["table"]["height"])
            projector = SimulatedProjector(ProjectorSettings(resolution=tuple(cfg["view"]["size"])),
                                           table)
        procam = RunProCam(view, source, projector)
    check = LiveCheck(procam, cal, detector)
    view.notices.append(check.lines)
    view.show_overlay = True
    return check
