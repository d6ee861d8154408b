"""Region-of-interest marker detection: look for known pucks around their predicted positions,
and search the whole frame periodically with a fast pass so new or returning pucks are found.

The region-of-interest pass crops a box around each predicted marker centre, merges overlapping
boxes, packs the crops side by side into one small mosaic image and runs the detector once on
the mosaic (one call instead of one per crop). The full-frame pass runs every ``full_period``
frames (so a marker appearing anywhere is found within ``full_period`` frames) with fast settings
(a single adaptive-threshold window, contours shorter than half the smallest known marker's
perimeter skipped, optionally OpenCV's ArUco3 mode; on the image halved while the known markers
are large enough, see ``HALVED_FULL_MIN_SIDE_PX``). Both passes refine the
found corners with ``cv2.cornerSubPix`` on the original image.

Between full-frame passes a marker seen in the previous frame is first tracked without detection:
its four corners are extrapolated from its last two sightings, refined with one batched
``cv2.cornerSubPix`` for all such markers, and its identity verified by reading its cells through
the corners' homography (:func:`tracking.markers.verify_markers`). Only markers that fail (moved
too far, covered, replaced, blurred) go to the region-of-interest pass. Units: image pixels.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Mapping

import cv2
import numpy as np

from tracking.crops import Box, boxes_around, dedupe, merge_boxes, pack_boxes
from tracking.markers import (DetectorSettings, detect_markers, detector_parameters,
                              dictionary_by_name, make_detector, marker_centres,
                              marker_side_lengths, refine_corners, track_corners, verify_markers)

# ArUco3's single-threshold search loses the small markers of low-resolution images (every
# marker of a 480x270 frame was missed); below this larger side the full pass runs without it.
ARUCO3_MIN_IMAGE_PX = 1000

# ArUco3 reads a marker only when its side is at least about this many times
# ``min_canonical_side_px``: at 1280x720 (16 markers, six scenes, canonical side 16 px) it found
# 4% of 25 px markers, 73% of 29 px, 97% of 34 px and all of 49 px, where the search without it
# found 99-100% of each. A marker below that size was never seen again (a still puck left
# invisible). So ArUco3 searches only while the known markers are large enough, and with none
# known every other full-frame search goes without it.
ARUCO3_MIN_SIDE_CANONICAL = 2.25

# While every known marker's side is at least this many pixels, the full-frame pass searches
# the image halved (area average) and refines the found corners on the original: at 1280x720
# with 16 pucks (sides 39-45 px) the halved search finds the same markers (15.75 of 16 fully
# visible per frame, as at full size) in 2.6 ms instead of 4.1 ms, refined corners within
# 0.002 px median of the full-size search's; a third of the size lost a quarter of the markers.
# Every puck carries the same printed size, so a new one is as large as the known ones.
HALVED_FULL_MIN_SIDE_PX = 32.0

FAST_FULL = DetectorSettings(corner_refinement="none", threshold_window_px=(13, 13, 10))
ROI = DetectorSettings(corner_refinement="none", threshold_window_px=(13, 13, 10),
                       min_perimeter_rate=0.01)


@dataclass
class _Known:
    centre: np.ndarray
    side: float
    velocity: np.ndarray = field(default_factory=lambda: np.zeros(2))
    frame: int = 0
    corners: np.ndarray | None = None          # (4, 2) last refined corners
    corner_velocity: np.ndarray | None = None  # (4, 2) per frame, from consecutive sightings


class MarkerTracker:
    """Fast marker detection for a video stream: region-of-interest passes around predictions and
    a periodic full-frame pass.

    ``detect(grey, predictions_px)`` returns ids (N,) and refined corners (N, 4, 2) in pixels.
    ``predictions_px`` maps marker id -> predicted centre (x, y) pixels for this frame (for
    example from the puck tracker); without it the detector predicts from its own last two
    detections. ``full_period``: a full-frame pass every that many frames (1: always).
    ``roi_margin_sides``/``roi_margin_px``: a crop reaches half the marker's diagonal plus that
    many marker sides plus pixels (plus half a frame of motion) beyond the predicted centre.
    ``verify``: track markers seen in the previous frame by corner refinement and verification
    of their code before any detection (``last_pass`` is then "verify" when no region-of-interest
    pass was needed). ``defer_full``: while markers are known, a due full-frame pass is put off
    until :meth:`search_pending` (after the frame's result is out).
    """

    def __init__(self, full: DetectorSettings = FAST_FULL, roi: DetectorSettings = ROI,
                 full_period: int = 3, roi_margin_sides: float = 0.25, roi_margin_px: float = 6.0,
                 refine_window_px: int = 5, gap_px: int = 8, forget_frames: int = 30,
                 verify: bool = True, defer_full: bool = False) -> None:
        if full_period < 1:
            raise ValueError(f"MarkerTracker: full_period {full_period!r} must be at least 1 "
                             "(frames between full-frame searches)")
        self.full_detector = make_detector(full)
        self._full_params = detector_parameters(full)
        self._full_base_rate = self._full_rate = float(full.min_perimeter_rate)
        self._aruco3 = bool(full.aruco3)
        self._aruco3_min_side = ARUCO3_MIN_SIDE_CANONICAL * float(full.min_canonical_side_px)
        self._blind_searches = 0  # full-frame searches with no marker known, in a row
        # The halved image's search: the threshold window halved too (its cells are half as
        # wide), no ArUco3 (the halved image is small; see ARUCO3_MIN_IMAGE_PX).
        lo, hi, step = full.threshold_window_px
        self._half_params = detector_parameters(replace(
            full, aruco3=False,
            threshold_window_px=(max(3, lo // 2 | 1), max(3, hi // 2 | 1), max(1, step // 2))))
        self.half_detector = cv2.aruco.ArucoDetector(dictionary_by_name(full.dictionary),
                                                     self._half_params)
        self._half_rate = -1.0
        self.roi_detector = make_detector(roi)
        self._roi_params = detector_parameters(roi)
        self._roi_rate = -1.0
        self.full_period = int(full_period)
        self.roi_margin_sides, self.roi_margin_px = float(roi_margin_sides), float(roi_margin_px)
        self.refine_window_px, self.gap_px = int(refine_window_px), int(gap_px)
        self.forget_frames = int(forget_frames)
        self.verify = bool(verify)
        self.defer_full = bool(defer_full)
        self._pending: tuple[np.ndarray, int] | None = None   # (image, frame) to search later
        self._found_late: set[int] = set()
        self.dictionary = dictionary_by_name(roi.dictionary)
        self.frame = 0
        self.known: dict[int, _Known] = {}
        self.last_pass = "full"

    def reset(self) -> None:
        """Forget every marker and start with a full-frame pass."""
        self.known.clear()
        self.frame = 0
        self._pending = None
        self._found_late.clear()

    def predict(self) -> dict[int, tuple[float, float]]:
        """Own prediction of each recently seen marker's centre for the next frame (pixels)."""
        out = {}
        for mid, k in self.known.items():
            steps = self.frame - k.frame
            if steps <= self.forget_frames:
                c = k.centre + k.velocity * steps
                out[mid] = (float(c[0]), float(c[1]))
        return out

    def detect(self, grey: np.ndarray,
               predictions_px: Mapping[int, tuple[float, float]] | None = None
               ) -> tuple[np.ndarray, np.ndarray]:
        """Detect markers in this frame of the stream: ids (N,), corners (N, 4, 2) pixels."""
        if grey.ndim == 3:
            grey = cv2.cvtColor(grey, cv2.COLOR_BGR2GRAY)
        if self._pending is not None:   # a put-off search nobody ran: run it now
            self.search_pending()
        self.frame += 1
        preds = self.predict() if predictions_px is None else dict(predictions_px)
        if self._found_late:
            # Found by a put-off search, which nobody else has seen yet: where they were just
            # found says more than a caller's prediction of a puck it lost (or never had).
            own = self.predict()
            preds.update({m: own[m] for m in self._found_late if m in own})
            self._found_late.clear()
        full = (self.frame - 1) % self.full_period == 0 or not preds
        if full and self.defer_full and preds:
            self._pending, full = (grey, self.frame), False
        if full:
            ids, corners = self._search_full(grey)
            self.last_pass = "full"
            corners = refine_corners(grey, corners, self.refine_window_px)
        else:
            ids, corners = self._track_known(grey, preds) if self.verify else (
                np.zeros(0, int), np.zeros((0, 4, 2)))
            self.last_pass = "verify"
            found = set(ids.tolist())
            rest = {m: p for m, p in preds.items() if m not in found}
            if rest:
                # A second, halved search of the crops still missing reads blurred markers more
                # often (four pucks at 720p, 12 mm blur: 10-13% -> 14-17% of frames; 9.6 mm: 81-86%
                # -> 88-91%), but pucks seen that sparsely were shown worse (p95 207-243 -> 215-257
                # mm; with sparse sightings as one track, 385 -> 465 mm at reversals): not done.
                # Nor a crop of a fast marker still missed, Wiener-deconvolved along a line blur
                # measured in its cepstrum near the velocity's direction: 12.8 mm blur at 60 Hz
                # read 0.10 -> 0.83, overall p95 188 -> 16 mm, no false ids; but 9 cm circles at
                # 1.5 m/s, 30 Hz (read 0.09 -> 0.12) overall p95 179 -> 221 mm, held out 198 ->
                # 233 (coasting from sparse sightings), and 1.2-1.4 ms CPU per crop.
                ids2, c2 = self._detect_regions(grey, rest)
                self.last_pass = "roi"
                if len(ids2):
                    c2 = refine_corners(grey, c2, self.refine_window_px)
                    ids = np.concatenate([ids, ids2])
                    corners = np.concatenate([corners, c2])
                    if len(found & set(ids2.tolist())):
                        ids, corners = dedupe(ids, corners)
        self._remember(ids, corners)
        return ids, corners

    def search_pending(self) -> tuple[np.ndarray, np.ndarray]:
        """The full-frame pass that ``detect`` put off (``defer_full``), on the image it was due
        for. Returns the markers it found that this frame's quick passes did not (a puck put
        down, one that moved too far): ids (N,), refined corners (N, 4, 2) pixels; they are
        remembered as seen in that frame and followed from the next. Run it once the frame's
        result is out (a camera thread, after publishing): the full search costs the frame no
        latency, and the camera publishes what it adds at once (a new puck shows a full
        search later, not a frame later: measured in the default installation, a puck put
        down was shown 7.1 ms after its frame's capture, median of 11; searched with the next
        frame instead, 20.2 ms)."""
        none = np.zeros(0, int), np.zeros((0, 4, 2))
        if self._pending is None:
            return none
        grey, frame = self._pending
        self._pending = None
        if frame != self.frame:
            return none
        ids, corners = self._search_full(grey)
        new = [i for i, m in enumerate(ids.tolist())
               if m not in self.known or self.known[m].frame != frame]
        if not new:
            return none
        ids, corners = ids[new], refine_corners(grey, corners[new], self.refine_window_px)
        self._remember(ids, corners)
        self._found_late.update(ids.tolist())
        return ids, corners

    def _track_known(self, grey: np.ndarray, preds: Mapping[int, tuple[float, float]]
                     ) -> tuple[np.ndarray, np.ndarray]:
        """Markers of ``preds`` seen last frame, found again by refining their extrapolated
        corners and verifying their code: ids (N,), refined corners (N, 4, 2)."""
        mids, guesses = [], []
        for mid, p in preds.items():
            k = self.known.get(mid)
            if k is None or k.corners is None or k.frame != self.frame - 1:
                continue
            if k.corner_velocity is not None:
                guesses.append(k.corners + k.corner_velocity)
            else:
                guesses.append(k.corners + (np.asarray(p, float) - k.centre))
            mids.append(mid)
        if not mids:
            return np.zeros(0, int), np.zeros((0, 4, 2))
        ids = np.array(mids, int)
        corners, ok = track_corners(grey, np.array(guesses), self.refine_window_px)
        if ok.any():
            ok[ok] = verify_markers(grey, ids[ok], corners[ok], self.dictionary)
        return ids[ok], corners[ok]

    def _half_size(self, mid: int) -> float:
        k = self.known.get(mid)
        if k is not None:
            side = k.side
            speed = float(np.hypot(*k.velocity))
        else:
            sides = [v.side for v in self.known.values()]
            side = float(np.median(sides)) if sides else 40.0
            speed = 0.0
        # Half the marker's diagonal, a quiet zone, and room for half a frame of motion.
        return side * (0.71 + self.roi_margin_sides) + self.roi_margin_px + 0.5 * speed

    def regions(self, shape: tuple[int, ...], predictions_px: Mapping[int, tuple[float, float]]
                ) -> list[Box]:
        """The merged crop boxes for these predictions in an image of ``shape``."""
        if not predictions_px:
            return []
        mids = list(predictions_px)
        centres = np.array([predictions_px[m] for m in mids], float).reshape(-1, 2)
        halves = np.array([self._half_size(m) for m in mids])
        return merge_boxes(boxes_around(centres, halves, shape[1], shape[0]))

    def _detect_regions(self, grey: np.ndarray, preds: Mapping[int, tuple[float, float]]
                        ) -> tuple[np.ndarray, np.ndarray]:
        boxes = self.regions(grey.shape, preds)
        if not boxes:
            return np.zeros(0, int), np.zeros((0, 4, 2))
        places, (mw, mh) = pack_boxes(boxes, self.gap_px)
        mosaic = np.full((mh, mw), 128, np.uint8)
        for (x0, y0, x1, y1), (px, py) in zip(boxes, places):
            mosaic[py:py + y1 - y0, px:px + x1 - x0] = grey[y0:y1, x0:x1]
        self._set_min_perimeter(preds, max(mw, mh))
        ids, corners = detect_markers(mosaic, self.roi_detector)
        if len(ids) == 0:
            return ids, corners
        # Each detection belongs to the crop holding its centre; keep it only if wholly inside
        # that crop (not cut by the crop's edge), and move it back to image pixels.
        b = np.array(boxes, float)
        pl = np.array(places, float)
        size = b[:, 2:] - b[:, :2]
        c = corners.mean(axis=1)
        inside = np.all((c[:, None, :] >= pl[None]) & (c[:, None, :] < pl[None] + size[None]),
                        axis=2)
        has = inside.any(axis=1)
        k = inside.argmax(axis=1)
        local = corners - pl[k][:, None, :]
        ok = (has & np.all(local >= 1.0, axis=(1, 2))
              & np.all(local <= size[k][:, None, :] - 2.0, axis=(1, 2)))
        ids = ids[ok]
        corners = local[ok] + b[k[ok], None, :2]
        if len(np.unique(ids)) < len(ids):
            ids, corners = dedupe(ids, corners)
        return ids, corners

    def _set_min_perimeter(self, preds: Mapping[int, tuple[float, float]], size: int) -> None:
        """Ignore contours shorter than half the smallest expected marker's perimeter: on a small
        mosaic a rate relative to its size would admit every speck of noise (and cost time)."""
        sides = [self.known[m].side for m in preds if m in self.known]
        side = 0.5 * min(sides) if sides else 12.0
        rate = float(np.clip(4.0 * side / max(size, 1), 0.005, 1.0))
        if abs(rate - self._roi_rate) > 0.1 * rate:
            self._roi_params.minMarkerPerimeterRate = rate
            self.roi_detector.setDetectorParameters(self._roi_params)
            self._roi_rate = rate

    def _search_full(self, grey: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The full-frame search before corner refinement: ids (N,), corners (N, 4, 2) pixels of
        ``grey``. On the image halved while every known marker is at least
        ``HALVED_FULL_MIN_SIDE_PX`` on a side, else on ``grey`` itself."""
        sides = [k.side for k in self.known.values()]
        if not sides or min(sides) < HALVED_FULL_MIN_SIDE_PX:
            self._set_full_min_perimeter(grey.shape)
            return detect_markers(grey, self.full_detector)
        h, w = grey.shape[:2]
        small = cv2.resize(grey, (w // 2, h // 2), interpolation=cv2.INTER_AREA)
        # Half the smallest known perimeter, in the halved image: the same rate as at full size.
        rate = max(self._full_base_rate, 2.0 * min(sides) / max(h, w))
        if abs(rate - self._half_rate) > 0.1 * rate:
            self._half_params.minMarkerPerimeterRate = rate
            self.half_detector.setDetectorParameters(self._half_params)
            self._half_rate = rate
        ids, corners = detect_markers(small, self.half_detector)
        # Pixel centres: small pixel i covers full pixels 2i and 2i + 1.
        return ids, (corners + 0.5) * 2.0 - 0.5

    def _set_full_min_perimeter(self, shape: tuple[int, ...]) -> None:
        """While markers are known, the full pass ignores contours shorter than half the
        smallest known marker's perimeter (every puck carries the same printed size; perspective
        changes it far less than twofold), never admitting less than the configured rate; and it
        uses ArUco3 only on images of at least ``ARUCO3_MIN_IMAGE_PX`` on their larger side, while
        the known markers are large enough for it (``ARUCO3_MIN_SIDE_CANONICAL``) or, with none
        known, on every other search (a small marker is found by the next one)."""
        sides = [k.side for k in self.known.values()]
        rate = self._full_base_rate
        if sides:
            rate = max(rate, 4.0 * 0.5 * min(sides) / max(shape[0], shape[1]))
            readable = min(sides) >= self._aruco3_min_side
            self._blind_searches = 0
        else:
            readable = self._blind_searches % 2 == 0
            self._blind_searches += 1
        aruco3 = (self._aruco3 and readable
                  and max(shape[0], shape[1]) >= ARUCO3_MIN_IMAGE_PX)
        if abs(rate - self._full_rate) > 0.1 * rate \
                or aruco3 != self._full_params.useAruco3Detection:
            self._full_params.minMarkerPerimeterRate = rate
            self._full_params.useAruco3Detection = aruco3
            self.full_detector.setDetectorParameters(self._full_params)
            self._full_rate = rate

    def _remember(self, ids: np.ndarray, corners: np.ndarray) -> None:
        if len(ids) == 0:
            self._forget()
            return
        q_all = np.asarray(corners, float).reshape(-1, 4, 2)
        centres = marker_centres(q_all)
        sides = marker_side_lengths(q_all).tolist()
        frame = self.frame
        for i, mid in enumerate(np.asarray(ids).tolist()):
            c, q, s = centres[i], q_all[i], sides[i]
            k = self.known.get(mid)
            if k is None:
                self.known[mid] = _Known(c, s, frame=frame, corners=q)
            elif k.frame == frame:
                # One id in two places this frame: no corner motion to trust until it is single.
                k.corner_velocity = None
            else:
                steps = max(1, frame - k.frame)
                v = (c - k.centre) / steps
                # A duplicate or a jump is not a velocity: keep the old one.
                jump = float(v[0] * v[0] + v[1] * v[1]) >= 4.0 * k.side * k.side
                if not jump:
                    k.velocity = v
                k.corner_velocity = (q - k.corners if steps == 1 and not jump
                                     and k.corners is not None else None)
                k.centre, k.side, k.frame, k.corners = c, s, frame, q
        self._forget()

    def _forget(self) -> None:
        for mid in [m for m, k in self.known.items() if self.frame - k.frame > self.forget_frames]:
            del self.known[mid]
