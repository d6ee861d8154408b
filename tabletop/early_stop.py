"""A stop signal while the program starts is a clean stop: one line and status 130.

The program takes Ctrl-C, SIGTERM and SIGHUP as a clean stop from its first moment (README):
until the command line has its modules (50-150 ms), :func:`stop_early` ends the program at
once, not a KeyboardInterrupt traceback (status 1) or an end by the signal (-15). A signal the
process was started ignoring (``nohup``'s SIGHUP, a background job's SIGINT) stays ignored.

This module imports only ``os``, ``sys`` and ``_signal`` (loaded before any program starts) and
nothing of the project: the package installs it at its first line, and the environment made by
``make`` runs this very file from a ``.pth`` line while the interpreter's ``site`` still sets
up the import path (editable install's finder: 20-40 ms under load), before the package can be
imported at all. The copy run there marks its handler (``tabletop_replaced``), so the
package's copy takes over what it replaced.
"""

from __future__ import annotations

import os
import sys

# the interpreter's own signal module: ``signal`` (its enums) takes 5-10 ms to import
import _signal

COMMANDS = ("run", "track", "behave", "follow", "pose", "calibrate", "replay", "status",
            "review")
STOP_SIGNALS = ("SIGINT", "SIGTERM", "SIGHUP")

# the dispositions stop_early replaced, by signal number (put back by release)
REPLACED: dict[int, object] = {}


def stop_early(signum: int, _frame: object) -> None:
    """One line and status 130, as a command it interrupts (README), with nothing to clean up
    yet. ``os._exit``, as a KeyboardInterrupt raised here would surface through the import
    machinery (``site``, ``runpy``) as a traceback."""
    words = sys.argv[1:2]
    command = f" {words[0]}" if words and words[0] in COMMANDS else ""
    try:
        os.write(2, f"tabletop{command}: interrupted\n".encode())
    finally:
        os._exit(130)


stop_early.tabletop_replaced = REPLACED  # type: ignore[attr-defined]


def started_as_program() -> bool:
    """Whether this process is the program (``python -m tabletop``, whose ``sys.argv[0]`` is
    ``-m`` while the package loads, or the ``tabletop`` script), not a library's or a
    test's."""
    argv = getattr(sys, "orig_argv", [])
    as_module = any(argv[i:i + 2] == ["-m", "tabletop"] for i in range(len(argv)))
    script = os.path.basename(sys.argv[0]) if sys.argv else ""
    return (sys.argv[:1] == ["-m"] and as_module) or script in ("tabletop", "tabletop.exe")


def install() -> bool:
    """Handle the stop signals with :func:`stop_early` if this process is the program; returns
    whether it did. A handler of another copy of this module (the ``.pth``'s) is replaced, and
    what that one replaced is what :func:`release` puts back."""
    if not started_as_program():
        return False
    for name in STOP_SIGNALS:
        s = getattr(_signal, name, None)
        if s is None:
            continue
        current = _signal.getsignal(s)
        if current == _signal.SIG_IGN or current is stop_early:
            continue
        before = getattr(current, "tabletop_replaced", {}).get(s, current)
        _signal.signal(s, stop_early)
        REPLACED[s] = before
    return True


def active() -> bool:
    """Whether :func:`stop_early` still stands for the program's stops."""
    return bool(REPLACED)


def release() -> None:
    """Put back the dispositions :func:`stop_early` replaced, where it still handles them
    (the command line has its modules and handles stops its own way from here on)."""
    for s, before in list(REPLACED.items()):
        if _signal.getsignal(s) is stop_early:
            _signal.signal(s, before)  # type: ignore[arg-type]
    REPLACED.clear()


def disposition_before(s: int, handler: object) -> object:
    """``handler`` (one replaced on signal ``s``), or what it replaced if it is the early
    stop."""
    return REPLACED.get(s, handler) if handler is stop_early else handler


SITE_NAME = "<tabletop-site>"
PTH_FILE = "00-tabletop-early-stop.pth"


def write_site_line() -> str:
    """Write the ``.pth`` file that runs this module's file while ``site`` starts the
    environment's interpreters (``make`` does, when it makes the environment); returns its path.
    It sorts before the editable install's own ``.pth``; a moved or removed file is skipped."""
    import py_compile
    import sysconfig
    here = os.path.abspath(__file__)
    # Read only where the program may be starting (other interpreters of the environment, a
    # test's ``python -c``, skip it), through the interpreter's own (frozen) source loader,
    # which takes the byte-code cached beside it (written here, and by the package's import;
    # a stale one is compiled again, as any import does): compiling the source took
    # 1.3 ms, and up to 17 ms on a loaded machine, during which a signal was not yet handled.
    # (an interpreter embedded without arguments has no sys.argv here; the names are
    # underscored: site runs the line inside its own function, whose file is ``f``)
    line = (f"import os, sys, _frozen_importlib_external as _fl; _p = {here!r}; _a = getattr("
            f"sys, 'argv', None) or ['']; (_a[0] == '-m' or os.path.basename(_a[0]).startswith("
            f"'tabletop')) and os.path.isfile(_p) and exec(_fl.SourceFileLoader("
            f"'tabletop.early_stop', _p).get_code('tabletop.early_stop'), "
            f"{{'__name__': {SITE_NAME!r}}})\n")
    py_compile.compile(here, doraise=True)   # the byte-code the line loads
    path = os.path.join(sysconfig.get_path("purelib"), PTH_FILE)
    with open(path + ".tmp", "w", encoding="utf-8") as f:
        f.write(line)
    os.replace(path + ".tmp", path)
    return path


if __name__ == SITE_NAME:   # run from the environment's .pth line (Makefile)
    install()
