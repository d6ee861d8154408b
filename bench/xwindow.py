"""A real X window for the benchmarks: a private Xvfb server, installed from the Debian packages
when it is missing (as root, with apt-get), else skipped with a reason.

pygame on a real X server pays for every presented pixel (shared-memory image transfers), which
SDL's dummy driver does not: the view and the loop are measured where a visitor sees them.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import subprocess
import time
from pathlib import Path
from typing import Iterator


def ensure_xvfb() -> str | None:
    """Path of ``Xvfb``, installing the ``xvfb`` package when missing and possible; else None."""
    path = shutil.which("Xvfb")
    if path:
        return path
    if os.geteuid() != 0 or not shutil.which("apt-get"):
        return None
    env = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
    for cmd in (["apt-get", "update", "-qq"], ["apt-get", "install", "-y", "-qq", "xvfb"]):
        try:
            subprocess.run(cmd, env=env, check=True, timeout=240, stdout=subprocess.DEVNULL,
                           stderr=subprocess.DEVNULL)
        except (subprocess.SubprocessError, OSError):
            return None
    return shutil.which("Xvfb")


@contextlib.contextmanager
def xvfb(size: tuple[int, int] = (1920, 1080)) -> Iterator[str | None]:
    """Run a private Xvfb server; yields its DISPLAY (e.g. ``":57"``), or None with the reason in
    ``xvfb.reason`` when no X server can be had. The server is stopped on exit."""
    exe = ensure_xvfb()
    if exe is None:
        xvfb.reason = "Xvfb is not installed and could not be installed (needs root and apt-get)"
        yield None
        return
    proc = None
    for n in range(50 + os.getpid() % 40, 140):
        if Path(f"/tmp/.X11-unix/X{n}").exists() or Path(f"/tmp/.X{n}-lock").exists():
            continue
        proc = subprocess.Popen([exe, f":{n}", "-screen", "0", f"{size[0]}x{size[1]}x24",
                                 "-nolisten", "tcp", "-noreset"],
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        deadline = time.monotonic() + 10.0
        while time.monotonic() < deadline and proc.poll() is None:
            if Path(f"/tmp/.X11-unix/X{n}").exists():
                break
            time.sleep(0.05)
        if proc.poll() is None and Path(f"/tmp/.X11-unix/X{n}").exists():
            display = f":{n}"
            break
        proc.kill()
        proc = None
    if proc is None:
        xvfb.reason = "Xvfb did not start"
        yield None
        return
    try:
        yield display
    finally:
        proc.terminate()
        try:
            proc.wait(timeout=5)
        except subprocess.TimeoutExpired:
            proc.kill()


xvfb.reason = ""


def server_cpu_s(display: str | None) -> float:
    """CPU seconds the X server of ``display`` (``":57"``) has used so far (its lock file names
    its process), or NaN when unknown: presenting a frame costs the server's time too."""
    if not display:
        return float("nan")
    try:
        pid = int(Path(f"/tmp/.X{display.lstrip(':')}-lock").read_text().strip())
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
        return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")
    except (OSError, ValueError, IndexError):
        return float("nan")
