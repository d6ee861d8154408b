"""What a visitor sees of a tracked puck: the shown pose against the truth, on rendered frames.

The synthetic camera (1280x720, blur, noise) and the installation's own detector and tracker
(``tracking`` defaults), at 30 and 60 Hz. Sections (``--sections=``):

- ``returns``: a puck lifted for 0.3 s and put back 0.14 m away (still), or hidden by a hand
  while it circles at 0.5 m/s; after the return it is read on every frame, or every other frame
  (the other frames drawn without it). Figures: the shown pose's error over the 12 frames after
  the puck is read again (mean, last, mm), updates until it is within 10 mm, and its largest
  move in one frame before that (mm).
- ``turns``: four pucks turning in place at 0.05-4 turns a second, and four still pucks, for
  each ``angle_beta`` of ``--angle-betas``: the shown heading's lag behind the truth (median, p95,
  degrees), a still puck's heading SD and a slowly turning one's heading jitter (SD of the
  second difference of the error, degrees).
- ``clutter``: pucks circling while scripted hands reach over the table: readings of ids not on
  the table or more than 20 mm from their puck (false sightings), and the shown pose's error.

Every error figure stands beside ``gone_frames`` (frames where a puck on the table is not shown
at all) and ``within_20mm_share`` (shown within 20 mm, a gone frame counting as not within), so
a tracker that drops a puck cannot score better than one that shows it. Units: mm, degrees.
"""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path
from typing import Callable, Iterator

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from bench.common import check_flags, emit  # noqa: E402
from tabletop.frames import wrap_angle  # noqa: E402
from tabletop.plugins import tracking as plugin  # noqa: E402
from tracking.hands import Occluder, scripted_hands  # noqa: E402
from tracking.markers import marker_measurements  # noqa: E402
from tracking.pucks import PuckTracker  # noqa: E402
from tracking.synthetic import CameraSettings, SyntheticCamera  # noqa: E402

SECTIONS = ("returns", "turns", "clutter")
RATES = (60.0, 30.0)
PRINTS = 24   # marker-like prints on the table in the clutter section's second half
Scene = Iterator[tuple[float, list, list, tuple]]  # t, poses, velocities, occluders


class Camera:
    """Rendered frames -> the installation's detector -> table-metre measurements."""

    def __init__(self, seed: int, exposure_s: float = 0.004, prints: int = 0) -> None:
        self.cam = SyntheticCamera(CameraSettings(blur_sigma=0.8, noise_sigma=3.0, seed=seed,
                                                  exposure_s=exposure_s, clutter=prints))
        self.det = plugin.build_detector({})
        self.hi = self.cam.image_to_table_homography()
        self.ht = self.cam.table_to_image_homography()

    def _map(self, h: np.ndarray, pts: np.ndarray) -> np.ndarray:
        hp = np.column_stack([pts, np.ones(len(pts))]) @ h.T
        return hp[:, :2] / hp[:, 2:3]

    def read(self, frame, pred: dict[int, tuple[float, float]]) -> tuple:
        """Measurements of one rendered frame, searched around the predictions (table m)."""
        pp = None
        if pred:
            ids = list(pred)
            px = self._map(self.ht, np.array([pred[i] for i in ids]))
            pp = {i: tuple(p) for i, p in zip(ids, px)}
        ids, corners = self.det.detect(frame.image, pp)
        i2, c2 = self.det.search_pending()
        if len(i2):
            ids, corners = np.concatenate([ids, i2]), np.concatenate([corners, c2])
        return marker_measurements(ids, corners, frame.t, lambda p: self._map(self.hi, p))


def _shown(errors: list[float], gone: int) -> dict[str, float]:
    e = np.array(errors) if errors else np.array([np.nan])
    n = len(errors) + gone
    return {"error_median_mm": float(np.median(e)), "error_p95_mm": float(np.percentile(e, 95)),
            "gone_frames": gone, "within_20mm_share": float(np.sum(e <= 20.0)) / max(n, 1)}


# ------------------------------------------------------------------------------- returns
def _return_scene(fps: float, moving: bool, sparse: bool) -> Scene:
    """Puck 1 of four: lifted (or under a hand) from 0.4 to 0.7 s; read every frame after, or
    only every other frame (drawn without it on the others)."""
    base = [(k + 1, 0.15 + 0.3 * k, 0.4, 0.3 * k) for k in range(4)]
    for f in range(int(1.4 * fps)):
        t = f / fps
        poses, vels, occ = [], [], ()
        for pid, x, y, a in base:
            vx = vy = 0.0
            if pid == 1 and moving:   # circling at 0.5 m/s, radius 0.09 m
                w = 0.5 / 0.09
                x, y = x + 0.09 * math.cos(w * t), y + 0.09 * math.sin(w * t)
                vx, vy = -0.5 * math.sin(w * t), 0.5 * math.cos(w * t)
                if 0.4 <= t < 0.7:
                    occ = (Occluder(x + 0.02, y + 0.01, 0.3),)
            elif pid == 1 and t >= 0.7:
                y += 0.14                 # put back 0.14 m away
            hidden = pid == 1 and not moving and 0.4 <= t < 0.7
            skipped = pid == 1 and sparse and t >= 0.7 and f % 2 == 1
            if not (hidden or skipped):
                poses.append((pid, x, y, a))
                vels.append((vx, vy))
        yield t, poses, vels, occ


def _run_return(fps: float, moving: bool, sparse: bool, seed: int) -> dict[str, float]:
    cam, trk = Camera(seed), PuckTracker(plugin.tracker_settings({}))
    after: list[tuple[float, float]] = []   # (error mm, move mm) of puck 1 once read again
    prev, back, errors, gone = None, None, [], 0
    for t, poses, vels, occ in _return_scene(fps, moving, sparse):
        fr = cam.cam.render(poses, t, vels, occ)
        pucks = {p.id: p for p in trk.step(cam.read(fr, trk.predict(t)), t)}
        truth = {pid: (x, y) for pid, x, y, _ in poses}
        for pid, (x, y) in truth.items():
            if pid in pucks:
                errors.append(1000 * math.hypot(pucks[pid].x - x, pucks[pid].y - y))
            elif t > 0.2:
                gone += 1
        p = pucks.get(1)
        if back is None and t >= 0.7 and p is not None and p.state == "seen":
            back = t
        if back is not None and p is not None and 1 in truth:
            move = 0.0 if prev is None else 1000 * math.hypot(p.x - prev[0], p.y - prev[1])
            after.append((1000 * math.hypot(p.x - truth[1][0], p.y - truth[1][1]), move))
        prev = (p.x, p.y) if p is not None else prev
    first = after[:12]
    settle = next((k for k, (e, _) in enumerate(after) if e <= 10.0), len(after))
    return {"after_return_error_mean_mm": float(np.mean([e for e, _ in first])),
            "after_return_error_last_mm": first[-1][0],
            "reads_until_within_10mm": settle,
            "largest_move_before_within_10mm_mm": max([m for _, m in after[1:settle + 1]] or [0]),
            **_shown(errors, gone)}


def returns(seeds: list[int]) -> dict[str, object]:
    out: dict[str, object] = {}
    for fps in RATES:
        for moving in (False, True):
            for sparse in (False, True):
                runs = [_run_return(fps, moving, sparse, s) for s in seeds]
                key = (f"{int(fps)}hz_{'hand_0.5mps' if moving else 'lifted_0.14m'}_"
                       f"{'every_other_frame' if sparse else 'every_frame'}")
                out[key] = {k: float(np.mean([r[k] for r in runs])) for k in runs[0]}
    return out


# ------------------------------------------------------------------------------- turns
def _turn_scene(fps: float, seconds: float, turns_per_s: list[float]) -> Scene:
    base = [(k + 1, 0.15 + 0.3 * (k % 4), 0.25 + 0.3 * (k // 4), 0.4 * k)
            for k in range(len(turns_per_s))]
    for f in range(int(seconds * fps)):
        t = f / fps
        poses = [(pid, x, y, wrap_angle(a + math.tau * w * t))
                 for (pid, x, y, a), w in zip(base, turns_per_s)]
        yield t, poses, [(0.0, 0.0)] * len(poses), ()


def turns(betas: list[float], seed: int) -> dict[str, object]:
    """Heading lag and jitter per ``angle_beta`` (every tracker reads the same frames)."""
    out: dict[str, object] = {}
    speeds = [0.0, 0.0, 0.05, 0.1, 0.5, 1.0, 2.0, 4.0]   # turns a second; two still pucks
    for fps in RATES:
        cam = Camera(seed)
        trks = {b: PuckTracker(plugin.tracker_settings({"angle_beta": b})) for b in betas}
        err: dict[float, dict[int, list[float]]] = {b: {} for b in betas}
        for t, poses, vels, occ in _turn_scene(fps, 3.0, speeds):
            fr = cam.cam.render(poses, t, vels, occ)
            ms = cam.read(fr, trks[betas[0]].predict(t))
            for b, trk in trks.items():
                for p in trk.step(ms, t):
                    if t >= 1.0:   # past the filter's settling
                        a = poses[p.id - 1][3]
                        err[b].setdefault(p.id, []).append(math.degrees(wrap_angle(p.angle - a)))
        for b in betas:
            row: dict[str, float] = {}
            for i, w in enumerate(speeds):
                e = np.array(err[b].get(i + 1, [np.nan]))
                lag = -np.sign(w) * e if w else e
                if w >= 0.5:
                    row[f"lag_{w:g}tps_median_deg"] = float(np.median(lag))
                    row[f"lag_{w:g}tps_p95_deg"] = float(np.percentile(np.abs(e), 95))
                elif w > 0:
                    row[f"jitter_{w:g}tps_deg"] = float(np.std(np.diff(e, 2)))
                    row[f"lag_{w:g}tps_median_deg"] = float(np.median(lag))
            row["still_sd_deg"] = float(np.mean([np.std(err[b].get(i, [np.nan])) for i in (1, 2)]))
            out[f"{int(fps)}hz_beta{b:g}"] = row
    return out


# ------------------------------------------------------------------------------- clutter
def clutter(seeds: list[int]) -> dict[str, object]:
    """False sightings among hands reaching over circling pucks (every 1.5 s, 1.2 s each); then
    the same with ``PRINTS`` marker-like prints on the table (``printed``): also the frames
    showing a puck whose id is not on the table (``false_puck_frames``)."""
    out: dict[str, object] = {}
    for prints in (0, PRINTS):
        for fps in RATES:
            key = f"{int(fps)}hz" + (f"_printed_{prints}" if prints else "")
            out[key] = _clutter_run(seeds, fps, prints)
            if not prints:
                del out[key]["false_puck_frames"]   # type: ignore[attr-defined]
    return out


def _clutter_run(seeds: list[int], fps: float, prints: int) -> dict[str, object]:
    """One rate of the clutter section, ``prints`` prints on the table."""
    false_reads = reads = gone = false_shown = 0
    errors: list[float] = []
    for seed in seeds:
        cam = Camera(seed, exposure_s=0.008, prints=prints)
        # with prints, the installation names its pucks (tracking.pucks), as it should
        trk = PuckTracker(plugin.tracker_settings({"pucks": [1, 2, 3, 4]} if prints else {}))
        rng = np.random.default_rng(seed)
        base = [(k + 1, 0.15 + 0.3 * k, 0.2 + 0.4 * rng.random(), 0.0) for k in range(4)]
        for f in range(int(4.0 * fps)):
            t = f / fps
            w = 0.4 / 0.09
            poses = [(pid, x + 0.09 * math.cos(w * t + pid), y + 0.09 * math.sin(w * t + pid),
                      wrap_angle(a + t)) for pid, x, y, a in base]
            vels = [(-0.4 * math.sin(w * t + p[0]), 0.4 * math.cos(w * t + p[0]))
                    for p in base]
            occ = scripted_hands(t, (1.2, 0.8), every_s=1.5, duration_s=1.2, seed=seed)
            fr = cam.cam.render(poses, t, vels, occ)
            ms = cam.read(fr, trk.predict(t))
            truth = {pid: (x, y) for pid, x, y, _ in poses}
            for m in ms:
                reads += 1
                tx = truth.get(m.id)
                false_reads += tx is None or math.hypot(m.x - tx[0], m.y - tx[1]) > 0.02
            pucks = {p.id: p for p in trk.step(ms, t)}
            false_shown += sum(pid not in truth for pid in pucks)
            for pid, (x, y) in truth.items():
                if pid in pucks:
                    errors.append(1000 * math.hypot(pucks[pid].x - x, pucks[pid].y - y))
                elif t > 0.2:
                    gone += 1
    return {"reads": reads, "false_sightings": false_reads,
            "false_puck_frames": false_shown, **_shown(errors, gone)}


def main() -> None:
    check_flags("tracking_quality", sys.argv[1:], lists={"sections": SECTIONS},
                values={"angle-betas": "B,B,...", "seeds": "S,S,..."})
    args = dict(a[2:].split("=", 1) for a in sys.argv[1:] if "=" in a)
    sections = args.get("sections", ",".join(SECTIONS)).split(",")
    betas = [float(b) for b in args.get("angle-betas", "2,4,6,8").split(",")]
    seeds = [int(s) for s in args.get("seeds", "1,2,3").split(",")]
    t0 = time.monotonic()
    runs: dict[str, Callable[[], dict[str, object]]] = {
        "returns": lambda: returns(seeds), "turns": lambda: turns(betas, seeds[0]),
        "clutter": lambda: clutter(seeds)}
    figures: dict[str, object] = {s: runs[s]() for s in sections}
    figures["wall_s"] = time.monotonic() - t0
    budgets = {"clutter": {"false_sightings": 0, "gone_frames": 0}}
    emit("tracking_quality", figures, budgets)


if __name__ == "__main__":
    main()
