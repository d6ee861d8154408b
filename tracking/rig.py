"""A simulated projector-camera rig: the synthetic overhead camera also sees what a projector
throws on the table, through a known camera pose and lens and a known projector pose.

The projector is a pinhole above the table (keystone included): its ``table_to_projector``
homography is exact, so calibration and the morning check can be tested end to end against it.
:func:`render_board_view` renders a printed ChArUco board held in front of the camera at any
pose through the camera's lens, for the lens calibration.

Units: table metres, projector and image pixels (OpenCV's pixel-centre convention), grey levels.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import cv2
import numpy as np

from calibration.transforms import apply_homography, homography_columns, inverse, normalised
from tracking.synthetic import CameraSettings, Pose, SyntheticCamera


@dataclass(frozen=True)
class ProjectorSettings:
    """A projector: ``resolution`` (W, H) pixels; lens centre ``position`` (x, y, z) in table
    metres; it aims at ``target`` (x, y) on the table, rolled by ``roll_deg``; its focal length
    makes the table fill the image with ``margin`` (fraction) to spare; ``brightness``: grey
    levels a white pixel adds, ``black``: the light of a black pixel (fraction of white)."""

    resolution: tuple[int, int] = (1280, 720)
    position: tuple[float, float, float] = (0.66, -0.35, 1.55)
    target: tuple[float, float] = (0.6, 0.4)
    roll_deg: float = 1.5
    margin: float = 0.03
    brightness: float = 170.0
    black: float = 0.04


class SimulatedProjector:
    """A pinhole projector over the table; ``H`` maps table metres to projector pixels."""

    def __init__(self, settings: ProjectorSettings, table: tuple[float, float],
                 offset: tuple[float, float] = (0.0, 0.0)) -> None:
        self.s, self.table = settings, table
        self.w, self.h = settings.resolution
        C = np.array(settings.position, float)
        z = np.array([*settings.target, 0.0]) - C
        z /= np.linalg.norm(z)
        x = np.cross(z, [0.0, 1.0, 0.0])  # image x along table +x, image y down toward -y
        x /= np.linalg.norm(x)
        y = np.cross(z, x)
        roll = math.radians(settings.roll_deg)
        R = np.vstack([math.cos(roll) * x + math.sin(roll) * y,
                       -math.sin(roll) * x + math.cos(roll) * y, z])
        t = -R @ C
        tw, th = table
        pc = np.array([[0, 0, 0], [tw, 0, 0], [tw, th, 0], [0, th, 0]], float) @ R.T + t
        nx, ny = pc[:, 0] / pc[:, 2], pc[:, 1] / pc[:, 2]
        f = min(self.w * (1 - 2 * settings.margin) / (nx.max() - nx.min()),
                self.h * (1 - 2 * settings.margin) / (ny.max() - ny.min()))
        cx = (self.w - 1) / 2.0 - f * (nx.max() + nx.min()) / 2.0
        cy = (self.h - 1) / 2.0 - f * (ny.max() + ny.min()) / 2.0
        K = np.array([[f, 0.0, cx], [0.0, f, cy], [0.0, 0.0, 1.0]])
        shift = np.array([[1.0, 0.0, -offset[0]], [0.0, 1.0, -offset[1]], [0.0, 0.0, 1.0]])
        # A projector bumped by ``offset`` shows everything ``offset`` metres further along.
        self.H = normalised(K @ np.column_stack([R[:, 0], R[:, 1], t]) @ shift)

    def shifted(self, dx: float, dy: float) -> "SimulatedProjector":
        """The same projector knocked sideways: its image lands (dx, dy) metres further on."""
        return SimulatedProjector(self.s, self.table, (dx, dy))

    def table_to_projector(self, points_m: np.ndarray) -> np.ndarray:
        """Table metres (N, 2) -> projector pixels (N, 2), exact."""
        return apply_homography(self.H, points_m)

    def throw(self, camera: SyntheticCamera, image: np.ndarray | None) -> None:
        """Show ``image`` (grey or BGR, this projector's size; None: off) on the table that
        ``camera`` sees: its later frames show the light under the pucks."""
        if image is None:
            camera.set_projection(None)
            return
        grey = image if image.ndim == 2 else cv2.cvtColor(image, cv2.COLOR_BGR2GRAY)
        s = self.s
        level = (s.black + (1.0 - s.black) * grey.astype(np.float32) / 255.0) * s.brightness
        # Ideal camera pixel -> table -> projector pixel: warp the projector image by the inverse.
        M = camera.homography() @ inverse(self.H)
        light = cv2.warpPerspective(level, M, (camera.w, camera.h), flags=cv2.INTER_LINEAR,
                                    borderMode=cv2.BORDER_CONSTANT, borderValue=0.0)
        camera.set_projection(light)


class SimulatedRig:
    """A synthetic camera and a simulated projector over one table: ``show`` an image on the
    projector, ``grab`` what the camera sees (pucks on the lit table)."""

    def __init__(self, camera: CameraSettings | None = None,
                 projector: ProjectorSettings | SimulatedProjector | None = None) -> None:
        self.camera = SyntheticCamera(camera or CameraSettings())
        table = self.camera.s.table
        if not isinstance(projector, SimulatedProjector):
            projector = SimulatedProjector(projector or ProjectorSettings(), table)
        self.projector = projector
        self.pucks: list[Pose] = []
        self._shown: np.ndarray | None = None

    @property
    def size(self) -> tuple[int, int]:
        """The projector's resolution (W, H)."""
        return self.projector.w, self.projector.h

    def show(self, image: np.ndarray | None) -> None:
        """Project ``image`` (grey or BGR, the projector's size); None switches it off."""
        self._shown = image
        self.projector.throw(self.camera, image)

    def grab(self) -> np.ndarray:
        """One camera frame (grey) of ``pucks`` on the table under the projector's light."""
        return self.camera.render(self.pucks).image

    def with_projector(self, projector: SimulatedProjector) -> "SimulatedRig":
        """This rig with another projector (the same camera)."""
        rig = SimulatedRig.__new__(SimulatedRig)
        rig.camera, rig.projector, rig.pucks, rig._shown = self.camera, projector, self.pucks, None
        return rig


# ---------------------------------------------------------------- boards held before the lens
class LensRenderer:
    """Renders a flat printed board held before a known lens (K, dist) at any pose; the
    distorted-to-ideal pixel map is computed once per camera."""

    def __init__(self, K: np.ndarray, dist: np.ndarray, size: tuple[int, int],
                 blur_sigma: float = 0.7, noise_sigma: float = 2.0, seed: int = 0,
                 oversample: int = 2) -> None:
        self.K, self.dist, self.size = np.asarray(K, float), np.asarray(dist, float), size
        self.blur_sigma, self.noise_sigma = blur_sigma, noise_sigma
        self.rng = np.random.default_rng(seed)
        self.n = n = max(1, int(oversample))
        w, h = size
        # Sample points of each sensor pixel (n x n of them, averaged: the pixel's area).
        yy, xx = np.mgrid[0:h * n, 0:w * n].astype(np.float32)
        pts = np.stack([(xx.ravel() + 0.5) / n - 0.5, (yy.ravel() + 0.5) / n - 0.5],
                       axis=1).reshape(-1, 1, 2)
        ideal = cv2.undistortPoints(pts, self.K, self.dist, P=self.K).reshape(-1, 2)
        # Kept as two contiguous float64 columns: a view maps them through its homography
        # without an (N, 2) float64 copy and strided reads (with the pairwise 2x2 mean below,
        # 20 views of 640x480: 1.95 -> 0.77 CPU s; bench/calibration's 400 views identical).
        self.ideal_x = ideal[:, 0].astype(np.float64)
        self.ideal_y = ideal[:, 1].astype(np.float64)

    def view(self, texture: np.ndarray, square_px: float, square_m: float,
             rvec: np.ndarray, tvec: np.ndarray) -> np.ndarray:
        """A camera image (grey, H x W) of a flat board printed from ``texture`` (``square_px``
        texture pixels per ``square_m`` metre square; OpenCV's board frame: origin at the
        texture's top-left edge, x right, y down), at pose (rvec, tvec)."""
        w, h = self.size
        k = square_m / square_px
        S = np.array([[k, 0.0, 0.5 * k], [0.0, k, 0.5 * k], [0.0, 0.0, 1.0]])  # texel -> m
        R = cv2.Rodrigues(np.asarray(rvec, float))[0]
        H = self.K @ np.column_stack([R[:, 0], R[:, 1], np.asarray(tvec, float).ravel()]) @ S
        n = self.n
        map_x, map_y = (m.astype(np.float32)
                        for m in homography_columns(np.linalg.inv(H), self.ideal_x, self.ideal_y))
        paper = texture.astype(np.float32) * (200.0 / 255.0) + 30.0
        img = cv2.remap(paper, map_x.reshape(h * n, w * n), map_y.reshape(h * n, w * n),
                        cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT, borderValue=90.0)
        if n > 1:
            img = pixel_means(img, n)
        if self.blur_sigma > 0:
            img = cv2.GaussianBlur(img, (0, 0), self.blur_sigma)
        if self.noise_sigma > 0:
            img = img + self.rng.normal(0.0, self.noise_sigma, img.shape).astype(np.float32)
        return np.clip(img, 0, 255).astype(np.uint8)

def pixel_means(samples: np.ndarray, n: int) -> np.ndarray:
    """Each pixel's mean of its ``n`` x ``n`` samples (float32, (H n, W n) -> (H, W))."""
    h, w = samples.shape[0] // n, samples.shape[1] // n
    if n == 2:
        # Summed pairwise, as numpy's mean sums them: the same values to the bit, 6x faster
        # than the mean over two axes (0.28 -> 0.04 CPU s for 20 views of 640x480).
        s = samples.reshape(h, 2, w, 2)
        return ((s[:, 0, :, 0] + s[:, 0, :, 1]) + (s[:, 1, :, 0] + s[:, 1, :, 1])) / 4
    return samples.reshape(h, n, w, n).mean(axis=(1, 3))


def board_poses(K: np.ndarray, size: tuple[int, int], board_m: tuple[float, float], n: int,
                seed: int = 0, dist: Sequence[float] | None = None
                ) -> list[tuple[np.ndarray, np.ndarray]]:
    """``n`` board poses (rvec, tvec) a technician following the README takes: cycling over the
    image's centre, its four corners and its four edges; each tilted 25-40 degrees about another
    direction; the board filling 45-65 % of the image's width. For a corner or an edge the
    board is pushed out until its outline touches the image's border there (within 3 % of the
    board's width either way, seen through the lens ``dist``), and squared up with the image's
    edges in a corner: the corners and edges are where the lens bends most."""
    rng = np.random.default_rng(seed)
    w, h = size
    spots = [(0.5, 0.5), (0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0),
             (0.5, 0.0), (1.0, 0.5), (0.5, 1.0), (0.0, 0.5)]
    f = float(K[0, 0])
    d = np.zeros(5) if dist is None else np.asarray(dist, float)
    bw, bh = board_m
    outline = np.array([[0, 0, 0], [bw, 0, 0], [bw, bh, 0], [0, bh, 0]], float)
    out = []
    for i in range(n):
        u, v = spots[i % len(spots)]
        corner = u != 0.5 and v != 0.5
        fill = rng.uniform(0.45, 0.65)
        depth = f * bw / (fill * w)
        # Tilted 25-40 degrees, each view about another axis (tilt is what fixes the principal
        # point and the tangential distortion, which a flat board leaves free).
        tilt, axis = rng.uniform(0.44, 0.7), rng.uniform(0.0, 2 * math.pi)
        ax, ay = tilt * math.cos(axis), tilt * math.sin(axis)
        # Squared up to the image's edges in a corner (a turned board leaves the corner empty).
        rz = rng.uniform(-0.3, 0.3) * (0.2 if corner else 1.0)
        R = cv2.Rodrigues(np.array([ax, ay, 0.0]))[0] @ cv2.Rodrigues(np.array([0, 0, rz]))[0]
        rvec = cv2.Rodrigues(R)[0].ravel()
        start = (np.array([0.5, 0.5]) + 0.7 * (np.array([u, v]) - 0.5)) * (w, h)
        ray = np.linalg.inv(K) @ np.array([start[0], start[1], 1.0])
        tvec = ray / ray[2] * depth - R @ np.array([bw / 2, bh / 2, 0.0])
        over = rng.uniform(-0.03, 0.03, 2) * fill * w  # > 0: the outline beyond the border
        for _ in range(6):  # slide the board parallel to the image until it touches the border
            px = cv2.projectPoints(outline, rvec, tvec, K, d)[0].reshape(-1, 2)
            shift = np.zeros(2)
            for axis, (pos, extent) in enumerate(((u, w), (v, h))):
                if pos == 0.0:
                    shift[axis] = -over[axis] - px[:, axis].min()
                elif pos == 1.0:
                    shift[axis] = (extent - 1 + over[axis]) - px[:, axis].max()
            if np.abs(shift).max() < 0.5:
                break
            tvec = tvec + np.array([shift[0], shift[1], 0.0]) * tvec[2] / f
        out.append((rvec, tvec))
    return out


def lens_camera(size: tuple[int, int] = (640, 480), fov_deg: float = 60.0,
                distortion: Sequence[float] = (-0.22, 0.07, 0.0008, -0.0006, 0.0),
                ) -> tuple[np.ndarray, np.ndarray]:
    """A known camera (K, distortion) for lens-calibration tests: ``fov_deg`` across, the
    principal point a little off centre, as real sensors have."""
    w, h = size
    f = (w / 2.0) / math.tan(math.radians(fov_deg) / 2.0)
    K = np.array([[f, 0.0, w / 2.0 + 0.013 * w], [0.0, f * 1.002, h / 2.0 - 0.011 * h],
                  [0.0, 0.0, 1.0]])
    return K, np.asarray(distortion, float)


def marker_layout(table: tuple[float, float], n_x: int = 4, n_y: int = 3,
                  inset: float = 0.08) -> list[Pose]:
    """Markers lying flat on the table for the table fit: ids 0.. on an ``n_x`` x ``n_y`` grid
    ``inset`` metres in from the edges (a fixed pose list; the angle varies so no two look
    alike)."""
    xs = np.linspace(inset, table[0] - inset, n_x)
    ys = np.linspace(inset, table[1] - inset, n_y)
    return [(i, float(x), float(y), 0.3 * i) for i, (y, x) in
            enumerate((y, x) for y in ys for x in xs)]
