"""Cold start: seconds from ``tabletop run`` to the first frame drawn, as a gallery boots.

Each round starts ``python -m tabletop run --headless`` for: the shipped config.yaml, the same
as a kiosk (``--kiosk``: the supervisor validates the config, then starts the installation and
its warm spares), examples/mop.yaml and examples/touch_pose.yaml, interleaved (A B C D A B C
D ...). Measured: launch -> ``READY=1`` (the first completed frame, systemd's notify protocol
on a socket of this script's), the CPU seconds of the process and its waited-for children, and
for the kiosk the supervisor's resident memory and CPU seconds at READY (what it holds for
weeks). ``--root`` runs another checkout of the repository (its own kernel caches) with this
Python. Timing figures carry the machine's load; CPU seconds less so.
"""

from __future__ import annotations

import argparse
import os
import socket
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import yaml  # noqa: E402

from bench.common import emit  # noqa: E402


def variants(root: Path, folder: Path) -> dict[str, list[str]]:
    """Name -> ``tabletop run`` arguments."""
    cfg = yaml.safe_load((root / "config.yaml").read_text())
    cfg["engines"][0]["behavior"] = str(root / cfg["engines"][0]["behavior"])
    cfg["kiosk"] = {"heartbeat": {"enabled": False}}
    kiosk = folder / "config.yaml"
    kiosk.write_text(yaml.safe_dump(cfg))
    return {"shipped": ["--config", str(root / "config.yaml")],
            "shipped_kiosk": ["--config", str(kiosk), "--kiosk"],
            "mop": ["--config", str(root / "examples" / "mop.yaml")],
            "touch_pose": ["--config", str(root / "examples" / "touch_pose.yaml")]}


def proc_figures(pid: int) -> tuple[float, float]:
    """(resident MB, CPU seconds so far) of a running process."""
    with open(f"/proc/{pid}/status") as f:
        rss = next(int(line.split()[1]) for line in f if line.startswith("VmRSS")) / 1024
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return rss, (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def one(root: Path, args: list[str], folder: Path) -> dict[str, float]:
    path = folder / f"notify-{time.monotonic_ns()}.sock"
    sock = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
    sock.bind(str(path))
    sock.settimeout(0.5)
    env = dict(os.environ, NOTIFY_SOCKET=str(path), OPENBLAS_NUM_THREADS="1")
    t0 = time.perf_counter()
    p = subprocess.Popen([sys.executable, "-m", "tabletop", "run", "--headless", "--seconds",
                          "1", *args], cwd=root, env=env, stdout=subprocess.DEVNULL,
                         stderr=subprocess.DEVNULL)
    out: dict[str, float] = {}
    try:
        while True:
            try:
                if b"READY=1" in sock.recv(4096):
                    break
            except socket.timeout:
                if p.poll() is not None or time.perf_counter() - t0 > 300:
                    raise RuntimeError(f"{args}: no first frame (exit status {p.returncode})")
        out["ready_s"] = time.perf_counter() - t0
        if "--kiosk" in args:
            out["supervisor_rss_mb"], out["supervisor_cpu_s"] = proc_figures(p.pid)
    finally:
        sock.close()
        path.unlink()
        _, status, usage = os.wait4(p.pid, 0)
        p.returncode = os.waitstatus_to_exitcode(status)
    out["cpu_s"] = usage.ru_utime + usage.ru_stime
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--root", type=Path, default=ROOT)
    ap.add_argument("--only", help="comma-separated variant names")
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as d:
        runs = variants(a.root.resolve(), Path(d))
        if a.only:
            runs = {k: v for k, v in runs.items() if k in a.only.split(",")}
        got: dict[str, list[dict[str, float]]] = {k: [] for k in runs}
        for _ in range(a.rounds):
            for name, args in runs.items():
                got[name].append(one(a.root.resolve(), args, Path(d)))
                print(name, got[name][-1], file=sys.stderr, flush=True)
    figures = {name: {key: round(statistics.median(r[key] for r in rs), 2) for key in rs[0]}
               for name, rs in got.items()}
    figures["root"] = str(a.root)
    figures["load_1min"] = os.getloadavg()[0]
    emit("cold_start", figures, {})


if __name__ == "__main__":
    main()
