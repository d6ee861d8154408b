"""Studio training benchmark: does stopping a take stall the frame loop?

Each round records one take through the studio (countdown 0) and times every tick (studio
filter + engine step) from the stop until the new take plays: the stop's tick and the worst
tick of that span. Compared, interleaved A B A B: a Puppet Master take of 60 s (2,400 samples
at 40 Hz, the lover) trained within the stop's tick vs in the worker thread
(``designer.background_training``), a MOP take (the square gesture on ``examples/mop.yaml``'s
five characters) whose followers are rebuilt within the tick vs in the stage's worker, and a
touch-pose take (3 s of the right hand posed along an arc, physics on) whose action is learned
within the tick vs in the target's worker (ticks paced at its 30 Hz). Budget: no tick of the
span longer than one frame with the worker (16.7 ms at 60 Hz; touch-pose runs at 30 Hz: 33.3 ms).
Wall and the loop thread's CPU time are both given: on a loaded machine the wall figures carry the
waits for a core (the worker competes for one).
"""

from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import numpy as np  # noqa: E402

from bench.common import check_flags, emit  # noqa: E402
from behaviors.puppet_master import designers  # noqa: E402
from tabletop.config import load_config, validate_config  # noqa: E402
from tabletop.files import read_csv  # noqa: E402
from tabletop.frames import Frame, Puck  # noqa: E402
from tabletop.plugins import mop  # noqa: E402
from tabletop.plugins import puppet_master as pm  # noqa: E402
from tabletop.registry import BuildContext  # noqa: E402
from tabletop.studio.machine import Studio  # noqa: E402
from tabletop.studio.mop_target import MopTarget  # noqa: E402
from tabletop.studio.targets import PuppetMasterTarget  # noqa: E402

ROUNDS = 5
TABLE = (1.2, 0.8)
DEMO = designers.demonstrate("lover", seed=8, seconds=61)
_, SQUARE = read_csv(ROOT / "examples" / "mop" / "gestures" / "square.csv")


def timed(studio: Studio, engine, frame: Frame) -> tuple[float, float]:
    """(wall s, the loop thread's CPU s) of one tick."""
    c0, t0 = time.thread_time(), time.perf_counter()
    engine.step(studio(frame))
    return time.perf_counter() - t0, time.thread_time() - c0


def until_trying(studio: Studio, engine, frames,
                 period: float | None = None) -> tuple[float, float, float, float]:
    """(stop tick wall s, worst tick wall s, stop tick CPU s, worst tick CPU s) from the stop
    until the take plays; ``period``: the loop's frame period (s), else 4 ms between ticks."""
    ticks = [timed(studio, engine, next(frames))]
    deadline = time.perf_counter() + 30.0
    while studio.state == "training" and time.perf_counter() < deadline:
        # the loop's own wait for its next frame
        time.sleep(0.004 if period is None else max(0.0, period - ticks[-1][0]))
        ticks.append(timed(studio, engine, next(frames)))
    assert studio.state == "trying", studio.state
    return (ticks[0][0], max(w for w, _ in ticks), ticks[0][1], max(c for _, c in ticks))


def pm_round(background: bool, tmp: Path) -> tuple[float, ...]:
    cfg = validate_config({"sources": [{"kind": "scripted"}], "engines": [{
        "kind": "puppet_master", "name": "pet", "designer": {
            "enabled": True, "library": str(tmp), "background_training": background}}]},
        "bench.yaml", ROOT)
    engine = pm.build(cfg["engines"][0], BuildContext(TABLE, 60.0, cfg, ROOT))
    studio = Studio([PuppetMasterTarget(engine)], countdown_s=0.0)

    def frames():
        i = 0
        while True:
            r = DEMO[min(i, len(DEMO) - 1)]
            cmds = ("designer.record",) if i in (0, 2400) else ()
            yield Frame(seq=i, t=100.0 + i / 40.0, commands=cmds,
                        pucks=(Puck(1, r[1], r[2], r[3]), Puck(2, r[4], r[5], r[6])))
            i += 1
    it = frames()
    for _ in range(2400):
        engine.step(studio(next(it)))
    return until_trying(studio, engine, it)


def mop_round(background: bool, tmp: Path) -> tuple[float, ...]:
    path = ROOT / "examples" / "mop.yaml"
    cfg = load_config(path)
    options = dict(next(e for e in cfg["engines"] if e["kind"] == "mop"), library=tmp)
    stage = mop.build(options, BuildContext(TABLE, 60.0, cfg, path.parent))
    studio = Studio([MopTarget(stage, "face", tmp, background=background)], countdown_s=0.0)
    gesture = [(0.4 + np.interp(tau, SQUARE[:, 0], SQUARE[:, 1]),
                0.4 + np.interp(tau, SQUARE[:, 0], SQUARE[:, 2]))
               for tau in np.arange(0.0, SQUARE[-1, 0], 1 / 60)]

    def frames():
        i = 0
        while True:
            x, y = gesture[i] if i < len(gesture) else gesture[-1]
            cmds = ("designer.record",) if i in (0, len(gesture)) else ()
            yield Frame(seq=i, t=100.0 + i / 60.0, commands=cmds, pucks=(Puck(2, x, y, 0.0),))
            i += 1
    it = frames()
    for _ in range(len(gesture)):
        stage.step(studio(next(it)))
    return until_trying(studio, stage, it)


def tp_round(background: bool, tmp: Path) -> tuple[float, ...]:
    from tabletop.frames import Touch
    from tabletop.plugins import touch_pose
    from tabletop.studio.pose_target import TouchPoseTarget
    cfg = validate_config({"sources": [{"kind": "scripted"}], "engines": [{
        "kind": "touch_pose", "name": "poser", "view": [90, 15], "mouse": False,
        "library": str(tmp)}]}, "bench.yaml", ROOT)
    engine = touch_pose.build(cfg["engines"][0], BuildContext(TABLE, 30.0, cfg, ROOT))
    studio = Studio([TouchPoseTarget(engine, background=background)], countdown_s=0.0)
    core = engine.core
    hand = core.camera.table(core._points(core.output)[core._np + 3])    # the right hand
    n = int(3.0 * 30)                   # a 3 s take: the most frames an action keeps (90)

    def frames():
        i = 0
        while True:
            u = min(i, n) / n
            xy = hand + np.array([0.06 * np.sin(np.pi / 2 * u), 0.10 * u])
            cmds = ("designer.record",) if i in (0, n) else ()
            yield Frame(seq=i, t=100.0 + i / 30.0, commands=cmds,
                        touches=(Touch(1, float(xy[0]), float(xy[1])),) if i <= n else ())
            i += 1
    it = frames()
    for _ in range(n):
        engine.step(studio(next(it)))
    out = until_trying(studio, engine, it, period=1 / 30)    # paced as the loop at 30 Hz
    engine.close()
    return out


def main() -> None:
    check_flags("studio", sys.argv[1:])
    runs = {"pm_in_tick": (pm_round, False), "pm_worker": (pm_round, True),
            "mop_in_tick": (mop_round, False), "mop_worker": (mop_round, True),
            "touch_pose_in_tick": (tp_round, False), "touch_pose_worker": (tp_round, True)}
    got: dict[str, list[tuple[float, ...]]] = {k: [] for k in runs}
    with tempfile.TemporaryDirectory() as tmp:
        for r in range(ROUNDS):
            for name, (fn, background) in runs.items():
                got[name].append(fn(background, Path(tmp) / f"{name}{r}"))
    figures = {}
    for name, rows in got.items():
        a = np.array(rows) * 1e3
        for k, what in ((0, "stop_tick_wall"), (1, "worst_tick_until_playing_wall"),
                        (2, "stop_tick_cpu"), (3, "worst_tick_until_playing_cpu")):
            figures[f"{name}_{what}_ms_median"] = round(float(np.median(a[:, k])), 2)
            figures[f"{name}_{what}_ms_max"] = round(float(a[:, k].max()), 2)
    figures["rounds"] = ROUNDS
    figures["pm_take_samples"] = 2400
    emit("studio", figures, {"pm_worker_worst_tick_until_playing_wall_ms_max": 16.7,
                             "mop_worker_worst_tick_until_playing_wall_ms_max": 16.7,
                             "touch_pose_worker_worst_tick_until_playing_wall_ms_max": 33.3})


if __name__ == "__main__":
    main()
