"""The ``tracking:`` config section: marker detector and puck tracker options, and their builders.

``build_tracker(options, ctx)`` returns the :class:`tracking.pucks.PuckTracker` the loop fuses
every source's observations with (table metres); ``build_detector(options)`` returns the
:class:`tracking.roi.MarkerTracker` a camera source detects markers with (region-of-interest
passes around the tracker's predictions plus a periodic full-frame pass). Both accept a partial
section (missing keys take their defaults).
"""

from __future__ import annotations

import logging
from pathlib import Path
from typing import TYPE_CHECKING, Any, Iterable, Mapping, Sequence

import dataclasses

from tabletop.frames import Observation, Puck
from tabletop.registry import BuildContext
from tabletop.schema import Bool, Context, ListOf, MapOf, Number, Record, Str, shown
from tracking.pucks import PuckTracker, TrackerSettings

if TYPE_CHECKING:
    from tracking.roi import MarkerTracker

log = logging.getLogger("tabletop")


class DictionaryName(Str):
    """An OpenCV predefined marker dictionary name (``DICT_4X4_50``, ``DICT_APRILTAG_36h11``...)."""

    def describe(self) -> str:
        return "an OpenCV dictionary name such as DICT_4X4_50 or DICT_APRILTAG_36h11"

    def validate(self, value: Any, path: str, ctx: Context) -> Any:
        value = super().validate(value, path, ctx)
        # The default is one of OpenCV's (tests/tracking/test_tracking_plugin.py): every build
        # validates the section again, defaults filled in, and a run without a camera imported
        # OpenCV for this check alone (0.06 of the 1.5 CPU s of its start)
        if value == self.default:
            return value
        import cv2  # only when a config names another dictionary
        if not (value.startswith("DICT_") and isinstance(getattr(cv2.aruco, value, None), int)):
            raise ctx.error(path, f"expected {self.describe()}, got {shown(value)}")
        return value


def _check_puck_ids(section: dict, path: str, ctx: Context) -> None:
    for key in section["puck_ids"]:
        if not key.isdigit():
            raise ctx.error(f"{path}.puck_ids.{key}" if path else f"puck_ids.{key}",
                            "expected a marker id (a whole number) as the key")


SCHEMA = Record({
    # Markers
    "dictionary": DictionaryName("DICT_4X4_50", doc="marker dictionary printed on the pucks"),
    "marker_size": Number(0.05, unit="metres", lo=0.005, hi=1.0,
                          doc="printed marker side including its black border, metres"),
    "puck_ids": MapOf(Number(integer=True, lo=0, hi=1_000_000), default={},
                      doc="marker id -> puck id, for pucks whose marker id differs from the id "
                          "the engines use (e.g. a replaced puck); others keep their marker id"),
    "pucks": ListOf(Number(integer=True, lo=0, hi=1_000_000), default=[],
                    doc="the puck ids on the table (after puck_ids): a reading of any other id "
                        "(a print, a stray marker) is no puck and not shown; [] = every id read"),
    "error_correction_rate": Number(0.6, lo=0.0, hi=1.0,
                                    doc="share of the dictionary's bit correction used; lower "
                                        "admits fewer false ids"),
    "valid_bit_id_threshold": Number(0.49, lo=0.0, hi=1.0,
                                     doc="OpenCV validBitIdThreshold (false-positive guard)"),
    "threshold_window_px": Number(13, integer=True, lo=3, hi=99,
                                  doc="adaptive threshold window, pixels (about a marker cell "
                                      "or two)"),
    "refine_window_px": Number(5, integer=True, lo=2, hi=20,
                               doc="sub-pixel corner refinement half window, pixels"),
    "aruco3": Bool(True, doc="use OpenCV's ArUco3 mode for the full-frame pass (corners are "
                             "refined on the full image afterwards)"),
    # 0.003: a fresh tracker on a 1280x720 camera tilted 14 degrees (tabletop/calibration_scenes.py
    # table_rig, seeds 3-8) finds every 37-44 px marker in its first frame; at 0.005 the far
    # corner's 37 px marker was missed by every first full-frame pass (found once other markers were
    # known), so a puck put down alone there went unseen. It costs the first full-frame pass about
    # 9% at 720p (1.82 -> 1.99 ms median, interleaved); bench/tracking.py on a quiet machine, two
    # runs each, is unchanged: 720p 16 pucks 1.27-1.28 ms (ratio to plain 0.285-0.287) at 0.005,
    # 1.28-1.30 ms (0.286-0.289) at 0.003 (budget 0.3), detection identical.
    "aruco3_min_length_ratio": Number(0.003, lo=0.0, hi=0.5,
                                      doc="ArUco3: smallest marker side / image's larger side"),
    "aruco3_min_side_px": Number(16, integer=True, lo=8, hi=128,
                                 doc="ArUco3: marker side in the downscaled search image"),
    "full_frame_period": Number(4, integer=True, lo=1, hi=30,
                                doc="a full-frame search every N frames: a puck entering or "
                                    "reappearing anywhere is found within N frames"),
    "defer_full_frame": Bool(True, doc="while pucks are followed, a camera runs the due "
                                       "full-frame search after publishing the frame's "
                                       "result (no latency) and publishes the pucks it adds "
                                       "at once"),
    "roi_margin_sides": Number(0.25, lo=0.0, hi=10.0,
                               doc="region-of-interest crop margin beyond the marker, in sides"),
    "roi_margin_px": Number(6.0, lo=0.0, hi=500.0, doc="and in pixels"),
    "verify_known": Bool(True, doc="between full-frame searches, follow a marker seen in the "
                                   "previous frame by refining its corners and checking its "
                                   "code, detecting only the markers that fail"),
    # Jitter filter (One Euro), in table units
    "smooth": Bool(True, doc="apply the One Euro filter to the poses engines use"),
    "min_cutoff": Number(0.2, unit="Hz", lo=0.001, hi=100.0, doc="One Euro minimum cutoff, Hz"),
    "beta": Number(40.0, lo=0.0, hi=10000.0, doc="One Euro speed coefficient, Hz per m/s"),
    "d_cutoff": Number(0.5, unit="Hz",
                       lo=0.001, hi=100.0, doc="One Euro speed low-pass cutoff, Hz"),
    "angle_min_cutoff": Number(0.3, unit="Hz",
                               lo=0.001, hi=100.0, doc="heading: minimum cutoff, Hz"),
    # 4-8 cut the turning lag (median 2.4-4.2 -> 0.9-2.2 deg) but raise a slowly turning puck's
    # heading jitter 31-77% (figures at tracking.pucks.TrackerSettings.angle_beta)
    "angle_beta": Number(2.0, lo=0.0, hi=10000.0, doc="heading: Hz per rad/s"),
    # Occlusion and outliers
    "coast_s": Number(0.5, lo=0.0, hi=60.0,
                      doc="a lost puck is predicted ('coasting') this long, then dropped"),
    "coast_decay_s": Number(0.3, lo=0.01, hi=60.0,
                            doc="time constant of a coasting puck's fading velocity"),
    "reacquire_step_m": Number(0.01, lo=0.0001, hi=1.0,
                               doc="most the smoothed pose moves per frame toward a puck "
                                   "that reappears, until read again where it lies, metres"),
    "reacquire_step_rad": Number(0.2, lo=0.001, hi=3.2, doc="and its heading, radians"),
    "gate_m": Number(0.06, lo=0.001, hi=10.0,
                     doc="a reading farther than this (plus max_speed times the time since "
                         "the puck was seen) from its prediction is an outlier"),
    "max_speed": Number(3.0, unit="metres per second",
                        lo=0.0, hi=100.0, doc="fastest plausible puck, m/s"),
    "confirm_frames": Number(2, integer=True, lo=1, hi=100,
                             doc="consecutive far readings at one place that move the puck"),
    "velocity_cutoff_hz": Number(5.0, lo=0.01, hi=1000.0,
                                 doc="low-pass of the velocity estimates, Hz"),
    "stale_s": Number(0.25, lo=0.001, hi=60.0,
                      doc="a puck whose source sent nothing for this long is coasting"),
}, check=_check_puck_ids)

def complete(options: Mapping[str, Any] | None) -> dict[str, Any]:
    """The section with every missing key at its default (keys ``kind``/``name`` ignored)."""
    given = {k: v for k, v in dict(options or {}).items() if k not in ("kind", "name")}
    return SCHEMA.validate(given, "tracking", Context("<tracking defaults>", Path(".")))


def tracker_settings(options: Mapping[str, Any] | None, units_per_metre: float = 1.0,
                     smooth: bool | None = None) -> TrackerSettings:
    """:class:`TrackerSettings` from the section (``units_per_metre`` != 1 for pixels)."""
    o = complete(options)
    return TrackerSettings(
        min_cutoff=o["min_cutoff"], beta=o["beta"], d_cutoff=o["d_cutoff"],
        angle_min_cutoff=o["angle_min_cutoff"], angle_beta=o["angle_beta"],
        smooth=o["smooth"] if smooth is None else smooth, coast_s=o["coast_s"],
        coast_decay_s=o["coast_decay_s"], reacquire_step_m=o["reacquire_step_m"],
        reacquire_step_rad=o["reacquire_step_rad"], gate_m=o["gate_m"],
        max_speed=o["max_speed"], confirm_frames=o["confirm_frames"],
        velocity_cutoff_hz=o["velocity_cutoff_hz"], stale_s=o["stale_s"],
        units_per_metre=units_per_metre, pucks=tuple(sorted(set(o["pucks"]))))


def puck_id_map(options: Mapping[str, Any] | None) -> dict[int, int]:
    """The section's ``puck_ids`` as marker id -> puck id."""
    return {int(k): int(v) for k, v in complete(options)["puck_ids"].items()}


class Tracker(PuckTracker):
    """The loop's puck tracker. Marker ids become puck ids through ``id_map`` (marker -> puck);
    ``predictions(t)`` gives the expected table position (metres) at time t of every tracked
    marker, keyed by marker id, for a camera's region-of-interest search."""

    def __init__(self, settings: TrackerSettings | None = None,
                 id_map: Mapping[int, int] | None = None) -> None:
        super().__init__(settings)
        self.id_map = dict(id_map or {})
        self._marker_of = {p: m for m, p in self.id_map.items()}
        self._shared_said: set[int] = set()   # pucks named as seen through several markers

    def update(self, observations: Sequence[Observation], t: float) -> tuple[Puck, ...]:
        if self.id_map:
            observations = [self._renamed(o) for o in observations]
        return super().update(observations, t)

    def _renamed(self, obs: Observation) -> Observation:
        if not any(m.id in self.id_map for m in obs.pucks) and not any(
                r in self.id_map for r in obs.removed):
            return obs
        pucks = tuple(dataclasses.replace(m, id=self.id_map.get(m.id, m.id)) for m in obs.pucks)
        if len({m.id for m in pucks}) < len(pucks):
            self._say_shared(obs)
        removed = tuple(self.id_map.get(r, r) for r in obs.removed)
        return dataclasses.replace(obs, pucks=pucks, removed=removed)

    def _say_shared(self, obs: Observation) -> None:
        """Name, once per puck, markers of different ids seen at once as one puck (``puck_ids``
        onto the id of a marker also on the table, or two markers onto one puck): the tracker
        keeps one sighting and the other puck is silently gone from the table."""
        markers: dict[int, set[int]] = {}
        for m in obs.pucks:
            markers.setdefault(self.id_map.get(m.id, m.id), set()).add(m.id)
        for pid, ids in sorted(markers.items()):
            if len(ids) > 1 and pid not in self._shared_said:
                self._shared_said.add(pid)
                *first, last = sorted(ids)
                log.warning("%s: markers %s and %d are each taken for puck %d (tracking.puck_ids); "
                            "the tracker follows one of them: give each marker on the table its "
                            "own puck", obs.source, ", ".join(map(str, first)), last, pid)

    def predictions(self, t: float) -> dict[int, tuple[float, float]]:
        return {self._marker_of.get(pid, pid): xy for pid, xy in self.predict(t).items()}


def build_tracker(options: Mapping[str, Any], ctx: BuildContext | None = None,
                  also: Iterable[int] = ()) -> Tracker:
    """The puck tracker for the section ``options`` (table metres); ids ``also`` (the studio's
    control markers) are kept when ``pucks`` names the pucks."""
    settings = tracker_settings(options)
    if settings.pucks:
        settings = dataclasses.replace(settings, pucks=tuple(sorted({*settings.pucks, *also})))
    return Tracker(settings, puck_id_map(options))


def build_detector(options: Mapping[str, Any] | None = None) -> MarkerTracker:
    """A region-of-interest marker detector (:class:`tracking.roi.MarkerTracker`) for one camera:
    ``detect(grey, predictions_px) -> (ids (N,), corners (N, 4, 2) pixels)``."""
    from tracking.markers import DetectorSettings
    from tracking.roi import MarkerTracker
    o = complete(options)
    win = o["threshold_window_px"]
    common = dict(dictionary=o["dictionary"], corner_refinement="none",
                  error_correction_rate=o["error_correction_rate"],
                  valid_bit_id_threshold=o["valid_bit_id_threshold"],
                  threshold_window_px=(win, win, 10))
    full = DetectorSettings(**common, aruco3=o["aruco3"],
                            min_length_ratio=o["aruco3_min_length_ratio"],
                            min_canonical_side_px=o["aruco3_min_side_px"])
    roi = DetectorSettings(**common, min_perimeter_rate=0.01)
    return MarkerTracker(full, roi, full_period=o["full_frame_period"],
                         roi_margin_sides=o["roi_margin_sides"], roi_margin_px=o["roi_margin_px"],
                         refine_window_px=o["refine_window_px"], verify=o["verify_known"],
                         defer_full=o["defer_full_frame"])
