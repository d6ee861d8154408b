"""Library behaviour loads: does a hot reload or a studio pick stall the tick that triggers it?

For a demonstration of 80 s and of 600 s (the lover and the stalker, saved in turn), times the
tick of a hot reload (:class:`~tabletop.studio.reloader.BehaviorReloader`: the change seen) and
of a studio pick (``PuppetMasterTarget.use``), read and trained within the tick vs in the
worker, and the tick that plays the worker's behaviour; median of 5, milliseconds of wall time
(the worker competes for a core: the worker figures carry that wait).
Run: ``OPENBLAS_NUM_THREADS=1 python -m bench.reload_tick``.
"""

from __future__ import annotations

import statistics
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from bench.common import check_flags  # noqa: E402
from behaviors.puppet_master import designers  # noqa: E402
from tabletop import library
from tabletop.config import validate_config
from tabletop.frames import Frame, Puck
from tabletop.plugins import puppet_master as pm
from tabletop.registry import BuildContext
from tabletop.studio.reloader import BehaviorReloader
from tabletop.studio.targets import PuppetMasterTarget

ROUNDS = 5


def _engine(tmp: Path, folder: Path, designer: dict | None = None):
    e = {"kind": "puppet_master", "name": "pet", "behavior": str(folder), "main": {"puck": 1}}
    if designer:
        e["designer"] = designer
    cfg = validate_config({"sources": [{"kind": "scripted"}], "engines": [e]}, "t.yaml", tmp)
    return pm.build(cfg["engines"][0], BuildContext((1.2, 0.8), 60.0, cfg, tmp))


def _ms(f) -> float:
    t0 = time.perf_counter()
    f()
    return (time.perf_counter() - t0) * 1e3


def main() -> None:
    check_flags("reload_tick", sys.argv[1:])
    frame = Frame(seq=0, t=1.0, pucks=(Puck(1, 0.4, 0.3, 0.0),))
    for secs in (80, 600):
        tmp = Path(tempfile.mkdtemp())
        demos = [designers.demonstrate(k, seconds=secs) for k in ("lover", "stalker")]
        folder = library.save_behavior(tmp / "lib", "x", demos[0], {})
        library.save_behavior(tmp / "lib", "y", demos[1], {})
        for background in (False, True):
            hook = BehaviorReloader(_engine(tmp, folder), background=background)
            hook.poller.every_s = 0.0
            t = PuppetMasterTarget(_engine(tmp, folder, {
                "enabled": True, "library": str(tmp / "lib"), "background_training": background}))
            got: dict[str, list[float]] = {"reload": [], "its swap": [], "pick": [],
                                           "its play": []}
            for i in range(ROUNDS):
                library.save_behavior(tmp / "lib", "x", demos[(i + 1) % 2], {}, replace=True)
                got["reload"].append(_ms(lambda: hook(frame)))
                if hook.worker is not None:
                    hook.worker.wait()
                    got["its swap"].append(_ms(lambda: hook(frame)))
                got["pick"].append(_ms(lambda: t.use("xy"[i % 2])))
                if t.loader is not None:
                    t.loader.wait()
                    got["its play"].append(_ms(lambda: t.between_ticks(1e9)))
            figures = ", ".join(f"{k} {statistics.median(v):.1f}" for k, v in got.items() if v)
            print(f"{secs:4d} s demonstration, {'worker' if background else 'within the tick'}: "
                  f"{figures} ms")


if __name__ == "__main__":
    main()
