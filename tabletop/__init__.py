"""Tabletop: the runtime that wires tracked pucks, engines and the projector view together."""

import os
import signal
import sys
from typing import Any

# The engines' matrix products are small (a Puppet Master step is one 24,000 x 8 product) and
# the loop already keeps both cores busy (camera, detection, view): a threaded BLAS made one
# such product take ~50 ms instead of ~0.13 ms on a 2-core machine. Set before numpy loads;
# an explicit setting in the environment wins.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

__version__ = "0.1.0"

# the subcommands of the program ``tabletop``, one module each in tabletop.commands
COMMANDS = ("run", "track", "behave", "follow", "pose", "calibrate", "replay", "status",
            "review")

# the dispositions the early stop (below) replaced, by signal: put back by release_early_stop,
# which empties _EARLY_STOP_ACTIVE
_BEFORE_EARLY_STOP: dict[int, Any] = {}
_EARLY_STOP_ACTIVE: list[bool] = []


def stop_early(signum: int, _frame: Any) -> None:
    """A stop signal while the program is still importing its modules: one line and status
    130, as a command it interrupts (README), with nothing to clean up yet. ``os._exit``, as
    a KeyboardInterrupt raised here would surface through the import machinery (``runpy``
    for ``python -m tabletop``) as a traceback."""
    words = sys.argv[1:2]
    command = f" {words[0]}" if words and words[0] in COMMANDS else ""
    try:
        os.write(2, f"tabletop{command}: interrupted\n".encode())
    finally:
        os._exit(130)


def _started_as_program() -> bool:
    """Whether this import is the program's own (``python -m tabletop``, whose ``sys.argv[0]``
    is ``-m`` while the package loads, or the ``tabletop`` script), not a library's or a
    test's."""
    argv = getattr(sys, "orig_argv", [])
    as_module = any(argv[i:i + 2] == ["-m", "tabletop"] for i in range(len(argv)))
    script = os.path.basename(sys.argv[0]) if sys.argv else ""
    return (sys.argv[:1] == ["-m"] and as_module) or script in ("tabletop", "tabletop.exe")


def early_stop_active() -> bool:
    """Whether the program is still in the imports :func:`stop_early` covers."""
    return bool(_EARLY_STOP_ACTIVE)


def release_early_stop() -> None:
    """Put back the dispositions :func:`stop_early` replaced, where it still handles them
    (the command line has its modules and handles stops its own way from here on)."""
    _EARLY_STOP_ACTIVE.clear()
    for s, before in _BEFORE_EARLY_STOP.items():
        if signal.getsignal(s) is stop_early:
            signal.signal(s, before)


def disposition_before_early_stop(s: int, handler: Any) -> Any:
    """``handler`` (one replaced on signal ``s``), or what it replaced if it is the early
    stop."""
    return _BEFORE_EARLY_STOP.get(s, handler) if handler is stop_early else handler


# The program takes Ctrl-C, SIGTERM and SIGHUP as a clean stop from its first line of its own
# (README: "from its first moment"): this package's first lines, before the command line and
# its modules load (50-150 ms): one line and status 130, not a KeyboardInterrupt traceback
# (status 1) or an end by the signal (-15). A signal the process was started ignoring
# (``nohup``'s SIGHUP, a background job's SIGINT) stays ignored.
if _started_as_program():
    for _name in ("SIGINT", "SIGTERM", "SIGHUP"):
        _s = getattr(signal, _name, None)
        if _s is not None and signal.getsignal(_s) is not signal.SIG_IGN:
            _BEFORE_EARLY_STOP[_s] = signal.signal(_s, stop_early)
    _EARLY_STOP_ACTIVE.append(True)
