"""Gallery soak: the kiosk left alone in real time, watched from outside its processes.

``--minutes M`` (default 20): the shipped configuration with every engine on (the lover
reacting through the 1280x720 synthetic camera, a MOP engine following a performer puck, a
touch-pose figure with physics, the studio, the recorder, the kiosk with status file and
heartbeat, a ``tuio`` sink, a snapshot a minute) runs as ``tabletop run --kiosk --headless``.
``--restarts N`` (default 0; the drill): the same installation with a ``fault`` engine crashing
each start ``CRASH_AFTER_S`` after its first step (every fifth start stalls instead), until
the supervisor has made N restarts.

Sampled every ``--every-s`` (20 s) from ``/proc``: the supervisor's and the running
installation's resident memory, open file descriptors and threads, the processes under the
supervisor (the installation and its warm spares), and the bytes of every file the
installation writes (logs, crash log, recordings, snapshots). Reported: first and last sample
after ``--warmup-s`` and their growth, and the installation's resident-memory slope (KB/s,
least squares) over the second half of the run, not before ``--settle-s``: the warm-up's growth
levels off by then (the scripted pucks' ``HISTORY_S`` of past, the drawing caches' 4096
colours and shapes, the loop's and recorder's bounded deques, the heap's first arenas: about
20 KB/s over 2-5 min, 9 KB/s over 5-8 min), steady growth does not, and 1 KB/s is 1.2 GB over a
two-week exhibition (the heap grows in steps of 0.5-2 MB: a window of 8 min, the default
20-minute run's, reads one step as 1-4 KB/s). Measured over 30 min: the glibc heap grew to
~600 s and stayed (0.3 KB/s over 900-1660 s); its 26-30 MB free is the frames' working space
(``malloc_trim`` gave back 16 MB, back within two minutes), Python's own arenas flat from 300 s.
Budgets: a supervisor that does not grow (fds, threads, processes within 0 and memory within 5 MB
over a drill), the installation's memory within 20 MB and fds/threads within 0 after the warm-up,
its slope within ``SLOPE_KB_S``, and no restart outside a drill (each config edit applied is
a rebuild, not a restart). Not part of ``make test`` (minutes).
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import numpy as np  # noqa: E402
import yaml  # noqa: E402

from bench.common import emit  # noqa: E402
from tracking.visitor import HISTORY_S  # noqa: E402

CRASH_AFTER_S = 2.0
SLOPE_KB_S = 1.0   # KB/s over the second half: 1.2 GB over two weeks at the budget
G = ROOT / "examples" / "mop" / "gestures"


def soak_config(restarts: int) -> dict:
    """The shipped config.yaml with every engine, studio, recorder, kiosk and sinks on."""
    cfg = yaml.safe_load((ROOT / "config.yaml").read_text())
    cam = cfg["sources"][0]
    cam["performers"] = [{"puck": 3, "home": [0.75, 0.35],
                          "gestures": [str(G / "circle.csv"), str(G / "zigzag.csv")]}]
    lover = cfg["engines"][0]
    lover["behavior"] = str(ROOT / lover["behavior"])
    lover["designer"] = {"enabled": True, "library": "lib", "main_puck": 1, "react_puck": 2}
    cfg["engines"] += [
        {"kind": "mop", "name": "mop", "rate_hz": 30,
         "performers": [{"name": "hand", "inputs": [{"kind": "puck", "id": 3}]}],
         "characters": [{"name": "lizard", "kind": "creature", "performer": "hand",
                         "at": [0.85, 0.25], "actions": [
                             {"name": "circle", "template": str(G / "circle.csv"),
                              "motion": "curl"},
                             {"name": "zigzag", "template": str(G / "zigzag.csv"),
                              "motion": "wag"}]}]},
        {"kind": "touch_pose", "name": "poser", "height": 0.3, "physics": True},
    ]
    if restarts:
        cfg["engines"].append({"kind": "fault", "faults": [
            {"start": k, "after_s": CRASH_AFTER_S, "kind": "stall" if k % 5 == 4 else "crash"}
            for k in range(restarts + 1)]})
    cfg["sinks"] = [{"kind": "tuio", "host": "127.0.0.1", "port": 3333}]
    cfg["recorder"] = {"enabled": True, "folder": "sessions"}
    cfg["view"].update({"snapshot_every_s": 60})
    cfg["studio"] = {"enabled": True}
    cfg["kiosk"] = {"enabled": True, "stall_s": 2, "backoff_s": [0.1, 0.4],
                    "heartbeat": {"enabled": True, "host": "127.0.0.1", "port": 9}}
    return cfg


def children(pid: int) -> list[int]:
    """The processes whose parent is ``pid``."""
    out = []
    for d in os.listdir("/proc"):
        if d.isdigit():
            try:
                with open(f"/proc/{d}/stat") as f:
                    if int(f.read().rsplit(")", 1)[1].split()[1]) == pid:
                        out.append(int(d))
            except (OSError, IndexError, ValueError):
                pass
    return out


def probe(pid: int) -> dict | None:
    """Resident MB, open fds and threads of ``pid``; None once it has gone."""
    try:
        with open(f"/proc/{pid}/status") as f:
            status = dict(line.split(":", 1) for line in f if ":" in line)
        return {"rss_mb": round(int(status["VmRSS"].split()[0]) / 1024, 2),   # (for the slope)
                "fds": len(os.listdir(f"/proc/{pid}/fd")),
                "threads": int(status["Threads"]), "state": status["State"].split()[0]}
    except (OSError, KeyError):
        return None


def running(sup: int, folder: Path) -> int | None:
    """The installation the supervisor runs: the pid of its status file when that is the
    supervisor's child (a spare that took over keeps the spare's environment), else its child
    that is not a waiting spare (before the first status)."""
    kids = children(sup)
    try:
        pid = json.loads((folder / "status.json").read_text()).get("pid")
    except (OSError, ValueError, AttributeError):
        pid = None
    if pid in kids:
        return pid
    for pid in kids:
        try:
            env = open(f"/proc/{pid}/environ", "rb").read()
        except OSError:
            continue
        if b"TABLETOP_WAIT_GO=1" not in env.split(b"\0"):
            return pid
    return None


def written(folder: Path) -> dict[str, int]:
    """Bytes per kind of file the installation writes under ``folder``."""
    out: dict[str, int] = {}
    for p in folder.rglob("*"):
        if p.is_file() and p.name != "config.yaml":
            kind = p.parent.name if p.parent != folder else p.name
            out[kind] = out.get(kind, 0) + p.stat().st_size
    return out


def rss_slope_kb_s(samples: list[dict], settle_s: float, who: str = "installation") -> float:
    """Least-squares slope (KB/s) of ``who``'s resident memory over the second half of the
    run's samples (by time), none before ``settle_s``; nan with fewer than three samples."""
    pts = [(s["t_s"], s[who]["rss_mb"]) for s in samples if s.get(who)]
    if not pts:
        return float("nan")
    half = [p for p in pts if p[0] >= max(pts[-1][0] / 2, settle_s)]
    if len(half) < 3:
        return float("nan")
    t, mb = np.array(half, dtype=float).T
    return round(float(np.polyfit(t, mb, 1)[0]) * 1024, 3)


def crashes(folder: Path) -> int:
    log = folder / "logs" / "crashes.log"
    if not log.exists():
        return 0
    return sum(1 for line in log.read_text(errors="replace").splitlines()
               if line.startswith("=== "))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--minutes", type=float, default=20.0)
    ap.add_argument("--restarts", type=int, default=0)
    ap.add_argument("--every-s", type=float, default=20.0)
    ap.add_argument("--warmup-s", type=float, default=120.0)
    ap.add_argument("--settle-s", type=float, default=HISTORY_S + 120.0,
                    help="the memory slope's window starts no earlier (s)")
    ap.add_argument("--keep", help="folder to run in and keep (default: a temporary one)")
    a = ap.parse_args()
    if a.keep:
        Path(a.keep).mkdir(parents=True, exist_ok=True)
        soak(a, Path(a.keep))
    else:
        with tempfile.TemporaryDirectory(prefix="tabletop-soak-") as d:
            soak(a, Path(d))


def soak(a: argparse.Namespace, folder: Path) -> None:
    """Run the kiosk in ``folder`` and print the result (see the module docstring)."""
    (folder / "config.yaml").write_text(yaml.safe_dump(soak_config(a.restarts)))
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    sup = subprocess.Popen([sys.executable, "-m", "tabletop", "run", "--config",
                            str(folder / "config.yaml"), "--kiosk", "--headless"],
                           cwd=ROOT, env=env, stdout=subprocess.DEVNULL,
                           stderr=subprocess.DEVNULL)
    t0, samples = time.monotonic(), []
    end = t0 + a.minutes * 60.0
    try:
        while time.monotonic() < end and sup.poll() is None:
            time.sleep(a.every_s)
            inst = running(sup.pid, folder)
            kids = children(sup.pid)
            samples.append({"t_s": round(time.monotonic() - t0), "supervisor": probe(sup.pid),
                            "installation": probe(inst) if inst else None,
                            "processes": len(kids),
                            "zombies": sum(1 for k in kids if (probe(k) or {}).get("state")
                                           == "Z"),
                            "crashes": crashes(folder), "written": written(folder)})
            print(samples[-1], file=sys.stderr, flush=True)
            if a.restarts and samples[-1]["crashes"] >= a.restarts:
                break
    finally:
        sup.send_signal(signal.SIGTERM)
        code = sup.wait(60)
    after = [s for s in samples if s["t_s"] >= a.warmup_s and s["installation"]] or samples
    first, last = after[0], after[-1]

    def growth(who: str, key: str) -> float:
        if not first[who] or not last[who]:
            return float("nan")
        return round(last[who][key] - first[who][key], 1)

    figures = {
        "minutes": round((time.monotonic() - t0) / 60, 1), "restarts": crashes(folder),
        "exit_status": code, "first": first, "last": last,
        "supervisor_rss_growth_mb": growth("supervisor", "rss_mb"),
        "supervisor_fds_growth": growth("supervisor", "fds"),
        "supervisor_threads_growth": growth("supervisor", "threads"),
        "processes_growth": last["processes"] - first["processes"],
        "max_zombies": max(s["zombies"] for s in samples),
        "stale_temporaries": len(list(folder.glob(".*.tmp"))),   # left by a crash mid-write
        "crash_log_bytes": sum(p.stat().st_size for p in folder.glob("logs/crashes.log*")),
    }
    budgets = {"supervisor_rss_growth_mb": 5.0, "supervisor_fds_growth": 0,
               "supervisor_threads_growth": 0, "processes_growth": 0, "max_zombies": 0,
               "stale_temporaries": 1, "crash_log_bytes": 6_000_000}
    if not a.restarts:
        figures.update({"installation_rss_growth_mb": growth("installation", "rss_mb"),
                        "installation_rss_slope_kb_s": rss_slope_kb_s(samples, a.settle_s),
                        "installation_fds_growth": growth("installation", "fds"),
                        "installation_threads_growth": growth("installation", "threads")})
        budgets.update({"restarts": 0, "installation_rss_growth_mb": 20.0,
                        "installation_rss_slope_kb_s": SLOPE_KB_S, "installation_fds_growth": 0,
                        "installation_threads_growth": 0})
    figures["folder"] = str(folder) if a.keep else None
    emit("gallery_soak", figures, budgets)


if __name__ == "__main__":
    main()
