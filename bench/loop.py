"""Whole-loop benchmark: the installation with its 1280x720 view, headless (SDL's dummy driver)
and in a real X window (a private Xvfb, see bench/xwindow.py; skipped with a reason when none can
be had).

Configurations: the scripted visitor straight to the view; the shipped config.yaml (synthetic
camera -> marker detection -> tracker -> one reactor -> view); and the synthetic camera with four
Puppet Master reactors (one reacting to another), the DESIGN.md whole-loop case.

For each configuration and display: the loop unpaced (as fast as it can tick: ticks per second)
and paced at 60 Hz (per-stage milliseconds, median and p99, capture-to-render latency).
Configurations run interleaved in rounds so drifting machine speed favours none.
Budgets (DESIGN.md): >= 60 ticks/s; capture-to-render p99 <= 15 ms.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402

from bench.common import emit  # noqa: E402
from bench.xwindow import xvfb  # noqa: E402
from tabletop.app import build_live  # noqa: E402
from tabletop.config import load_config, validate_config  # noqa: E402
from tabletop.loop import LoopStats  # noqa: E402
from tabletop.recorder import jsonable  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
VIEW = {"headless": True, "size": [1280, 720], "overlay": True}


def configs() -> dict[str, dict]:
    out = {"scripted_view": validate_config(
        {"sources": [{"kind": "scripted", "pucks": [1, 2]}], "view": VIEW}, "bench", ROOT)}
    default = load_config(ROOT / "config.yaml")
    default["view"] = dict(default["view"], headless=True, size=[1280, 720])
    out["default_config"] = default
    lib = ROOT / "behaviors" / "library"
    reactors = [
        {"kind": "puppet_master", "name": "lover", "behavior": str(lib / "lover"), "main": {"puck": 1}},
        {"kind": "puppet_master", "name": "bully", "behavior": str(lib / "bully"), "main": {"puck": 2}},
        {"kind": "puppet_master", "name": "stalker", "behavior": str(lib / "stalker"),
         "main": {"puck": 1}},
        {"kind": "puppet_master", "name": "afraid", "behavior": str(lib / "afraid"),
         "main": {"character": "lover"}},
    ]
    out["synthetic_camera_4_reactors"] = validate_config(
        {"sources": jsonable(default["sources"]), "engines": reactors, "view": VIEW}, "bench", ROOT)
    return out


def measure(cfg: dict, seconds: float, paced: bool, warmup: float = 1.0,
            display: str | None = None) -> dict[str, float]:
    """Run the installation for ``warmup + seconds``; figures are of the last ``seconds`` only
    (steady state: the camera's phase lock and the caches have settled). With ``display`` the
    view opens a real window on that X display, else it runs on SDL's dummy driver."""
    if display is None:
        os.environ["SDL_VIDEODRIVER"] = "dummy"
    else:
        os.environ["SDL_VIDEODRIVER"] = "x11"
        os.environ["DISPLAY"] = display
        cfg = dict(cfg, view=dict(cfg["view"], headless=False))
    inst = build_live(cfg, headless=display is None, stats=LoopStats(window=100_000))
    inst.loop.paced = paced
    ticks = inst.loop.run(seconds=warmup + seconds)
    st = inst.loop.stats
    times = np.asarray(st.tick_times)
    steady = times >= times[0] + warmup
    n = int(steady.sum())
    fig = {"ticks": n, "ticks_per_s": n / (times[-1] - times[steady][0])}
    for stage, d in st.samples.items():
        if d:
            a = np.asarray(d)[-n:] * 1e3
            fig[f"{stage}_median_ms"] = float(np.median(a))
            fig[f"{stage}_p99_ms"] = float(np.percentile(a, 99))
    return fig


def main() -> None:
    cfgs = configs()
    rounds, seconds = 2, 3.0
    load0 = os.getloadavg()[0]
    results: dict[str, dict[str, list[float]]] = {}
    figures: dict[str, object] = {}
    with xvfb((1280, 720)) as display:
        displays = {"dummy": None}
        if display is None:
            figures["x11_skipped"] = xvfb.reason
        else:
            displays["x11"] = display
        for _ in range(rounds):
            for name, cfg in cfgs.items():
                for driver, disp in displays.items():
                    for paced in (False, True):
                        key = f"{driver}.{name}_{'paced60' if paced else 'unpaced'}"
                        for k, v in measure(cfg, seconds, paced, display=disp).items():
                            results.setdefault(key, {}).setdefault(k, []).append(v)
    for key, figs in results.items():
        for k, vals in figs.items():
            figures[f"{key}.{k}"] = float(np.median(vals))
    figures["load_average_1min_start_end"] = [load0, os.getloadavg()[0]]
    budgets = {"*_unpaced.ticks_per_s": ">= 60", "*_paced60.capture_age_p99_ms": "<= 15"}
    emit("loop", figures, budgets)


if __name__ == "__main__":
    main()
