"""Equation 6 (paper 003, the physical effect) read three ways, measured on the engine.

    dq_i = s1 dq_i' + s2 (q_sim,i - q_sim,i'),   s1 = 0.2 dt, s2 = 0.5 dt      (6)

- ``frames_minus_tracked`` (the engine's :class:`~behaviors.touch_pose.tracking.PhysicalEffect`):
  dt in frames of the paper's 30 fps (s1 = 0.2, s2 = 0.5 a frame), the tracked pose's own
  change subtracted from the simulated change;
- ``frames_literal``: dt in frames, the simulated change as it is;
- ``seconds_literal``: dt in seconds (s1 = 0.2/30, s2 = 0.5/30 at 30 fps), the simulated change.

Three scenes, physics on, seen from 90,15: the right hand dragged up and down 0.03 m at 1 Hz
(2 s), the punch dragged at its pace, the pelvis dragged sideways 0.04 m at 0.7 Hz (2 s), each
followed by 1 s without fingers. Figures (degrees): the sway of the untouched arm(s) (the
output's rotation from the tracked pose's, left shoulder and elbow, and the right's in the
pelvis scene; median and largest over frames), the largest turn of any joint in one output
frame and how much more that is than the tracked pose's own turn that frame (continuity), and
the largest sway left after the second without fingers.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402

from bench.common import check_flags, emit  # noqa: E402
from behaviors.touch_pose.engine import TouchPose, learned_models  # noqa: E402
from behaviors.touch_pose.tracking import FRAME, S1, S2, PhysicalEffect, rot_diff  # noqa: E402

DT = 1.0 / 30.0


class Literal(PhysicalEffect):
    """Equation 6 with the simulated change as it is; ``seconds``: s1, s2 scaled by dt in s."""

    def __init__(self, n_joints: int, seconds: bool) -> None:
        super().__init__(n_joints)
        self.seconds = seconds

    def update(self, sim, target, dt: float) -> None:
        if self._sim is not None:
            f = dt if self.seconds else dt / FRAME
            self.dq = min(S1 * f, 1.0) * self.dq + S2 * f * rot_diff(sim.rots, self._sim.rots)
            self.dp = min(S1 * f, 1.0) * self.dp + S2 * f * (sim.root - self._sim.root)
        self._sim, self._target = sim.copy(), target.copy()


VARIANTS = {"frames_minus_tracked": lambda n: PhysicalEffect(n),
            "frames_literal": lambda n: Literal(n, seconds=False),
            "seconds_literal": lambda n: Literal(n, seconds=True)}


def scene(e: TouchPose, name: str) -> list[dict[int, tuple[float, float]]]:
    """The fingers of each frame of scene ``name``."""
    parts = e.describe()["parts"]
    if name == "punch":
        a = next(a for a in e.describe()["actions"] if a["name"] == "punch")
        traj = np.array(a["trajectory"])
        act = next(x for x in e.m.actions if x.name == "punch")
        n = int(act.stroke_t[-1] * 30) + 1
        return [{1: (float(np.interp(k * DT, act.stroke_t, traj[:, 0])),
                     float(np.interp(k * DT, act.stroke_t, traj[:, 1])))} for k in range(n)] \
            + [{} for _ in range(90)]
    if name == "shake":
        h = np.array(parts["right_hand"])
        return [{1: tuple(h + [0.0, 0.03 * math.sin(2 * math.pi * k * DT)])} for k in range(60)] \
            + [{} for _ in range(30)]
    p = np.array(parts["pelvis"])
    return [{1: tuple(p + [0.04 * math.sin(2 * math.pi * 0.7 * k * DT), 0.0])} for k in range(60)] \
        + [{} for _ in range(30)]


def run(models, variant: str, name: str) -> dict[str, list[float]]:
    e = TouchPose(azimuth=90.0, elevation=15.0, physics=True, models=models)
    e.effect = VARIANTS[variant](len(models.body.names))
    names = models.body.names
    arms = [names.index(j) for j in ("left_shoulder", "left_elbow")]
    if name == "pelvis":
        arms += [names.index(j) for j in ("right_shoulder", "right_elbow")]
    out: dict[str, list[float]] = {"sway": [], "jump": [], "extra": [], "rest": []}
    prev_out = prev_tr = None
    fingers = scene(e, name)
    for k, touches in enumerate(fingers):
        e.step(k * DT, touches)
        sway = np.degrees(np.linalg.norm(rot_diff(e.output.rots, e.tracker.pose.rots), axis=1))
        out["sway"].append(float(sway[arms].max()))
        if k >= len(fingers) - 3:
            out["rest"].append(float(sway.max()))
        if prev_out is not None:
            turn = np.degrees(np.linalg.norm(rot_diff(e.output.rots, prev_out), axis=1))
            own = np.degrees(np.linalg.norm(rot_diff(e.tracker.pose.rots, prev_tr), axis=1))
            out["jump"].append(float(turn.max()))
            out["extra"].append(float((turn - own).max()))
        prev_out, prev_tr = e.output.rots.copy(), e.tracker.pose.rots.copy()
    e.close()
    return out


def main() -> None:
    check_flags("touch_pose_effect", sys.argv[1:])
    models = learned_models()
    figures: dict = {}
    for name in ("shake", "punch", "pelvis"):
        for variant in VARIANTS:
            r = run(models, variant, name)
            key = f"{name}_{variant}"
            figures[f"{key}_arm_sway_median_deg"] = round(float(np.median(r["sway"])), 2)
            figures[f"{key}_arm_sway_max_deg"] = round(max(r["sway"]), 2)
            figures[f"{key}_turn_max_deg_per_frame"] = round(max(r["jump"]), 2)
            figures[f"{key}_extra_turn_max_deg_per_frame"] = round(max(r["extra"]), 2)
            figures[f"{key}_sway_after_rest_deg"] = round(max(r["rest"]), 2)
    emit("touch_pose_effect", figures, {})


if __name__ == "__main__":
    main()
