"""Action control (paper 003, section 5): a finger resting on a running action, and its lag.

Each action's stroke is dragged on its primary part at its recorded pace from four views
(90,15 270,30 60,10 300,20; views that exclude the action are skipped), then the finger rests
1.5 s at the stroke's end with touches off by up to 1 or 2 mm each way (seeds 0-3, physics
off). ``*_rest_*``: the action time's back-and-forth (its path minus its net change, seconds of
action time) over the frames where the action may stand still, from 0.5 s after the finger
stopped; median and largest over views and seeds (the kick runs on to where it may stand: 0).
Lag on real motion, table metres: ``*_follow_*`` the primary part's mean distance from the
finger while it drags the stroke at 0.75, 1 and 1.5 times its pace (mean over the six actions),
``*_back_*`` the same while it drags back along the stroke from its end (the punch to 0.4 of
it, the wave to 0.3 and 0.6, the bow to 0.3, the walk from 0.9 to 0.5) and rests 1 s.
Usage: ``bench/touch_pose_rest.py``.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402

from bench.common import check_flags, emit  # noqa: E402
from behaviors.touch_pose.engine import TouchPose, learned_models  # noqa: E402

VIEWS = ((90.0, 15.0), (270.0, 30.0), (60.0, 10.0), (300.0, 20.0))
RATE = 30.0


def drag(e: TouchPose, models, name: str, pace: float = 1.0, back: tuple | None = None,
         hold: float = 1.5, jitter: float = 0.0, seed: int = 0):
    """Drag ``name``'s stroke at ``pace`` (to its end, or there and back: ``back`` = (turn,
    to) fractions of it), rest ``hold`` s, touches off by up to ``jitter`` m (seeded); the
    output records with the finger's true position, or None where the view excludes it."""
    rng = np.random.default_rng(seed)
    d = next(a for a in e.describe()["actions"] if a["name"] == name)
    if d["excluded"]:
        return None
    traj = np.array(d["trajectory"])
    act = next(a for a in models.actions if a.name == name)
    times = act.stroke_t * pace
    turn, to = back or (1.0, 1.0)
    turn_t = turn * times[-1]
    end = turn_t + (turn - to) * times[-1] + hold
    out, k = [], 0
    while (t := k / RATE) <= end:
        k += 1
        s = t if t <= turn_t else max(2 * turn_t - t, to * times[-1])
        xy = np.array([np.interp(s, times, traj[:, 0]), np.interp(s, times, traj[:, 1])])
        out.append((e.step(t, {1: tuple(xy + rng.uniform(-jitter, jitter, 2))}), xy))
    return out


def rest(models, name: str, jitter: float) -> list[float]:
    act = next(a for a in models.actions if a.name == name)
    found = []
    for view in VIEWS:
        for seed in range(4):
            e = TouchPose(azimuth=view[0], elevation=view[1], physics=False, models=models)
            out = drag(e, models, name, jitter=jitter, seed=seed)
            e.close()
            stop = act.stroke_t[-1] + 0.5
            u = [r["action_time"] for r, _ in out or [] if r["action"] == name and r["t"] >= stop
                 and act.segment(r["action_time"] / act.duration).still]
            if len(u) >= 5:
                found.append(float(np.abs(np.diff(u)).sum() - abs(u[-1] - u[0])))
    return found


def gap(models, name: str, **kw) -> list[float]:
    """The primary part's distances from the finger (table m) while the action runs."""
    act = next(a for a in models.actions if a.name == name)
    found = []
    for view in VIEWS:
        e = TouchPose(azimuth=view[0], elevation=view[1], physics=False, models=models)
        out = drag(e, models, name, **kw)
        e.close()
        found += [float(np.linalg.norm(np.array(r["parts"][act.spec.part]) - xy))
                  for r, xy in out or [] if r["action"] == name]
    return found


def main() -> None:
    check_flags("touch_pose_rest", sys.argv[1:], [], {})
    models = learned_models()
    figures: dict[str, float] = {}
    for name in ("punch", "wave", "bow", "kick"):
        for mm in (1, 2):
            d = rest(models, name, mm / 1000)
            figures[f"{name}_rest_{mm}mm_median_s"] = round(float(np.median(d)), 4)
            figures[f"{name}_rest_{mm}mm_max_s"] = round(float(max(d)), 4)
    for pace in (0.75, 1.0, 1.5):
        means = [np.mean(d) for a in models.actions if a.name != "walk"
                 if (d := gap(models, a.name, pace=pace, hold=0.0))]
        figures[f"follow_{pace}x_mean_m"] = round(float(np.mean(means)), 4)
    for name, turn, to in (("punch", 1.0, 0.4), ("wave", 1.0, 0.3), ("wave", 1.0, 0.6),
                           ("bow", 1.0, 0.3), ("walk", 0.9, 0.5)):
        d = gap(models, name, back=(turn, to), hold=1.0)
        figures[f"{name}_back_to_{to}_mean_m"] = round(float(np.mean(d)), 4)
    emit("touch_pose_rest", figures, {})


if __name__ == "__main__":
    main()
