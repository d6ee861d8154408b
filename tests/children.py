"""Child processes that a test stops with a signal, started as a terminal's shell starts a
command: SIGINT, SIGTERM and SIGHUP at their defaults and unblocked, whatever this process
inherited. A program keeps a stop signal it was started ignoring (Unix convention, and
CPython's own): pytest run as a background job of a script has SIGINT ignored, under
``nohup`` SIGHUP, and a child started plainly would keep them ignored and outlive the test's
Ctrl-C. And a Python script run in a child of its own, its answer one JSON line."""

import json
import signal
import subprocess
import sys
from pathlib import Path
from typing import Any, Callable, Optional, Sequence

ROOT = Path(__file__).resolve().parents[1]
STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)


def stop_signals_by_default() -> None:
    """In the forked child, before exec: the stop signals at SIG_DFL and unblocked (the
    interpreter exec'd then installs its own SIGINT handler, as from a terminal)."""
    for sig in STOP_SIGNALS:
        signal.signal(sig, signal.SIG_DFL)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, STOP_SIGNALS)


def _then(preexec_fn: Optional[Callable[[], Any]]) -> Callable[[], None]:
    """The defaults, then the test's own ``preexec_fn`` (which may ignore one again, as
    ``nohup`` does)."""
    def start() -> None:
        stop_signals_by_default()
        if preexec_fn is not None:
            preexec_fn()
    return start


def popen(args: Sequence[str], *, preexec_fn: Optional[Callable[[], Any]] = None,
          **kw: Any) -> subprocess.Popen:
    """``subprocess.Popen(args, **kw)`` with the stop signals at their defaults."""
    return subprocess.Popen(args, preexec_fn=_then(preexec_fn), **kw)


def run(args: Sequence[str], *, preexec_fn: Optional[Callable[[], Any]] = None,
        **kw: Any) -> subprocess.CompletedProcess:
    """``subprocess.run(args, **kw)`` with the stop signals at their defaults."""
    return subprocess.run(args, preexec_fn=_then(preexec_fn), **kw)


def python_json(script: str, *args: str, timeout: float = 120.0) -> Any:
    """The last line ``script`` prints, read as JSON, run by this interpreter in a process of
    its own (``python -c script args``, in the project's folder): what it imports and the
    memory it holds are then its own, not the test worker's; a failed child fails the test
    with the end of its stderr."""
    out = subprocess.run([sys.executable, "-c", script, *args], cwd=ROOT, capture_output=True,
                         text=True, timeout=timeout)
    assert out.returncode == 0, out.stderr[-2000:]
    return json.loads(out.stdout.splitlines()[-1])
