"""Config-edit soak: the gallery kiosk's config.yaml edited on disk, edit after edit, while the
kiosk runs (``watch_config`` applies each edit by rebuilding the installation).

The gallery soak's configuration (:func:`bench.gallery_soak.soak_config`: the lover through
the 1280x720 synthetic camera in designer mode, MOP, touch-pose with physics, studio, recorder,
kiosk with status file and heartbeat, a ``tuio`` sink) runs in this process in the real
:class:`~tabletop.kiosk.runner.Runner` (what ``tabletop run --kiosk --no-supervisor`` runs),
headless, in real time. ``--edits N`` (default 70, within a bench's 300 s; ``--edits 110``
for the longer soak) times the file is rewritten as a technician would (in turn: the lover's
colour, the kiosk's ``idle_s``, the MOP character's place, the snapshot period), each time
waiting until the rebuilt installation has made ``--ticks`` ticks (past the loop's second
``gc.freeze``). After each, with a collection made:
resident memory (MB), open file descriptors, threads, Python objects the collector tracks
(and the frozen ones). ``--trace-from K`` starts :mod:`tracemalloc` at edit K and prints to
stderr what grew between edit 20 (or K if later) and the last edit, top by traceback, and the
object types whose counts grew. ``--plot FILE.png``: resident MB per edit.

Reported: resident MB per applied edit (least squares) over edits 1-20 and over the last 50,
the C heap in use per edit over the last 50, fds and threads at edit 1 and at the last.
Budgets: the heap in use within 0.05 MB an edit over the last 50 (a leak of the installation
grows it; the resident memory also counts the allocator's free space, which a rebuild
fragments), fds within 1 (a file open at the moment of the sample: 14 or 15 throughout),
threads growth 0. Not part of ``make test`` (70 edits: about 4 min).

Measured (110 edits, two runs): resident 376-383 MB at edit 20, 392-396 MB at edit 110,
0.08-0.26 MB an edit over the last 50 (0.39-0.82 over the first 20); the heap in use flat
(147.1 -> 145.9 MB, edit 20 -> 110), its free space 33 -> 66 MB; Python's allocated blocks
827k -> 858k, levelled by edit 40 (+5k over the last 70: each recording's two paths the
running recorder knows of its folder, ``tabletop.drawing.raster``'s views, capped at 64);
threads 14 and fds 14-15 throughout: no leak, the resident growth is the allocator's free
space. Tried: the environment's ``MALLOC_ARENA_MAX=2`` (fewer heaps to fragment), free space
26 -> 37 MB, resident 374.8 -> 389.4 MB (edit 20 -> 110, 0.14 MB an edit over the last 50):
no clear gain. ``--trace-from`` makes each edit ~10x slower (39 s against 3 s here).
"""

from __future__ import annotations

import argparse
import collections
import ctypes
import gc
import os
import sys
import tempfile
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import numpy as np  # noqa: E402
import yaml  # noqa: E402

from bench.common import emit  # noqa: E402
from bench.gallery_soak import soak_config  # noqa: E402
from tracking.scenes import wait_for as wait  # noqa: E402

HEAP_MB_PER_EDIT = 0.05   # budget: the C heap in use, MB an applied edit over the last 50


def edited(cfg: dict, k: int) -> dict:
    """``cfg`` (the running one) with the ``k``-th technician's edit: four kinds in turn, each
    switching its value, so every edit changes the running configuration."""
    cfg = yaml.safe_load(yaml.safe_dump(cfg))
    kind, side = k % 4, (k // 4) % 2
    if kind == 0:
        cfg["engines"][0]["color"] = [254, 121, 79] if side else [81, 201, 254]
    elif kind == 1:
        cfg["kiosk"]["idle_s"] = 47 if side else 61
    elif kind == 2:
        cfg["engines"][1]["characters"][0]["at"] = [0.8, 0.3] if side else [0.84, 0.26]
    else:
        cfg["view"]["snapshot_every_s"] = 91 if side else 61
    return cfg


def write(path: Path, cfg: dict) -> None:
    """Rewrite ``path`` as an editor does (a temporary file renamed over it)."""
    tmp = path.with_name(".config.yaml.tmp")
    tmp.write_text(yaml.safe_dump(cfg))
    tmp.replace(path)


class _Mallinfo2(ctypes.Structure):
    _fields_ = [(name, ctypes.c_size_t) for name in (
        "arena", "ordblks", "smblks", "hblks", "hblkhd", "usmblks", "fsmblks", "uordblks",
        "fordblks", "keepcost")]


def heap_mb() -> dict:
    """The C heap (glibc ``mallinfo2``, MB): in use (``uordblks`` + mapped blocks) and free in
    its arenas; empty where the C library has none."""
    try:
        fn = ctypes.CDLL(None).mallinfo2
    except (OSError, AttributeError, TypeError):
        return {}
    fn.restype = _Mallinfo2
    m = fn()
    return {"heap_used_mb": round((m.uordblks + m.hblkhd) / 2**20, 2),
            "heap_free_mb": round(m.fordblks / 2**20, 2)}


def probe() -> dict:
    """This process now: resident MB, fds, threads, tracked and frozen Python objects, the
    Python allocator's blocks, the C heap."""
    gc.collect()
    with open("/proc/self/status") as f:
        status = dict(line.split(":", 1) for line in f if ":" in line)
    return {"rss_mb": round(int(status["VmRSS"].split()[0]) / 1024, 2),
            "fds": len(os.listdir("/proc/self/fd")), "threads": int(status["Threads"]),
            "objects": len(gc.get_objects()), "frozen": gc.get_freeze_count(),
            "py_blocks": sys.getallocatedblocks(), **heap_mb()}


def type_counts() -> collections.Counter:
    """Python objects the collector tracks, by type name (frozen ones included)."""
    gc.unfreeze()   # (gc.get_objects leaves the frozen generation out)
    try:
        return collections.Counter(type(o).__qualname__ for o in gc.get_objects())
    finally:
        gc.freeze()


def slope(points: list[tuple[int, float]]) -> float:
    """Least-squares MB per edit of (edit, MB) points; nan with fewer than three."""
    if len(points) < 3:
        return float("nan")
    x, y = np.array(points, dtype=float).T
    return round(float(np.polyfit(x, y, 1)[0]), 3)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--edits", type=int, default=70)
    ap.add_argument("--ticks", type=int, default=150, help="ticks of each installation")
    ap.add_argument("--trace-from", type=int, default=0, help="start tracemalloc (0: never)")
    ap.add_argument("--plot", help="PNG of resident MB per edit")
    a = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="tabletop-edits-") as d:
        run(a, Path(d))


def run(a: argparse.Namespace, folder: Path) -> None:
    """Run the kiosk in ``folder`` and edit its config (see the module docstring)."""
    import tracemalloc

    from tabletop.config import load_config
    from tabletop.kiosk.runner import Runner
    cfg = soak_config(0)
    path = folder / "config.yaml"
    write(path, cfg)
    runner = Runner(path, load_config(path), headless=True, kiosk=True)
    th = threading.Thread(target=runner.run, daemon=True)
    th.start()
    ticked = lambda inst, n: inst is not None and inst.loop.stats.ticks > n  # noqa: E731
    assert wait(lambda: ticked(runner.inst, a.ticks), 120), "the kiosk did not start"
    samples, snaps, counts = [probe()], {}, {}
    print({"edit": 0, **samples[0]}, file=sys.stderr, flush=True)
    first_trace = max(20, a.trace_from)
    t0 = time.monotonic()
    for k in range(1, a.edits + 1):
        if k == a.trace_from:
            tracemalloc.start(10)
        before = runner.inst
        cfg = edited(cfg, k)
        write(path, cfg)
        ok = wait(lambda: (i := runner.inst) is not None and i is not before
                  and ticked(i, a.ticks), 180)
        del before
        assert ok, f"edit {k} was not applied (refused: {runner.watcher.error})"
        samples.append(probe())
        if tracemalloc.is_tracing():
            samples[-1]["tracemalloc_mb"] = round(tracemalloc.get_tracemalloc_memory() / 2**20, 2)
        print({"edit": k, "t_s": round(time.monotonic() - t0), **samples[-1]}, file=sys.stderr,
              flush=True)
        if k in (first_trace, a.edits):
            counts[k] = type_counts()
            if tracemalloc.is_tracing():
                snaps[k] = tracemalloc.take_snapshot()
    runner.stop.set()
    th.join(60)
    report(a, samples, snaps, counts, first_trace)


def report(a, samples: list[dict], snaps: dict, counts: dict, first_trace: int) -> None:
    """Print what grew (stderr), plot, and emit the figures."""
    if len(snaps) == 2:
        start, end = snaps[first_trace], snaps[a.edits]
        print(f"--- tracemalloc: edit {first_trace} -> {a.edits}, top by traceback",
              file=sys.stderr)
        for st in end.compare_to(start, "traceback")[:12]:
            print(f"{st.size_diff / 1024:+.1f} KB {st.count_diff:+d} blocks", file=sys.stderr)
            for line in st.traceback.format()[-8:]:
                print("   ", line, file=sys.stderr)
    if len(counts) == 2:
        c0, c1 = counts[first_trace], counts[a.edits]
        grew = sorted(((c1[t] - c0[t], t) for t in c1 if c1[t] != c0[t]), reverse=True)
        print(f"--- object types whose counts changed, edit {first_trace} -> {a.edits}:",
              grew[:15], grew[-5:], file=sys.stderr)
    rss = [(k, s["rss_mb"]) for k, s in enumerate(samples)]
    if a.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(8, 4))
        ax.plot(*zip(*rss), marker=".")
        ax.set_xlabel("applied config edit")
        ax.set_ylabel("resident MB")
        ax.set_title("kiosk resident memory per applied config edit")
        ax.grid(True)
        fig.savefig(a.plot, dpi=90, bbox_inches="tight")
    last = samples[-1]
    figures = {
        "edits": a.edits,
        "rss_mb": {"start": samples[0]["rss_mb"], "edit_1": samples[1]["rss_mb"],
                   "edit_20": samples[min(20, a.edits)]["rss_mb"], "last": last["rss_mb"]},
        "rss_mb_per_edit_first_20": slope(rss[1:21]),
        "rss_mb_per_edit_last_50": slope(rss[-50:]),
        "fds": [samples[1]["fds"], last["fds"]], "threads": [samples[1]["threads"],
                                                             last["threads"]],
        "fds_growth": last["fds"] - samples[1]["fds"],
        "threads_growth": last["threads"] - samples[1]["threads"],
        "objects": [samples[1]["objects"] + samples[1]["frozen"],
                    last["objects"] + last["frozen"]],
        "heap_used_mb_per_edit_last_50": slope(
            [(k, s["heap_used_mb"]) for k, s in enumerate(samples) if "heap_used_mb" in s][-50:]),
        "heap_used_mb": [samples[min(20, a.edits)].get("heap_used_mb"), last.get("heap_used_mb")],
        "heap_free_mb": [samples[min(20, a.edits)].get("heap_free_mb"), last.get("heap_free_mb")],
        "py_blocks": [samples[min(20, a.edits)]["py_blocks"], last["py_blocks"]],
        "tracemalloc": a.trace_from or None,
    }
    emit("edit_soak", figures, {"heap_used_mb_per_edit_last_50": HEAP_MB_PER_EDIT,
                                "fds_growth": 1, "threads_growth": 0})


if __name__ == "__main__":
    main()
