"""Marker tracking speed: our tracker (verification of known markers, region-of-interest and
periodic full-frame detection, then the puck tracker) against a plain full-frame
``ArucoDetector.detectMarkers`` on the same frames; and the same tracker without verification
(``roi_only``: every known marker re-detected in its crop) for comparison.

For 1280x720 and 1920x1080 with 4 and 16 moving pucks (synthetic camera: blur, noise, motion
blur), all run interleaved frame by frame in one process. Figures: ms per frame of each, their
ratio to plain (budget <= 0.3 at 720p, <= 0.2 at 1080p), detection rate of fully visible
markers, centre error (pixels), and the share of frames between full-frame passes that needed no
detection at all. Ours includes the full-frame search a camera runs after publishing the frame's
result (``defer_full_frame``); ``ours_until_result`` is the part before the result, which is what
the capture-to-render latency sees.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from bench.common import check_flags, emit, interleaved, stats_ms  # noqa: E402
from tabletop.plugins import tracking as plugin  # noqa: E402
from tracking.markers import (DetectorSettings, detect_markers, make_detector,  # noqa: E402
                              marker_measurements,
                              marker_side_lengths)
from tracking.pucks import PuckTracker  # noqa: E402
from tracking.scenes import moving_scene, score_detections  # noqa: E402
from tracking.synthetic import CameraSettings, SyntheticCamera  # noqa: E402

FRAMES = 60
PASSES = 3
FPS = 30.0


def score(frames, outputs) -> tuple[float, float, float]:
    """Detection rate of fully visible markers, median and p95 centre error (pixels)."""
    rate, errs, _, _ = score_detections(frames, outputs)
    e = errs if len(errs) else np.array([np.nan])
    return rate, float(np.median(e)), float(np.percentile(e, 95))


def run_config(resolution: tuple[int, int], n: int) -> dict[str, float]:
    cam = SyntheticCamera(CameraSettings(resolution=resolution, blur_sigma=0.8, noise_sigma=3.0,
                                         exposure_s=0.01, seed=n))
    frames = [cam.render(p, t, v) for t, p, v in moving_scene(n, FRAMES, FPS, speed=0.4, seed=n)]
    plain = make_detector(DetectorSettings(corner_refinement="none"))
    state: dict[str, object] = {}

    def reset() -> None:
        for name, verify in (("ours", True), ("roi_only", False)):
            state[name] = plugin.build_detector({"verify_known": verify})
            state[f"tracker_{name}"] = None
            state[f"k_{name}"] = 0
            state[f"out_{name}"], state[f"passes_{name}"] = [], []
            state.setdefault(f"quick_{name}", [])
        state["k_plain"] = 0
        state["out_plain"] = []

    def tracked(name: str) -> None:
        k = state[f"k_{name}"]
        f = frames[k]
        det = state[name]
        tracker = state[f"tracker_{name}"]
        preds = tracker.predict(f.t) if tracker is not None else None
        t0 = time.perf_counter()
        ids, corners = det.detect(f.image, preds or None)
        state[f"quick_{name}"].append(time.perf_counter() - t0)
        if tracker is None:  # pixels: scale the metre settings by the markers' size
            scale = float(np.median(marker_side_lengths(corners))) / 0.05 if len(ids) else 900.0
            tracker = state[f"tracker_{name}"] = PuckTracker(plugin.tracker_settings({}, scale))
        tracker.step(marker_measurements(ids, corners, f.t), f.t)
        state[f"out_{name}"].append((ids, corners))
        state[f"passes_{name}"].append(det.last_pass)
        det.search_pending()  # the put-off full-frame search, after the frame's result is out
        state[f"k_{name}"] = k + 1

    def plain_full() -> None:
        k = state["k_plain"]
        state["out_plain"].append(detect_markers(frames[k].image, plain))
        state["k_plain"] = k + 1

    ours_t: list[float] = []
    roi_t: list[float] = []
    plain_t: list[float] = []
    for _ in range(PASSES):
        reset()
        times = interleaved({"ours": lambda: tracked("ours"), "plain": plain_full,
                             "roi_only": lambda: tracked("roi_only")}, FRAMES)
        ours_t += times["ours"]
        roi_t += times["roi_only"]
        plain_t += times["plain"]
    rate_o, med_o, p95_o = score(frames, state["out_ours"])
    rate_r, med_r, p95_r = score(frames, state["out_roi_only"])
    rate_p, med_p, p95_p = score(frames, state["out_plain"])
    so, sr, sp = stats_ms(ours_t), stats_ms(roi_t), stats_ms(plain_t)
    between = [p for p in state["passes_ours"] if p != "full"]
    quick = stats_ms(state["quick_ours"])
    return {"ours_ms": so["mean_ms"], "ours_median_ms": so["median_ms"],
            "ours_p99_ms": so["p99_ms"],
            "ours_until_result_median_ms": quick["median_ms"],
            "ours_until_result_p99_ms": quick["p99_ms"],
            "roi_only_ms": sr["mean_ms"], "roi_only_ratio": sr["mean_ms"] / sp["mean_ms"],
            "plain_ms": sp["mean_ms"], "plain_median_ms": sp["median_ms"],
            "ratio": so["mean_ms"] / sp["mean_ms"],
            "verified_only_frame_share": between.count("verify") / max(len(between), 1),
            "roi_only_detection_rate": rate_r, "roi_only_centre_error_median_px": med_r,
            "roi_only_centre_error_p95_px": p95_r,
            "ours_detection_rate": rate_o, "plain_detection_rate": rate_p,
            "ours_centre_error_median_px": med_o, "ours_centre_error_p95_px": p95_o,
            "plain_centre_error_median_px": med_p, "plain_centre_error_p95_px": p95_p}


def main() -> None:
    check_flags("tracking", sys.argv[1:])
    t0 = time.monotonic()
    figures: dict[str, object] = {}
    budgets: dict[str, object] = {}
    for res in ((1280, 720), (1920, 1080)):
        for n in (4, 16):
            key = f"{res[0]}x{res[1]}_{n}pucks"
            r = run_config(res, n)
            figures[key] = r
            budgets[key] = {"ratio": 0.3 if res[1] == 720 else 0.2, "ours_detection_rate": 0.99,
                            "ours_centre_error_median_px": 0.5, "ours_centre_error_p95_px": 1.5}
            print(f"{key}: ours {r['ours_ms']:.2f} ms, roi only {r['roi_only_ms']:.2f} ms, "
                  f"plain {r['plain_ms']:.2f} ms, ratio {r['ratio']:.2f} "
                  f"(roi only {r['roi_only_ratio']:.2f}), rate {r['ours_detection_rate']:.3f}, "
                  f"verified-only frames {r['verified_only_frame_share']:.2f}", flush=True)
    figures["frames_per_config"] = FRAMES * PASSES
    figures["wall_s"] = time.monotonic() - t0
    emit("tracking", figures, budgets)


if __name__ == "__main__":
    main()
