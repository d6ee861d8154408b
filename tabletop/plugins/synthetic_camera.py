"""Source ``synthetic_camera``: the scripted visitor seen through a rendered overhead camera.

The pucks of the ``scripted`` source (same options: ``pucks``, ``seed``, ``performers``) are
rendered with real markers by :class:`tracking.synthetic.SyntheticCamera` (perspective, lens
distortion, lighting, blur, motion blur, noise, a visitor's hand now and then) at ``fps``, in the
source's own thread or (``render_process``) in a child process, as a real camera's images cost
the installation nothing (tabletop/plugins/synthetic_render.py); the tracking section's detector
finds the markers and the camera's true calibration (or this entry's ``calibration`` file) maps them
to table metres. So the default installation runs through real images, exactly as a camera would
feed it.
"""

from __future__ import annotations

import math
import time
from typing import TYPE_CHECKING, Any, Callable

import numpy as np

from tabletop.plugins import scripted
from tabletop.plugins.camera import (MarkerMeasurer, make_detector, share_calibration,
                                     tracker_predictions, tracking_dictionary)
from tabletop.registry import BuildContext
from tabletop.schema import Bool, Context, FilePath, ListOf, Number, Optional_, Record, Str
from tabletop.plugins.synthetic_render import (RenderProcessReader, ScriptedHands,
                                               SyntheticReader)
from tracking.camera import CameraSettings as CaptureSettings
from tracking.camera import CameraSource, PhaseLock
from tracking.synthetic import CameraSettings, Occluder, SyntheticCamera, SyntheticFrame

if TYPE_CHECKING:
    from calibration.files import Calibration
    from tabletop.frames import Observation


def _check(options: dict, path: str, ctx: Context) -> None:
    """Each puck once (scripted.check_pucks); a marker printed on its puck: a square of side s
    lies within a disc of diameter d only when d >= s * sqrt(2). Measured on 10 rendered pucks
    of 0.075 m: d / s = 1.25 found 10, 1.21 found 5, 1.17 to 1.0 none (the cut corners), and
    below 1 every render failed ("could not broadcast input array"), for ever."""
    scripted.check_pucks(options, path, ctx)
    s, d = options["marker_size"], options["puck_diameter"]
    if d < s * math.sqrt(2.0):
        raise ctx.error(f"{path}.puck_diameter", f"a {d:g} m puck cannot carry a {s:g} m marker "
                        f"(its corners stick out); give a puck_diameter of at least "
                        f"{math.ceil(s * math.sqrt(2.0) * 1e4) / 1e4:g} m or a smaller "
                        "marker_size")


SCHEMA = Record({
    **scripted.SCHEMA.fields,
    "resolution": ListOf(Number(integer=True, unit="pixels",
                                lo=64, hi=7680), default=[1280, 720], min_len=2,
                         max_len=2, doc="image [width, height] in pixels"),
    "fps": Number(60.0, unit="Hz", lo=1.0, hi=240.0, doc="frames rendered per second"),
    "tilt_deg": Number(12.0, lo=0.0, hi=40.0, doc="camera tilt from straight down, degrees"),
    "height": Number(1.5, unit="metres",
                     lo=0.3, hi=10.0, doc="camera distance from the table centre, metres"),
    "distortion": ListOf(Number(lo=-2.0, hi=2.0), default=[0.0, 0.0, 0.0, 0.0, 0.0], min_len=0,
                         max_len=5, doc="lens distortion k1, k2, p1, p2, k3 (OpenCV)"),
    "blur": Number(0.6, unit="pixels", lo=0.0, hi=5.0, doc="optical blur (Gaussian sigma), pixels"),
    "noise": Number(2.0, lo=0.0, hi=40.0, doc="sensor noise (sigma), grey levels"),
    "exposure_s": Number(0.008, lo=0.0, hi=0.1, doc="shutter time for motion blur, seconds"),
    "lighting": Number(0.25, lo=0.0, hi=0.9, doc="brightness fall-off across the table, 0..1"),
    "dictionary": Optional_(Str(), doc="marker dictionary (default: the tracking section's)"),
    "marker_size": Number(0.05, unit="metres", lo=0.005, hi=0.5, doc="printed marker side, metres"),
    "puck_diameter": Number(0.075, unit="metres", lo=0.005, hi=0.5, doc="puck diameter, metres"),
    "hands": Record({
        "every_s": Number(15.0, lo=0.0, hi=3600.0, unit="seconds",
                          doc="a hand reaches over the table this often (0: never)"),
        "duration_s": Number(1.6, lo=0.1, hi=60.0, doc="how long each reach lasts"),
        "size": Number(0.1, unit="metres", lo=0.02, hi=0.5, doc="palm length, metres"),
    }),
    "occluders": ListOf(Record({
        "x": Number(), "y": Number(), "angle": Number(0.0), "size": Number(0.09, lo=0.01),
    }), default=[], doc="hands lying still on the table (metres, radians)"),
    "calibration": Optional_(FilePath(kind="file"),
                             doc="map with this calibration instead of the camera's true one"),
    "keep_image": Bool(False, doc="attach each rendered frame to the observation"),
    "render_process": Bool(False, doc="render in a child process (as a real camera's images "
                                      "cost the installation's process nothing): the frame "
                                      "loop does not wait for the render's interpreter lock"),
    "sync_to_loop": Bool(True, doc="time each frame to be ready just before a loop tick, as a "
                                   "camera triggered by the loop would (only for a loop that "
                                   "does not tick on the camera's frames itself)"),
}, check=_check)



class SyntheticCameraSource(CameraSource):
    """A :class:`CameraSource` reading rendered frames; ``truth()`` pairs the newest observation
    with the ground truth it was measured from (``poses`` at script time = t - the reader's
    ``t0``)."""

    def __init__(self, name: str, camera: SyntheticCamera, poses: Callable[[float], list],
                 hands: Callable[[float], list[Occluder]], fps: float, measurer: MarkerMeasurer,
                 clock: Callable[[], float] = time.monotonic, sync_to_loop: bool = True,
                 render_process: bool = False) -> None:
        self.camera, self.measurer, self.poses = camera, measurer, poses
        self.reader: SyntheticReader | RenderProcessReader | None = None
        self._truth: tuple[Any, SyntheticFrame] | None = None
        if render_process and clock is not time.monotonic:
            raise ValueError("a render process needs the monotonic clock")

        # The render process starts now: its interpreter loads while the installation starts
        # (if it cannot, opening the camera tries again and says why).
        self._warm: RenderProcessReader | None = None
        if render_process:
            try:
                self._warm = RenderProcessReader(camera.s, poses, hands, fps)
            except OSError:
                pass

        def opener(_settings: CaptureSettings) -> SyntheticReader | RenderProcessReader:
            if render_process:
                reader, self._warm = self._warm, None
                self.reader = reader or RenderProcessReader(camera.s, poses, hands, fps)
                self.reader.t0 = clock()
            else:
                self.reader = SyntheticReader(camera, poses, hands, fps, clock)
            return self.reader

        def process(image: np.ndarray, t: float, n: int) -> Observation:
            obs = measurer(image, t, n)
            self._truth = (obs, self.reader.frame)
            return obs

        def after_publish() -> Observation | None:
            more = measurer.after_publish()
            if more is not None and self._truth is not None:
                self._truth = (more, self._truth[1])
            return more

        process.after_publish = after_publish

        settings = CaptureSettings(device=f"synthetic camera {camera.w}x{camera.h}",
                                   fps=fps, grey=False, stall_s=max(3.0, 10.0 / fps))
        super().__init__(name, settings, process, opener=opener, clock=clock,
                         phase_lock=PhaseLock() if sync_to_loop else None)

    def close(self) -> None:
        super().close()
        if self._warm is not None:   # never opened
            self._warm.release()
            self._warm = None

    def truth(self) -> tuple[Any, SyntheticFrame] | None:
        """(newest observation, the synthetic frame it came from), or None before the first."""
        return self._truth


def camera_settings(options: dict, ctx: BuildContext) -> CameraSettings:
    """The synthetic camera's settings from this entry's options and the config."""
    return CameraSettings(
        resolution=(int(options["resolution"][0]), int(options["resolution"][1])),
        table=ctx.table, dictionary=options["dictionary"] or tracking_dictionary(ctx.config),
        tilt_deg=options["tilt_deg"], height=options["height"],
        distortion=tuple(options["distortion"]), blur_sigma=options["blur"],
        noise_sigma=options["noise"], exposure_s=options["exposure_s"],
        lighting=options["lighting"], marker_size=options["marker_size"],
        puck_diameter=options["puck_diameter"], seed=options["seed"])


def true_calibration(camera: SyntheticCamera) -> Calibration:
    """The rendered camera's exact calibration (intrinsics, distortion, camera -> table)."""
    from calibration.files import Calibration
    return Calibration(camera.image_to_table_homography(), None, camera.K, camera.dist,
                       (camera.w, camera.h), {"intrinsics_px": 0.0, "camera_to_table_m": 0.0},
                       "synthetic")


def build(options: dict, ctx: BuildContext) -> SyntheticCameraSource:
    from calibration.files import load_calibration

    script = scripted.build({k: options[k] for k in ("name", *scripted.SCHEMA.fields)}, ctx)
    try:
        camera = SyntheticCamera(camera_settings(options, ctx))
    except ValueError as exc:  # an unknown dictionary name
        from tabletop.schema import ConfigError
        raise ConfigError(f"sources: {options['name']}: {exc}") from None
    if options["calibration"] is not None:
        calibration = load_calibration(options["calibration"])
        share_calibration(ctx, calibration)
    else:
        calibration = true_calibration(camera)
    fixed = [Occluder(o["x"], o["y"], o["angle"], o["size"]) for o in options["occluders"]]
    h = options["hands"]
    hands = ScriptedHands(fixed, ctx.table, h["every_s"], h["duration_s"], h["size"],
                          options["seed"])

    measurer = MarkerMeasurer(options["name"], make_detector(ctx), calibration, ctx.table,
                              tracker_predictions(ctx), options["keep_image"])
    return SyntheticCameraSource(options["name"], camera, script.poses, hands, options["fps"],
                                 measurer, clock=ctx.shared.get("clock", time.monotonic),
                                 sync_to_loop=options["sync_to_loop"],
                                 render_process=options["render_process"])
