"""A finger dragging a touch-pose action's stroke, step by step, as the tests and the benches
(``bench/touch_pose_rest.py``, ``bench/touch_pose_turns.py``) drive the engine: along the stroke
and lifted (:func:`stroke_drag`), or there and back (:func:`there_and_back`)."""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from behaviors.touch_pose.engine import TouchPose


class Drag(NamedTuple):
    """What :func:`there_and_back` recorded, one entry a step."""
    recs: list          # the engine's output records
    fingers: list       # the finger's true point (table m) without its jitter; None once lifted
    targets: list       # the target's drawn parts (table m), before tracking
    turn: float         # when the finger turned back (s)


def there_and_back(engine: TouchPose, models: Any, name: str, frac: float = 1.0,
                   back: float | None = None, pace: float = 1.0, slower: float = 1.0,
                   rate: float = 30.0, after: float = 0.0, hold: float = 0.0,
                   jitter: float = 0.0, seed: int = 0, pause: float = 0.0) -> Drag | None:
    """Drag ``name``'s stroke forward at ``pace`` times its duration to ``frac`` of it, rest
    ``pause`` s, then back along it to ``back`` of it (``frac`` if None) taking ``slower`` times
    as long, hold the finger there ``hold`` s, lift, run ``after`` s (``rate`` Hz); each touch
    off by up to ``jitter`` m each way (seeded). None where the view excludes the action."""
    rng = np.random.default_rng(seed)
    desc = next(a for a in engine.describe()["actions"] if a["name"] == name)
    if desc["excluded"]:
        return None
    traj = np.array(desc["trajectory"])
    act = next(a for a in models.actions if a.name == name)
    times = act.stroke_t * pace
    back = frac if back is None else back
    turn = frac * times[-1] + pause
    end = turn + (frac - back) * times[-1] * slower + hold
    out, k = Drag([], [], [], turn), 0
    while (t := k / rate) <= end + after:
        k += 1
        s = min(t, frac * times[-1]) if t <= turn else max(
            frac * times[-1] - (t - turn) / slower, back * times[-1])
        xy = np.array([np.interp(s, times, traj[:, 0]), np.interp(s, times, traj[:, 1])])
        off = rng.uniform(-jitter, jitter, 2)
        touches = {1: (float(xy[0] + off[0]), float(xy[1] + off[1]))} if t <= end else {}
        out.recs.append(engine.step(t, touches))
        out.fingers.append(xy if t <= end else None)
        out.targets.append(engine.camera.table(engine.body.parts(engine.target)))
    return out


def stroke_drag(engine: TouchPose, models: Any, name: str, pace: float = 1.0, frac: float = 1.0,
                hold: float = 0.0, after: float = 3.0, rate: float = 30.0,
                before: float = 0.0) -> tuple[list, list[np.ndarray], list[np.ndarray]]:
    """Drag the primary part of action ``name`` along its projected stroke at ``pace`` times
    its recorded duration (``frac`` of it), hold the finger ``hold`` s, lift, run ``after`` s
    (``rate`` Hz); ``before`` s of resting on the part come first.
    Returns the output records, and the target (before tracking) and output rotations per step."""
    desc = engine.describe()
    traj = np.array(next(a for a in desc["actions"] if a["name"] == name)["trajectory"])
    act = next(a for a in models.actions if a.name == name)
    times = act.stroke_t * pace + before
    end = before + (times[-1] - before) * frac
    out, targets, outputs = [], [], []
    k, t = 0, 0.0
    while t <= end + hold + after:
        t = k / rate
        k += 1
        if t <= end + hold:
            s = min(t, end)
            touches = {1: (float(np.interp(s, times, traj[:, 0])),
                           float(np.interp(s, times, traj[:, 1])))}
        else:
            touches = {}
        out.append(engine.step(t, touches))
        targets.append(engine.target.rots.copy())
        outputs.append(engine.output.rots.copy())
    return out, targets, outputs
