"""Touch-pose control, this version against an older one: CPU ms per whole 30 fps frame,
interleaved.

The older version (a commit, by default the one before the speed work, or a folder holding such
a tree) is loaded in the same process under another package name, so both run the same scripted
frames in turn (old, new, old, new ...) on the same machine state: posing with 1 and 3 touches
(hands and a foot circling) and an action frame (the wave running), each with tracking and
physics. Figures are thread CPU time (the machine may be shared), median and p99, and the
new/old ratio of each. Usage: ``bench/touch_pose_compare.py [COMMIT_OR_FOLDER]``.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import tempfile
import time
import timeit
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from bench.common import check_flags, emit, stats_ms  # noqa: E402
from bench.touch_pose import Driver  # noqa: E402
from behaviors.touch_pose.engine import TouchPose, learned_models  # noqa: E402

BEFORE = "45e4b539daeb5938bfb5296e51c221145ca73e1d"
ROUNDS = 400
ALIAS = "behaviors_before"


class Unavailable(Exception):
    """The older version cannot be had (a clone without its history, a wrong argument)."""


def load_older(source: str, into: Path):
    """The older version's engine module, from a commit of this repository or a folder."""
    tree = Path(source)
    if not tree.is_dir():
        tree = into / "tree"
        tree.mkdir()
        try:
            archive = subprocess.run(["git", "-C", str(ROOT), "archive", source, "behaviors"],
                                     check=True, capture_output=True).stdout
        except (OSError, subprocess.CalledProcessError) as exc:
            said = getattr(exc, "stderr", b"") or b""
            raise Unavailable(f"{source}: not a folder, nor a commit of {ROOT} "
                              f"({said.decode(errors='replace').strip() or exc})") from None
        subprocess.run(["tar", "-x", "-C", str(tree)], input=archive, check=True)
    for f in (tree / "behaviors").rglob("*.py"):
        out = into / ALIAS / f.relative_to(tree / "behaviors")
        out.parent.mkdir(parents=True, exist_ok=True)
        out.write_text(re.sub(r"\bbehaviors\.", f"{ALIAS}.", f.read_text()))
    # the older models module hashes its own sources by their paths beside the package
    # (behaviors/...), which the renamed copy does not have: the original tree is linked there
    if not (into / "behaviors").exists():
        (into / "behaviors").symlink_to((tree / "behaviors").resolve(), target_is_directory=True)
    sys.path.insert(0, str(into))
    return __import__(f"{ALIAS}.touch_pose.engine", fromlist=["TouchPose"])


def main() -> None:
    check_flags("touch_pose_compare", sys.argv[1:], positional="COMMIT_OR_FOLDER")
    source = sys.argv[1] if len(sys.argv) > 1 else BEFORE
    folder = tempfile.TemporaryDirectory()  # the older code and a cache folder, for the run
    os.environ["XDG_CACHE_HOME"] = folder.name  # not the user's cache
    try:
        old = load_older(source, Path(folder.name))
    except Unavailable as exc:
        folder.cleanup()
        if len(sys.argv) > 1:               # asked for: a wrong argument
            sys.exit(f"bench/touch_pose_compare.py: {exc}")
        # the default older commit is not in this copy (e.g. a shallow clone): skipped
        emit("touch_pose_compare", {"skipped": str(exc)}, {})
        return
    versions = {"before": (old.learned_models(), old.TouchPose, old),
                "after": (learned_models(), TouchPose, sys.modules[TouchPose.__module__])}
    configs, drivers = {}, []
    for label, (models, engine, module) in versions.items():
        for name, parts in (("posing_1_touch", ("right_hand",)),
                            ("posing_3_touches", ("right_hand", "left_hand", "left_foot")),
                            ("action", ())):
            d = Driver(models, parts, engine=engine)
            drivers.append(d)
            d.e.step(0.0, d.touches())
            configs[f"frame_{name}_{label}"] = _frame(d, models, name == "action", module)
    for fn in configs.values():
        for _ in range(20):
            fn()  # warm up
    cpu = {k: [] for k in configs}
    for _ in range(ROUNDS):
        for k, fn in configs.items():
            c0 = time.thread_time()
            fn()
            cpu[k].append(time.thread_time() - c0)
    figures = {f"{k}_cpu_{m}": round(v, 4) for k, s in cpu.items()
               for m, v in stats_ms(s).items() if m != "mean_ms"}
    for name in ("posing_1_touch", "posing_3_touches", "action"):
        for m in ("median", "p99"):
            figures[f"frame_{name}_after_over_before_{m}"] = round(
                figures[f"frame_{name}_after_cpu_{m}_ms"]
                / figures[f"frame_{name}_before_cpu_{m}_ms"], 3)
    figures["before"] = source
    figures["load_average_1min"] = round(os.getloadavg()[0], 2)
    # the machine's speed while measuring: a 3x3 matrix-vector product (about 1 us when idle)
    figures["reference_matvec_us"] = round(min(timeit.repeat(
        "a @ v", setup="import numpy as np; a = np.eye(3); v = np.ones(3)",
        number=20000, repeat=5)) / 20000 * 1e6, 3)
    for d in drivers:
        d.e.close()
    folder.cleanup()
    emit("touch_pose_compare", figures,
         {f"frame_{n}_after_cpu_p99_ms": 5.0 for n in ("posing_1_touch", "posing_3_touches",
                                                       "action")})


def _frame(d: Driver, models, action: bool, module):
    wave = next(a for a in models.actions if a.name == "wave")

    def run() -> None:
        if action:
            if d.e.mode != "action":
                d.e.mode = "action"
                d.e.clock = module.ActionClock(wave, wave.start + 0.1)
                d.e.action_base = (d.e.base.copy(), d.e.yaw)
            d.e.step(d.advance(), {})
        else:
            d.e.step(d.advance(), d.touches())
            d.e.mode = "posing"
    return run


if __name__ == "__main__":
    main()
