"""Posing blend (paper 003, section 4): inverse-distance weights and the quaternion blend.

Weights w = 1 / (d + eps)^p over the chosen cell's and its neighbours' samples (d: constraint
distance, m), for p in 1, 2, 4 and eps in 0.005, 0.02, 0.05, and a Gaussian exp(-(d/s)^2/2)
(s = 0.05); joints blended as the normalised weighted sum of sign-aligned quaternions
(``nlerp``, the engine's) or as the weighted mean of rotation vectors about the heaviest sample
(``logmap``). Figures: over the held-out postures of bench/touch_pose_posing.py (in place,
touched on 1-3 parts from two views), the blend's constraint distance (median / p90, screen m,
character scale); and smoothness, the largest move of the blended right hand per metre the
finger moves (the hand's target swept 0.6 m in 2 mm steps across the screen, view 90,15), its
p99, the steps where it moved over 5 times the finger's step (jumps) and its mean (the hand's
path per metre of the finger's).
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402

from bench.common import check_flags, emit  # noqa: E402
from bench.touch_pose_posing import bounded, distances, held_out  # noqa: E402
from behaviors.motion.clips import (quat_conj, quat_from_rotvec, quat_mul,  # noqa: E402
                                    quat_to_rotvec)
from behaviors.touch_pose.engine import learned_models  # noqa: E402
from behaviors.touch_pose.humanoid import PARTS, Camera, Pose  # noqa: E402


def weights(d: np.ndarray, scheme: str) -> np.ndarray:
    if scheme.startswith("gauss"):
        return np.exp(-0.5 * (d / float(scheme[5:])) ** 2) + 1e-300
    p, eps = scheme.split("/")
    return 1.0 / (d + float(eps)) ** float(p)


def blended(model, parts, targets, view, scheme: str, quats: str) -> Pose:
    """The model's synthesis with another weighting or quaternion blend."""
    b = model.synthesize(parts, targets, view, np.zeros(2), lambda d: weights(d, scheme))
    if quats == "nlerp":
        return b.pose
    q = model.rots[b.index]
    ref = q[int(np.argmax(b.weight))]
    mean = np.einsum("n,njk->jk", b.weight, quat_to_rotvec(quat_mul(quat_conj(ref)[None], q)))
    return Pose(b.pose.root, quat_mul(ref, quat_from_rotvec(mean)))


def main() -> None:
    check_flags("touch_pose_blend", sys.argv[1:])
    models = learned_models()
    model, body = models.posing, models.body
    tests = [bounded(p, 0.0, 0.0) for p in held_out(body)]
    figures: dict = {}
    schemes = ["1/0.02", "2/0.005", "2/0.02", "2/0.05", "4/0.02", "gauss0.05"]
    runs = [(s, "nlerp") for s in schemes] + [("2/0.02", "logmap")]
    hand = np.array([PARTS.index("right_hand")])
    sweep_view = Camera(90.0, 15.0, 1.0).matrix
    start = body.parts(models.stand)[hand] @ sweep_view.T
    path = start + np.linspace(-0.3, 0.3, 301)[:, None] * np.array([[1.0, 0.3]])
    for scheme, quats in runs:
        dist = distances(model, tests,
                         lambda i, tg, v: blended(model, i, tg, v, scheme, quats))
        moves = []
        prev = None
        for tg in path:
            h = body.parts(blended(model, hand, tg[None], sweep_view, scheme, quats))[hand[0]]
            if prev is not None:
                moves.append(float(np.linalg.norm(h - prev))
                             / float(np.linalg.norm(path[1] - path[0])))
            prev = h
        key = f"{quats}_{scheme.replace('/', '_')}"
        figures[f"{key}_median_m"] = round(float(np.median(dist)), 4)
        figures[f"{key}_p90_m"] = round(float(np.percentile(dist, 90)), 4)
        figures[f"{key}_hand_move_per_m_max"] = round(max(moves), 2)
        figures[f"{key}_hand_move_per_m_p99"] = round(float(np.percentile(moves, 99)), 2)
        figures[f"{key}_hand_jumps"] = int(np.sum(np.array(moves) > 5.0))
        figures[f"{key}_hand_path_per_m"] = round(float(np.mean(moves)), 2)
    emit("touch_pose_blend", figures, {})


if __name__ == "__main__":
    main()
