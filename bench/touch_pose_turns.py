"""Touch-pose control: the largest joint turn (degrees) in one 30 fps frame of each action.

Each action's stroke is dragged on its primary part at its recorded pace from four views
(90,15 270,30 60,10 300,20; views that exclude the action are skipped), then the finger lifts
and the action runs on to its end (bench/touch_pose_drags.py ``stroke_drag``, physics off).
Over the frames in action control, per action: the largest turn of any joint of the target
posture (before tracking) while the finger drags (``*_drag_deg``) and once it has lifted
(``*_run_deg``), and of the tracked output (``*_output_deg``); the worst view each.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402

from bench.common import check_flags, emit  # noqa: E402
from behaviors.touch_pose.engine import TouchPose, learned_models  # noqa: E402
from behaviors.touch_pose.tracking import rot_diff  # noqa: E402
from bench.touch_pose_drags import stroke_drag  # noqa: E402

VIEWS = ((90.0, 15.0), (270.0, 30.0), (60.0, 10.0), (300.0, 20.0))


def largest_turns(rots: list[np.ndarray], frames: list[int]) -> float:
    """The largest joint turn (degrees) between each of ``frames`` and the frame before."""
    return max((float(np.degrees(np.linalg.norm(rot_diff(rots[k], rots[k - 1]), axis=1)).max())
                for k in frames), default=0.0)


def main() -> None:
    check_flags("touch_pose_turns", sys.argv[1:])
    models = learned_models()
    figures: dict[str, float] = {}
    for a in models.actions:
        drag, run, output = [], [], []
        for view in VIEWS:
            e = TouchPose(azimuth=view[0], elevation=view[1], physics=False, models=models)
            if next(d for d in e.describe()["actions"] if d["name"] == a.name)["excluded"]:
                e.close()
                continue
            recs, targets, outputs = stroke_drag(e, models, a.name, pace=1.0, after=2.0)
            e.close()
            acting = [k for k in range(1, len(recs))
                      if recs[k]["action"] == a.name and recs[k - 1]["action"] == a.name]
            drag.append(largest_turns(targets, [k for k in acting if recs[k]["touches"]]))
            run.append(largest_turns(targets, [k for k in acting if not recs[k]["touches"]]))
            output.append(largest_turns(outputs, acting))
        for key, values in (("drag", drag), ("run", run), ("output", output)):
            figures[f"{a.name}_{key}_deg"] = round(max(values, default=0.0), 1)
    emit("touch_pose_turns", figures, {})


if __name__ == "__main__":
    main()
