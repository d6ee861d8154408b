"""Action control (paper 003, section 5): a finger resting on a running action, and its lag.

Each action's stroke is dragged on its primary part at its recorded pace from four views
(90,15 270,30 60,10 300,20; views that exclude the action are skipped), then the finger rests
1.5 s at the stroke's end with touches off by up to 1 or 2 mm each way (seeds 0-3, physics
off). Over the frames where the action may stand still, from 0.5 s after the finger stopped,
the back-and-forth (path minus net change) of: ``*_rest_*_s`` the action time (seconds of
action time), ``*_rest_*_target_m`` / ``*_output_m`` the body part that moves most in the
target (before tracking) / the output (table m); median and largest over views and seeds (the
kick runs on to where it may stand: 0).
Lag on real motion, table metres: ``follow_{f}x`` the primary part's mean distance from the
finger while it drags the stroke over f = 0.75, 1 and 1.5 times its recorded duration (4/3,
1 and 2/3 of its pace; mean over the six actions other than the walk), ``*_back_*`` the same while
it drags back along the stroke from its end (the punch to 0.4 of it, the wave to 0.3 and 0.6, the
bow to 0.3, the walk from 0.9 to 0.5) and rests 1 s; ``*_slower``: the drag back takes 3 or 5 times
as long as the stroke forward (a finger that slow moves the synthesised time less than the resting
finger's band).
Usage: ``bench/touch_pose_rest.py``.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402

from bench.common import check_flags, emit  # noqa: E402
from bench.touch_pose_drags import there_and_back  # noqa: E402
from behaviors.touch_pose.engine import TouchPose, learned_models  # noqa: E402

VIEWS = ((90.0, 15.0), (270.0, 30.0), (60.0, 10.0), (300.0, 20.0))


def rest(models, name: str, jitter: float) -> tuple[list[float], list[float], list[float]]:
    """Per view and seed: the action time's back-and-forth (s), and the largest over the parts
    of their back-and-forth (table m) in the target and in the output, while the finger rests."""
    act = next(a for a in models.actions if a.name == name)
    times, target, output = [], [], []
    for view in VIEWS:
        for seed in range(4):
            e = TouchPose(azimuth=view[0], elevation=view[1], physics=False, models=models)
            d = there_and_back(e, models, name, hold=1.5, jitter=jitter, seed=seed)
            e.close()
            stop = act.stroke_t[-1] + 0.5
            k = [i for i, r in enumerate(d.recs if d else []) if r["action"] == name
                 and r["t"] >= stop and act.segment(r["action_time"] / act.duration).still]
            if len(k) < 5:
                continue
            u = np.array([d.recs[i]["action_time"] for i in k])
            times.append(float(np.abs(np.diff(u)).sum() - abs(u[-1] - u[0])))
            for found, pts in ((target, [d.targets[i] for i in k]),
                               (output, [list(d.recs[i]["parts"].values()) for i in k])):
                p = np.array(pts)
                path = np.linalg.norm(np.diff(p, axis=0), axis=2).sum(axis=0)
                found.append(float((path - np.linalg.norm(p[-1] - p[0], axis=1)).max()))
    return times, target, output


def gap(models, name: str, **kw) -> list[float]:
    """The primary part's distances from the finger (table m) while the action runs and the
    finger touches (``kw`` as :func:`there_and_back`'s)."""
    act = next(a for a in models.actions if a.name == name)
    found = []
    for view in VIEWS:
        e = TouchPose(azimuth=view[0], elevation=view[1], physics=False, models=models)
        d = there_and_back(e, models, name, **kw)
        e.close()
        if d is not None:
            found += [float(np.linalg.norm(np.array(r["parts"][act.spec.part]) - xy))
                      for r, xy in zip(d.recs, d.fingers) if r["action"] == name and xy is not None]
    return found


def main() -> None:
    check_flags("touch_pose_rest", sys.argv[1:], [], {})
    models = learned_models()
    figures: dict[str, float] = {}
    for name in ("punch", "wave", "bow", "kick"):
        for mm in (1, 2):
            for what, d in zip(("s", "target_m", "output_m"), rest(models, name, mm / 1000)):
                figures[f"{name}_rest_{mm}mm_median_{what}"] = round(float(np.median(d)), 4)
                figures[f"{name}_rest_{mm}mm_max_{what}"] = round(float(max(d)), 4)
    for pace in (0.75, 1.0, 1.5):
        means = [np.mean(d) for a in models.actions if a.name != "walk"
                 if (d := gap(models, a.name, pace=pace))]
        figures[f"follow_{pace}x_mean_m"] = round(float(np.mean(means)), 4)
    for name, turn, to, slower in (("punch", 1.0, 0.4, 1), ("wave", 1.0, 0.3, 1),
                                   ("wave", 1.0, 0.6, 1), ("bow", 1.0, 0.3, 1),
                                   ("walk", 0.9, 0.5, 1), ("wave", 1.0, 0.3, 3),
                                   ("wave", 1.0, 0.3, 5), ("bow", 1.0, 0.3, 5)):
        d = gap(models, name, frac=turn, back=to, slower=slower, hold=1.0)
        key = f"{name}_back_to_{to}" + (f"_{slower}x_slower" if slower > 1 else "")
        figures[f"{key}_mean_m"] = round(float(np.mean(d)), 4)
    emit("touch_pose_rest", figures, {})


if __name__ == "__main__":
    main()
