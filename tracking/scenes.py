"""Scenes for the tracking tests and benchmark: pucks laid out without overlap on the table."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Callable, Iterator, Sequence

import numpy as np

if TYPE_CHECKING:
    from tabletop.frames import Puck
    from tracking.pucks import TrackerSettings
    from tracking.synthetic import SyntheticCamera, SyntheticFrame

#: A puck's pose: (id, x m, y m, heading rad).
PuckPose = tuple[int, float, float, float]


def grid_poses(n: int, table: tuple[float, float] = (1.2, 0.8), seed: int = 0,
               jitter: float = 0.02, first_id: int = 0) -> list[PuckPose]:
    """``n`` pucks (ids first_id..) on a jittered grid over the table, random headings."""
    rng = np.random.default_rng(seed)
    cols = int(math.ceil(math.sqrt(n * table[0] / table[1])))
    rows = int(math.ceil(n / cols))
    out = []
    for k in range(n):
        r, c = divmod(k, cols)
        x = (c + 0.5) / cols * table[0] + rng.uniform(-jitter, jitter)
        y = (r + 0.5) / rows * table[1] + rng.uniform(-jitter, jitter)
        out.append((first_id + k, x, y, float(rng.uniform(-math.pi, math.pi))))
    return out


def moving_scene(n: int, frames: int, fps: float, table: tuple[float, float] = (1.2, 0.8),
                 speed: float = 0.3, seed: int = 0
                 ) -> Iterator[tuple[float, list[PuckPose], list[tuple[float, float]]]]:
    """Yield (t s, poses, velocities m/s) of ``n`` pucks circling around their grid places at
    ``speed`` m/s, ``frames`` frames at ``fps``."""
    base = grid_poses(n, table, seed)
    rng = np.random.default_rng(seed + 1)
    radius = min(table[0], table[1]) / (2.5 * math.ceil(math.sqrt(n)))
    phase = rng.uniform(0, 2 * math.pi, n)
    direction = rng.choice([-1.0, 1.0], n)
    w = speed / radius
    for k in range(frames):
        t = k / fps
        poses, vels = [], []
        for i, (pid, x, y, a) in enumerate(base):
            ph = phase[i] + direction[i] * w * t
            poses.append((pid, x + radius * math.cos(ph), y + radius * math.sin(ph),
                          math.remainder(a + 0.5 * direction[i] * t, math.tau)))
            vels.append((-radius * w * direction[i] * math.sin(ph),
                         radius * w * direction[i] * math.cos(ph)))
        yield t, poses, vels


class CameraPipeline:
    """Synthetic camera frames -> region-of-interest detection -> puck tracker, in table metres
    (the camera's exact homography stands in for a calibration)."""

    def __init__(self, cam: SyntheticCamera, settings: TrackerSettings | None = None,
                 full_period: int = 3) -> None:
        from tracking.pucks import PuckTracker
        from tracking.roi import MarkerTracker
        self.cam = cam
        self.detector = MarkerTracker(full_period=full_period)
        self.tracker = PuckTracker(settings)
        self.H_img_to_table = cam.image_to_table_homography()
        self.H_table_to_img = cam.table_to_image_homography()

    def to_table(self, px: np.ndarray) -> np.ndarray:
        """Image pixels (N, 2) -> table metres (N, 2)."""
        hp = np.column_stack([px, np.ones(len(px))]) @ self.H_img_to_table.T
        return hp[:, :2] / hp[:, 2:3]

    def to_image(self, xy: np.ndarray) -> np.ndarray:
        """Table metres (N, 2) -> image pixels (N, 2)."""
        hp = np.column_stack([xy, np.ones(len(xy))]) @ self.H_table_to_img.T
        return hp[:, :2] / hp[:, 2:3]

    def process(self, frame: SyntheticFrame) -> tuple[Puck, ...]:
        """The pucks (table metres) after one rendered frame."""
        from tracking.markers import marker_measurements
        pred = self.tracker.predict(frame.t)
        pred_px = {}
        if pred:
            ids = list(pred)
            px = self.to_image(np.array([pred[i] for i in ids]))
            pred_px = {i: tuple(p) for i, p in zip(ids, px)}
        ids, corners = self.detector.detect(frame.image, pred_px or None)
        ms = marker_measurements(ids, corners, frame.t, self.to_table)
        return self.tracker.step(ms, frame.t)


def score_detections(frames: Sequence[SyntheticFrame],
                     outputs: Sequence[tuple[np.ndarray, np.ndarray]]
                     ) -> tuple[float, np.ndarray, np.ndarray, int]:
    """How detections ``outputs`` [(ids, corners px), ...] did on rendered ``frames``: the share
    of fully visible markers found, centre errors (px) and heading errors (rad) of those found,
    and the number of ids reported that are not on the table."""
    from tabletop.frames import wrap_angle
    from tracking.markers import marker_poses

    found, visible, errs, heads, false_ids = 0, 0, [], [], 0
    for f, (ids, corners) in zip(frames, outputs):
        false_ids += len(set(ids.tolist()) - set(f.ids.tolist()))
        poses = marker_poses(corners) if len(ids) else np.zeros((0, 3))
        truth = marker_poses(f.corners)
        for i, pid in enumerate(f.ids):
            if not f.visible[i]:
                continue
            visible += 1
            m = np.flatnonzero(ids == pid)
            if len(m):
                found += 1
                errs.append(float(np.hypot(*(poses[m[0], :2] - f.centres[i]))))
                heads.append(abs(wrap_angle(float(poses[m[0], 2] - truth[i, 2]))))
    return found / max(visible, 1), np.array(errs), np.array(heads), false_ids


def wait_for(predicate: Callable[[], object], timeout: float, every_s: float = 0.01) -> bool:
    """Poll ``predicate`` every ``every_s`` seconds until it holds (True) or ``timeout`` seconds
    pass (False): for sources whose threads deliver in their own time."""
    import time

    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if predicate():
            return True
        time.sleep(every_s)
    return False
