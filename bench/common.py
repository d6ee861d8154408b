"""Shared helpers for the benchmarks: machine description, percentiles, one-line JSON output.

Every benchmark prints exactly one single-line JSON object as the last line of stdout, with its
figures (units in their names), the budget for each, and the machine it ran on.
"""

from __future__ import annotations

import json
import os
import platform
import sys
import time
from importlib import metadata
from typing import Any, Callable, Sequence

import numpy as np

PACKAGES = ("numpy", "scipy", "opencv-contrib-python-headless", "pygame-ce", "PyWavelets",
            "python-osc", "pyserial", "numba")


def machine() -> dict[str, Any]:
    """This machine and the library versions the figures were measured with."""
    versions = {}
    for name in PACKAGES:
        try:
            versions[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            pass
    return {"python": platform.python_version(), "platform": platform.platform(),
            "processor": platform.machine(), "cpus": os.cpu_count(), "packages": versions}


def stats_ms(samples_s: Sequence[float]) -> dict[str, float]:
    """Median, p99 and mean of durations given in seconds, returned in milliseconds."""
    a = np.asarray(samples_s, dtype=float) * 1e3
    return {"median_ms": float(np.median(a)), "p99_ms": float(np.percentile(a, 99)),
            "mean_ms": float(a.mean())}


def interleaved(configs: dict[str, Callable[[], None]], rounds: int,
                cpu: dict[str, list[float]] | None = None) -> dict[str, list[float]]:
    """Time each named callable once per round, in turn (A B A B ...), returning seconds each.

    Interleaving keeps a drifting machine speed from favouring whichever runs first. With
    ``cpu`` (a dict to fill), the calling thread's CPU seconds of each call are kept too: on a
    machine shared with other work they leave out the time the thread waited to be scheduled.
    """
    out: dict[str, list[float]] = {k: [] for k in configs}
    if cpu is not None:
        cpu.update({k: [] for k in configs})
    for _ in range(rounds):
        for name, fn in configs.items():
            c0 = time.thread_time()
            t0 = time.perf_counter()
            fn()
            out[name].append(time.perf_counter() - t0)
            if cpu is not None:
                cpu[name].append(time.thread_time() - c0)
    return out


def emit(name: str, figures: dict[str, Any], budgets: dict[str, Any]) -> None:
    """Print the benchmark's result as one JSON line (the last line of stdout)."""
    print(json.dumps({"bench": name, "figures": figures, "budgets": budgets,
                      "machine": machine()}, separators=(",", ":"), default=float))
    sys.stdout.flush()
