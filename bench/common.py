"""Shared helpers for the benchmarks: machine description, percentiles, one-line JSON output.

Every benchmark prints exactly one single-line JSON object as the last line of stdout, with its
figures (units in their names), the budget for each, and the machine it ran on.
"""

from __future__ import annotations

import json
import math
import os
import platform
import sys
import time
from importlib import metadata
from typing import Any, Callable, Sequence

import numpy as np

try:
    import resource
except ImportError:         # not on Windows
    resource = None  # type: ignore[assignment]

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
                cpu: dict[str, list[float]] | None = None,
                switched: dict[str, list[bool]] | None = None) -> dict[str, list[float]]:
    """Time each named callable once per round, in turn (A B A B ...), returning seconds each.

    Interleaving keeps a drifting machine speed from favouring whichever runs first. With
    ``cpu`` (a dict to fill), the calling thread's CPU seconds of each call are kept too: on a
    machine shared with other work they leave out the time the thread waited to be scheduled.

    The figures go into arrays made before the first call: lists of kept floats grew the
    process by a page every ~80 calls, and the page fault (10-16 us on the development VM) hit
    whichever timed call next allocated an object (bench/puppet_master.py, real-time priority:
    72-136 of 2,000 step calls took a fault, 0-1 with the arrays).
    With ``switched`` (a dict to fill; Linux), whether the scheduler took the core from the
    call (an involuntary context switch of this thread during it) is kept per call: the
    share of calls that waited for another program, and the tail of the calls that did not.
    """
    names = list(configs)
    wall = np.zeros((len(names), rounds))
    used = np.zeros((len(names), rounds))
    taken = np.zeros((len(names), rounds), dtype=bool)
    calls = list(enumerate(configs.values()))
    thread_time, perf_counter = time.thread_time, time.perf_counter
    usage = _thread_switches if switched is not None else None
    for r in range(rounds):
        for c, fn in calls:
            s0 = usage() if usage is not None else 0
            c0 = thread_time()
            t0 = perf_counter()
            fn()
            wall[c, r] = perf_counter() - t0
            used[c, r] = thread_time() - c0
            if usage is not None:
                taken[c, r] = usage() != s0
    if cpu is not None:
        cpu.update({k: used[c].tolist() for c, k in enumerate(names)})
    if switched is not None:
        switched.update({k: taken[c].tolist() for c, k in enumerate(names)})
    return {k: wall[c].tolist() for c, k in enumerate(names)}


def _thread_switches() -> int:
    """Involuntary context switches of the calling thread so far (0 where not reported)."""
    who = getattr(resource, "RUSAGE_THREAD", None) if resource is not None else None
    return resource.getrusage(who).ru_nivcsw if who is not None else 0


def emit(name: str, figures: dict[str, Any], budgets: dict[str, Any]) -> None:
    """Print the benchmark's result as one JSON line (the last line of stdout)."""
    print(json.dumps({"bench": name, "figures": figures, "budgets": budgets,
                      "machine": machine()}, separators=(",", ":"), default=float))
    sys.stdout.flush()


def check_flags(name: str, args: Sequence[str], flags: Sequence[str] = (),
                lists: dict[str, Sequence[str]] | None = None,
                numbers: dict[str, tuple[float, float]] | None = None,
                values: dict[str, str] | None = None, positional: str = "") -> None:
    """Refuse a bench's unknown command line before minutes of measuring: ``args`` may hold
    ``flags``, ``--KEY=A,B`` with each value among ``lists[KEY]``, ``--KEY=X`` with X a
    number within ``numbers[KEY]`` (lo, hi), ``--KEY=VALUE`` for ``values[KEY]`` (its form, as
    the usage shows it: the bench reads it) and one ``positional`` argument when named;
    ``-h``/``--help`` prints the usage and exits 0, anything else exits with one line naming it,
    then the usage. Every ``bench/*.py`` script calls it first (a bench taking no argument
    too: ``--help`` ran the whole bench)."""
    lists, numbers, values = lists or {}, numbers or {}, values or {}
    options = " ".join(
        [f"[{f}]" for f in flags] + [f"[--{k}=NAME,...]" for k in lists]
        + [f"[--{k}=X]" for k in numbers] + [f"[--{k}={v}]" for k, v in values.items()]
        + ([f"[{positional}]"] if positional else []))
    usage = f"usage: python bench/{name}.py {options or '(no arguments)'}" + "".join(
        f"\n  {k}: {', '.join(v)}" for k, v in lists.items()) + "".join(
        f"\n  {k}: a number in {lo:g}..{hi:g}" for k, (lo, hi) in numbers.items())
    if {"-h", "--help"} & set(args):
        print(usage)
        sys.exit(0)
    given = [a for a in args if not a.startswith("-")]
    if len(given) > (1 if positional else 0):
        sys.exit(f"{name}: unknown argument {given[1 if positional else 0]!r}\n{usage}")
    for a in args:
        key, _, value = a.partition("=")
        if a in flags or a in given:
            continue
        if key.startswith("--") and key[2:] in values and value:
            continue
        if key.startswith("--") and key[2:] in numbers:
            lo, hi = numbers[key[2:]]
            try:
                x = float(value)
            except ValueError:
                x = math.nan
            if not lo <= x <= hi:
                sys.exit(f"{name}: {key}: expected a number in {lo:g}..{hi:g}, got {value!r}\n"
                         f"{usage}")
            continue
        if not (key.startswith("--") and key[2:] in lists and value):
            sys.exit(f"{name}: unknown argument {a!r}\n{usage}")
        bad = [v for v in value.split(",") if v not in lists[key[2:]]]
        if bad:
            sys.exit(f"{name}: {key}: unknown {bad[0]!r}\n{usage}")
