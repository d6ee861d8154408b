"""A synthetic overhead camera: renders pucks carrying real fiducial markers on a table.

The camera is a pinhole above the table, tilted about its x axis, with optional radial/tangential
lens distortion. Pucks are white discs with an ArUco/AprilTag marker
(``cv2.aruco.generateImageMarker``) on top, rendered by warping only their small texture patches
onto a precomputed background; then a lighting gradient, per-puck motion blur, hand-shaped
occluders, the optics (Gaussian blur and lens distortion, :mod:`tracking.optics`) and sensor noise
are applied. Every frame comes with its ground truth (marker corners and centres in pixels, poses in
table metres, which markers are fully visible).

Units: table metres, radians CCW from +x, image pixels x right / y down. Output images are 8-bit
grey (one channel), as the detector consumes them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Sequence

import cv2
import numpy as np

from tracking.clutter import draw_clutter
from tracking.hands import Occluder, hand_polygons, scripted_hands  # noqa: F401  (re-exported)
from tracking.markers import dictionary_by_name  # noqa: F401  (re-exported)
from tracking.optics import Optics

Pose = tuple[int, float, float, float]  # id, x m, y m, angle rad


@dataclass
class CameraSettings:
    """Synthetic camera options. ``tilt_deg``: tilt of the optical axis from vertical;
    ``height``: camera distance from the table centre along its axis (m); ``distortion``: OpenCV
    (k1, k2, p1, p2, k3); ``blur_sigma``: Gaussian blur in pixels; ``noise_sigma``: grey levels;
    ``exposure_s``: shutter time for motion blur; ``marker_size``: printed marker side including
    its black border (m); ``puck_diameter`` (m); ``margin``: fraction of the image left around the
    table; ``full_frame_optics``: apply blur and distortion to the whole frame instead of only
    where pucks and hands changed it (same image, slower; for checking); ``clutter``: how many
    marker-like prints lie on the table (:mod:`tracking.clutter`)."""

    resolution: tuple[int, int] = (1280, 720)
    table: tuple[float, float] = (1.2, 0.8)
    dictionary: str = "DICT_4X4_50"
    tilt_deg: float = 12.0
    height: float = 1.5
    distortion: tuple[float, ...] = (0.0, 0.0, 0.0, 0.0, 0.0)
    blur_sigma: float = 0.6
    noise_sigma: float = 2.0
    exposure_s: float = 0.008
    lighting: float = 0.25
    marker_size: float = 0.05
    puck_diameter: float = 0.075
    margin: float = 0.04
    seed: int = 0
    full_frame_optics: bool = False  # reference path: blur and distort the whole frame
    clutter: int = 0  # marker-like prints on the table (tracking.clutter); 0: none


@dataclass
class SyntheticFrame:
    """One rendered frame and its ground truth.

    ``ids`` (N,), ``corners`` (N, 4, 2) pixels in OpenCV's corner order, ``centres`` (N, 2)
    pixels (the projected marker centre), ``poses`` (N, 3) table x, y (m) and angle (rad),
    ``visible`` (N,) True when the whole marker is inside the image and not covered.
    """

    image: np.ndarray
    t: float
    ids: np.ndarray
    corners: np.ndarray
    centres: np.ndarray
    poses: np.ndarray
    visible: np.ndarray
    occluders: tuple[Occluder, ...] = field(default=())


def _look_rotation(tilt: float) -> np.ndarray:
    """World->camera rotation: looking down (camera z = -table z), image x along table +x,
    tilted by ``tilt`` rad about the camera x axis (the camera leans toward -y)."""
    down = np.array([[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]])
    c, s = math.cos(tilt), math.sin(tilt)
    rx = np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])
    return rx @ down


class SyntheticCamera:
    """Renders frames of pucks at given poses. Precomputes background, textures and maps once."""

    def __init__(self, settings: CameraSettings | None = None) -> None:
        self.s = s = settings or CameraSettings()
        self.w, self.h = int(s.resolution[0]), int(s.resolution[1])
        self.dictionary = dictionary_by_name(s.dictionary)
        self.dist = np.asarray(list(s.distortion) + [0.0] * (5 - len(s.distortion)), float)[:5]
        self.has_distortion = bool(np.any(self.dist != 0.0))
        self._rng = np.random.default_rng(s.seed)
        self._setup_camera()
        self._setup_background()
        self._setup_textures()
        self._setup_noise()
        self.optics = Optics(self.K, self.dist, (self.w, self.h), s.blur_sigma,
                             s.full_frame_optics)
        self.optics.set_background(self.background)

    # ----------------------------------------------------------------- geometry
    def _setup_camera(self) -> None:
        s = self.s
        tw, th = s.table
        self.R = _look_rotation(math.radians(s.tilt_deg))
        target = np.array([tw / 2.0, th / 2.0, 0.0])
        self.C = target - s.height * self.R[2]  # camera centre: back along its optical axis
        self.tvec = -self.R @ self.C
        self.rvec = cv2.Rodrigues(self.R)[0]
        # Focal length that fits the table (in the pinhole model) with the requested margin.
        corners = np.array([[0, 0, 0], [tw, 0, 0], [tw, th, 0], [0, th, 0]], float)
        pc = (self.R @ corners.T).T + self.tvec
        nx, ny = pc[:, 0] / pc[:, 2], pc[:, 1] / pc[:, 2]
        cx0, cy0 = (nx.max() + nx.min()) / 2.0, (ny.max() + ny.min()) / 2.0
        half_w, half_h = (nx.max() - nx.min()) / 2.0, (ny.max() - ny.min()) / 2.0
        f = min(self.w * (0.5 - s.margin) / half_w, self.h * (0.5 - s.margin) / half_h)
        self.K = np.array([[f, 0.0, self.w / 2.0 - f * cx0],
                           [0.0, f, self.h / 2.0 - f * cy0], [0.0, 0.0, 1.0]])

    def homography(self, z: float = 0.0) -> np.ndarray:
        """Table (x, y) metres on the plane at height ``z`` -> ideal (undistorted) image pixels."""
        m = np.column_stack([self.R[:, 0], self.R[:, 1], self.R[:, 2] * z + self.tvec])
        H = self.K @ m
        return H / H[2, 2]

    def table_to_image_homography(self) -> np.ndarray:
        """Homography from table metres to image pixels (exact when there is no distortion)."""
        return self.homography(0.0)

    def image_to_table_homography(self) -> np.ndarray:
        """Inverse of :meth:`table_to_image_homography` (pixels -> metres)."""
        H = np.linalg.inv(self.homography(0.0))
        return H / H[2, 2]

    def project(self, pts: np.ndarray) -> np.ndarray:
        """Table points (N, 2) metres on the table plane -> image pixels (N, 2), with distortion."""
        p = np.asarray(pts, float).reshape(-1, 2)
        if not self.has_distortion:
            hp = np.column_stack([p, np.ones(len(p))]) @ self.homography().T
            return hp[:, :2] / hp[:, 2:3]
        obj = np.column_stack([p, np.zeros(len(p))])
        img, _ = cv2.projectPoints(obj, self.rvec, self.tvec, self.K, self.dist)
        return img.reshape(-1, 2)

    def pixels_per_metre(self) -> float:
        """Approximate image scale at the table centre (pixels per metre)."""
        c = np.array([[self.s.table[0] / 2, self.s.table[1] / 2]])
        a = self.project(c)
        b = self.project(c + [[0.1, 0.0]])
        return float(np.linalg.norm(b - a) / 0.1)

    # ----------------------------------------------------------------- precomputed images
    def _setup_background(self) -> None:
        s = self.s
        H = self.homography()
        # Floor around the table (dark grey) and the table top (mid grey with a faint grain).
        bg = np.full((self.h, self.w), 60, np.uint8)
        tw, th = s.table
        quad = np.array([[0, 0], [tw, 0], [tw, th], [0, th]], float)
        hp = np.column_stack([quad, np.ones(4)]) @ H.T
        poly = (hp[:, :2] / hp[:, 2:3]).round().astype(np.int32)
        cv2.fillConvexPoly(bg, poly, 150, lineType=cv2.LINE_AA)
        grain = self._rng.normal(0.0, 4.0, (self.h // 8 + 1, self.w // 8 + 1)).astype(np.float32)
        grain = cv2.resize(grain, (self.w, self.h), interpolation=cv2.INTER_CUBIC)
        self.background = np.clip(bg.astype(np.float32) + grain, 0, 255).astype(np.uint8)
        if s.clutter > 0:
            self.background = draw_clutter(self.background, H, s.table, self.dictionary,
                                           s.clutter, s.seed)
        # Lighting: a smooth gain from a lamp off one corner, multiplied into every frame.
        yy, xx = np.mgrid[0:self.h, 0:self.w].astype(np.float32)
        r = np.hypot((xx - 0.2 * self.w) / self.w, (yy - 0.15 * self.h) / self.h)
        gain = 1.0 - s.lighting * np.clip(r / 1.1, 0.0, 1.0)
        self.gain = gain.astype(np.float32)
        self.background = np.clip(self.background * self.gain, 0, 255).astype(np.uint8)
        self.unlit = self.background

    def set_projection(self, light: np.ndarray | None) -> None:
        """Light a projector throws on the table, as float grey levels (H, W) in ideal image
        pixels at full reflectance (None: the projector is off). The table reflects it in
        proportion to its own grey; every later frame shows it under the pucks."""
        if light is None:
            self.background = self.unlit
        else:
            lit = self.unlit * (1.0 + np.asarray(light, np.float32) / 255.0)
            self.background = np.clip(lit, 0, 255).astype(np.uint8)
        self.optics.set_background(self.background)

    def _setup_textures(self) -> None:
        s = self.s
        bits = self.dictionary.markerSize + 2
        cell = 16
        self._marker_px = bits * cell
        pad = int(math.ceil((s.puck_diameter / s.marker_size) * self._marker_px / 2.0
                            - self._marker_px / 2.0)) + 2
        self._tex_size = self._marker_px + 2 * pad
        self._tex_pad = pad
        self._tex_cache: dict[int, np.ndarray] = {}
        # Texture pixel -> marker-local metres (u right, v down, centred on the marker).
        k = s.marker_size / self._marker_px
        off = (self._tex_size - 1) / 2.0  # texel centres at integers: the marker's centre
        self._tex_to_local = np.array([[k, 0.0, -k * off], [0.0, k, -k * off], [0.0, 0.0, 1.0]])

    def _texture(self, marker_id: int) -> np.ndarray:
        """Two-channel texture (grey, alpha) of a puck carrying marker ``marker_id``."""
        tex = self._tex_cache.get(marker_id)
        if tex is not None:
            return tex
        n = self._tex_size
        grey = np.full((n, n), 235, np.uint8)
        marker = cv2.aruco.generateImageMarker(self.dictionary, int(marker_id), self._marker_px)
        p = self._tex_pad
        grey[p:p + self._marker_px, p:p + self._marker_px] = np.where(marker > 127, 235, 20)
        alpha = np.zeros((n, n), np.uint8)
        rad = (self.s.puck_diameter / self.s.marker_size) * self._marker_px / 2.0
        c = int(round((n - 1) / 2.0 * 16))
        cv2.circle(alpha, (c, c), int(rad * 16), 255, -1, cv2.LINE_AA, 4)
        tex = np.dstack([grey, alpha])
        self._tex_cache[marker_id] = tex
        return tex

    def _setup_noise(self) -> None:
        if self.s.noise_sigma <= 0:
            self._noise = None
            return
        # A bank of noise larger than the frame; each frame takes a random offset window.
        n = self._rng.normal(0.0, self.s.noise_sigma, (self.h + 64, self.w + 64))
        noise = np.clip(n, -127, 127).astype(np.int16)
        # Kept as its positive and negative parts: a saturating add of one and subtract of the
        # other equals the clipped signed sum exactly (a pixel's noise is one or the other),
        # in two 8-bit operations 4x faster than one mixed 8/16-bit addition (~2 ms a frame).
        self._noise = (np.clip(noise, 0, None).astype(np.uint8),
                       np.clip(-noise, 0, None).astype(np.uint8))

    # ----------------------------------------------------------------- rendering
    def marker_corners_table(self, x: float, y: float, angle: float) -> np.ndarray:
        """The marker's four corners (4, 2) in table metres, in OpenCV's order (c0 -> c1 along
        ``angle``)."""
        h = self.s.marker_size / 2.0
        local = np.array([[-h, -h], [h, -h], [h, h], [-h, h]])
        return self._local_to_table(x, y, angle) @ np.column_stack([local, np.ones(4)]).T

    @staticmethod
    def _local_to_table(x: float, y: float, angle: float) -> np.ndarray:
        """2x3 affine map marker-local (u right, v down, as printed) -> table metres."""
        c, s = math.cos(angle), math.sin(angle)
        return np.array([[c, s, x], [s, -c, y]])

    def render(self, poses: Sequence[Pose], t: float = 0.0,
               velocities: Sequence[tuple[float, float]] | None = None,
               occluders: Sequence[Occluder] = ()) -> SyntheticFrame:
        """Render pucks at ``poses`` (id, x m, y m, angle rad); ``velocities`` (m/s, per pose)
        drive the motion blur. Returns the image with its ground truth."""
        img = self.background.copy()
        H = self.homography()
        n = len(poses)
        ids = np.array([p[0] for p in poses], dtype=int)
        poses_arr = np.array([p[1:] for p in poses], float).reshape(n, 3)
        corners = np.zeros((n, 4, 2))
        dirty: list[tuple[int, int, int, int]] = []
        for i, (mid, x, y, a) in enumerate(poses):
            A = np.vstack([self._local_to_table(x, y, a), [0.0, 0.0, 1.0]])
            M = H @ A @ self._tex_to_local  # texture px -> ideal image px
            corners[i] = self.project(self.marker_corners_table(x, y, a).T)
            vel = None if velocities is None else velocities[i]
            rect = self._draw_puck(img, self._texture(mid), M, vel, H)
            if rect is not None:
                dirty.append(rect)
        self._last_mask = None
        if occluders:
            rect = self._draw_occluders(img, occluders)
            if rect is not None:
                dirty.append(rect)
        img = self.optics.apply(img, dirty)
        if self._noise is not None:
            ox, oy = self._rng.integers(0, 64, 2)
            up, down = (part[oy:oy + self.h, ox:ox + self.w] for part in self._noise)
            img = cv2.subtract(cv2.add(img, up), down)
        centres = self.project(poses_arr[:, :2]) if n else np.zeros((0, 2))
        visible = self._visibility(corners, occluders) & ~self._covered_by_pucks(poses_arr)
        return SyntheticFrame(img, t, ids, corners, centres, poses_arr, visible, tuple(occluders))

    def _draw_puck(self, img: np.ndarray, tex: np.ndarray, M: np.ndarray,
                   vel: tuple[float, float] | None, H: np.ndarray
                   ) -> tuple[int, int, int, int] | None:
        """Blend one puck into ``img``; returns the rectangle (x0, y0, x1, y1) it touched."""
        n = tex.shape[0]
        quad = np.array([[0, 0, 1], [n, 0, 1], [n, n, 1], [0, n, 1]], float) @ M.T
        quad = quad[:, :2] / quad[:, 2:3]
        # Motion blur follows the puck's travel only; its turn during the shutter is not drawn.
        # With the turn drawn (the mean of 9 renders across the shutter), pucks turning 1-4 times
        # a second at 8 ms are still read on every frame at 30 and 60 Hz (raw heading p95 under
        # 0.6 deg); at 20 ms and 30 Hz, 3 turns a second loses 9 of 180 reads, 4 turns 129.
        blur_px = np.zeros(2)
        if vel is not None and self.s.exposure_s > 0:
            blur_px = (H[:2, :2] @ np.asarray(vel, float)) * self.s.exposure_s  # approx pixels
        lo = np.floor(quad.min(axis=0) - np.abs(blur_px) - 2).astype(int)
        hi = np.ceil(quad.max(axis=0) + np.abs(blur_px) + 2).astype(int)
        lo = np.maximum(lo, 0)
        hi = np.minimum(hi, [self.w, self.h])
        if np.any(hi - lo <= 1):
            return None
        bw, bh = int(hi[0] - lo[0]), int(hi[1] - lo[1])
        T = np.array([[1.0, 0.0, -lo[0]], [0.0, 1.0, -lo[1]], [0.0, 0.0, 1.0]])
        patch = cv2.warpPerspective(tex, T @ M, (bw, bh), flags=cv2.INTER_LINEAR,
                                    borderMode=cv2.BORDER_CONSTANT, borderValue=(0, 0))
        value = patch[..., 0].astype(np.float32)
        alpha = patch[..., 1].astype(np.float32) * (1.0 / 255.0)
        roi = img[lo[1]:hi[1], lo[0]:hi[0]]
        gain = self.gain[lo[1]:hi[1], lo[0]:hi[0]]
        blended = roi.astype(np.float32) + alpha * (value * gain - roi)
        steps = int(math.ceil(float(np.hypot(*blur_px))))
        if steps >= 2:
            k = np.zeros((2 * steps + 1, 2 * steps + 1), np.float32)
            p0 = (steps - blur_px[0] / 2.0, steps - blur_px[1] / 2.0)
            p1 = (steps + blur_px[0] / 2.0, steps + blur_px[1] / 2.0)
            cv2.line(k, (int(round(p0[0] * 16)), int(round(p0[1] * 16))),
                     (int(round(p1[0] * 16)), int(round(p1[1] * 16))), 1.0, 1, cv2.LINE_AA, 4)
            k /= max(float(k.sum()), 1e-6)
            blended = cv2.filter2D(blended, -1, k, borderType=cv2.BORDER_REPLICATE)
        roi[...] = np.clip(blended, 0, 255).astype(np.uint8)
        return int(lo[0]), int(lo[1]), int(hi[0]), int(hi[1])

    def occluder_mask(self, occluders: Sequence[Occluder]) -> np.ndarray:
        """uint8 mask (255 where a hand covers the image), in ideal image pixels."""
        mask = np.zeros((self.h, self.w), np.uint8)
        H = self.homography(0.02)  # hands hover a little above the table
        for o in occluders:
            for poly in hand_polygons(o):
                hp = np.column_stack([poly, np.ones(len(poly))]) @ H.T
                pix = (hp[:, :2] / hp[:, 2:3] * 16).round().astype(np.int32)
                cv2.fillPoly(mask, [pix], 255, cv2.LINE_AA, 4)
        return mask

    def _draw_occluders(self, img: np.ndarray, occluders: Sequence[Occluder]
                        ) -> tuple[int, int, int, int] | None:
        """Darken ``img`` under the hands; returns the rectangle it touched (or None)."""
        mask = self.occluder_mask(occluders)
        self._last_mask = mask
        ys, xs = np.nonzero(mask[::4, ::4])
        if len(xs) == 0:
            return None
        x0, y0 = max(int(xs.min()) * 4 - 4, 0), max(int(ys.min()) * 4 - 4, 0)
        x1, y1 = min(int(xs.max()) * 4 + 8, self.w), min(int(ys.max()) * 4 + 8, self.h)
        roi = img[y0:y1, x0:x1]
        skin = self.gain[y0:y1, x0:x1] * 70.0
        a = mask[y0:y1, x0:x1].astype(np.float32) * (1.0 / 255.0)
        roi[...] = np.clip(roi + a * (skin - roi), 0, 255).astype(np.uint8)
        return x0, y0, x1, y1

    def _covered_by_pucks(self, poses: np.ndarray) -> np.ndarray:
        """(N,) True where a puck drawn later (later in ``poses``) overlaps this one's marker
        (with a quiet zone), as a puck stacked on or pushed against it would."""
        n = len(poses)
        covered = np.zeros(n, bool)
        if n < 2:
            return covered
        reach = self.s.puck_diameter / 2.0 + 1.25 * self.s.marker_size / math.sqrt(2.0)
        d = np.hypot(poses[:, None, 0] - poses[None, :, 0], poses[:, None, 1] - poses[None, :, 1])
        later = np.triu(np.ones((n, n), bool), k=1)
        return np.any((d < reach) & later, axis=1)

    def _visibility(self, corners: np.ndarray, occluders: Sequence[Occluder]) -> np.ndarray:
        n = len(corners)
        inside = np.all((corners[..., 0] >= 2) & (corners[..., 0] <= self.w - 3)
                        & (corners[..., 1] >= 2) & (corners[..., 1] <= self.h - 3), axis=1)
        if not occluders or n == 0:
            return inside
        mask = self._last_mask
        vis = inside.copy()
        for i in np.flatnonzero(inside):
            q = corners[i]
            # The marker plus a quiet zone around it must be clear of the hand.
            centre = q.mean(axis=0)
            grown = centre + (q - centre) * 1.25
            lo = np.maximum(np.floor(grown.min(axis=0)).astype(int) - 1, 0)
            hi = np.minimum(np.ceil(grown.max(axis=0)).astype(int) + 2, [self.w, self.h])
            m = np.zeros((hi[1] - lo[1], hi[0] - lo[0]), np.uint8)
            cv2.fillConvexPoly(m, (grown - lo).round().astype(np.int32), 255)
            if np.any((m > 0) & (mask[lo[1]:hi[1], lo[0]:hi[0]] > 0)):
                vis[i] = False
        return vis

