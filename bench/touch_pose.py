"""Touch-pose control benchmark: milliseconds per 30 fps frame of each control stage.

Stages (paper 003): posing control with 1 and with 3 touches (latent-space blend, CCD IK,
action recognition), action control (time control, posture at the generalised time, IK for
secondary touches), and tracking control with physics (equations 2-4, the pybullet simulation
of equation 5, equations 6-7, feet re-fixed by IK); then whole frames with 1 and 3 touches
(posing) and during an action, and the time to learn the models and to load them from the
cache. Each stage runs on its own character fed a scripted drag; all configurations run
interleaved (A B A B ...). Budget (DESIGN.md): <= 5 ms p99 per frame in total; the paper ran
at about 30 fps.
"""

from __future__ import annotations

import math
import sys
import tempfile
import time
from importlib import metadata
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402

from bench.common import check_flags, emit, stats_ms  # noqa: E402
from behaviors.touch_pose.engine import TouchPose  # noqa: E402
from behaviors.touch_pose.models import (PREFIX, build_models, input_key,  # noqa: E402
                                         load_or_build, save)

ROUNDS = 400
DT = 1.0 / 30.0


class Driver:
    """A character with scripted fingers circling near parts; ``frame()`` advances one step."""

    def __init__(self, models, parts: tuple[str, ...], physics: bool = True,
                 engine: type = TouchPose) -> None:
        self.e = engine(azimuth=60.0, elevation=20.0, physics=physics, models=models)
        d = self.e.describe()["parts"]
        self.home = {i: np.array(d[p]) for i, p in enumerate(parts)}
        self.k = 0

    def touches(self) -> dict[int, tuple[float, float]]:
        a = 2 * math.pi * self.k / 90
        return {i: tuple(h + 0.01 * np.array([math.cos(a + i), math.sin(a + i)]))
                for i, h in self.home.items()}

    def advance(self) -> float:
        self.k += 1
        return self.k * DT


def interleaved_both(configs: dict, rounds: int) -> tuple[dict, dict]:
    """Wall and thread-CPU seconds of each callable, run in turn (A B A B ...)."""
    wall = {k: [] for k in configs}
    cpu = {k: [] for k in configs}
    for _ in range(rounds):
        for name, fn in configs.items():
            c0, w0 = time.thread_time(), time.perf_counter()
            fn()
            wall[name].append(time.perf_counter() - w0)
            cpu[name].append(time.thread_time() - c0)
    return wall, cpu


def main() -> None:
    check_flags("touch_pose", sys.argv[1:])
    t0 = time.perf_counter()
    learned = build_models()
    learn_s = time.perf_counter() - t0
    with tempfile.TemporaryDirectory() as folder:  # not the user's cache folder
        key = input_key()
        save(learned, Path(folder) / f"{PREFIX}{key[:32]}.npz", key)
        t0 = time.perf_counter()
        models, how = load_or_build(Path(folder))
        cache_s = time.perf_counter() - t0
    assert how == "cache"
    one = Driver(models, ("right_hand",))
    three = Driver(models, ("right_hand", "left_hand", "left_foot"))
    act = Driver(models, ())
    track = Driver(models, ("left_hand",))
    whole = Driver(models, ("right_hand",))
    whole3 = Driver(models, ("right_hand", "left_hand", "left_foot"))
    whole_act = Driver(models, ())
    for d in (one, three, track, whole, whole3):
        d.e.step(0.0, d.touches())
    wave = next(a for a in models.actions if a.name == "wave")
    from behaviors.touch_pose.action import ActionClock

    def start_action(d: Driver) -> None:
        d.e.mode = "action"
        d.e.clock = ActionClock(wave, wave.start + 0.1)
        d.e.action_base = (d.e.base.copy(), d.e.yaw)

    def posing(d: Driver):
        def run() -> None:
            t = d.advance()
            d.e._fingers(t, d.touches())
            d.e._posing(DT)
            d.e.mode = "posing"  # a recognised action would change the stage measured
        return run

    def action() -> None:
        if act.e.mode != "action":
            start_action(act)
        act.e._action(DT)

    def tracking() -> None:
        t = track.advance()
        track.e._fingers(t, track.touches())
        track.e.target = models.posing.blend(np.array([track.k % len(models.posing)]),
                                             np.array([1.0])).pose if track.k % 45 == 0 \
            else track.e.target
        track.e.track(DT)

    def frame_posing() -> None:
        whole.e.step(whole.advance(), whole.touches())
        whole.e.mode = "posing"

    def frame_posing_3() -> None:
        whole3.e.step(whole3.advance(), whole3.touches())
        whole3.e.mode = "posing"

    def frame_action() -> None:
        if whole_act.e.mode != "action":
            start_action(whole_act)
        whole_act.e.step(whole_act.advance(), {})

    for fn in (posing(one), posing(three), action, tracking, frame_posing, frame_posing_3,
               frame_action):
        for _ in range(20):
            fn()  # warm up
    wall, cpu = interleaved_both({"posing_1_touch": posing(one), "posing_3_touches": posing(three),
                                  "action_control": action, "tracking_physics": tracking,
                                  "frame_posing_1_touch": frame_posing,
                                  "frame_posing_3_touches": frame_posing_3,
                                  "frame_action": frame_action}, ROUNDS)
    figures = {f"{k}_wall_{m}": round(v, 4) for k, s in wall.items()
               for m, v in stats_ms(s).items()}
    figures.update({f"{k}_cpu_{m}": round(v, 4) for k, s in cpu.items()
                    for m, v in stats_ms(s).items()})
    figures["learn_models_s"] = round(learn_s, 3)
    figures["load_cached_models_s"] = round(cache_s, 3)
    drivers = (one, three, act, track, whole, whole3, whole_act)
    figures["physics_resets"] = sum(d.e.physics.resets for d in drivers)
    stages = ("posing_3_touches", "action_control", "tracking_physics")
    for clock in ("wall", "cpu"):
        figures[f"sum_of_stage_{clock}_p99_ms"] = round(
            max(figures[f"posing_3_touches_{clock}_p99_ms"],
                figures[f"action_control_{clock}_p99_ms"])
            + figures[f"tracking_physics_{clock}_p99_ms"], 4)
    figures["load_average_1min"] = round(__import__("os").getloadavg()[0], 2)
    # the machine's speed while measuring: a 3x3 matrix-vector product (about 1 us when idle)
    import timeit
    figures["reference_matvec_us"] = round(min(timeit.repeat(
        "a @ v", setup="import numpy as np; a = np.eye(3); v = np.ones(3)",
        number=20000, repeat=5)) / 20000 * 1e6, 3)
    for d in drivers:
        d.e.close()
    budgets = {f"{k}_{c}_p99_ms": 5.0 for k in ("frame_posing_1_touch", "frame_posing_3_touches",
                                                  "frame_action", "sum_of_stage")
               for c in ("wall", "cpu")}
    figures["stages"] = list(stages)
    figures["pybullet"] = metadata.version("pybullet")
    emit("touch_pose", figures, budgets)


if __name__ == "__main__":
    main()
