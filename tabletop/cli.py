"""The ``tabletop`` command line: one subcommand per module in :mod:`tabletop.commands`.

Every subcommand prints one clear line and exits non-zero on bad input, never a traceback.
Command modules import their heavy dependencies inside ``main`` so ``--help`` stays fast and
commands that draw nothing never import pygame.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import os
import re
import signal
import sys
import threading
from typing import Any, Iterator, Sequence

from tabletop import __version__, early_stop
from tabletop.early_stop import COMMANDS

EXIT_BAD_INPUT = 2
# ``run`` ended on purpose but its recording failed (a full disk): the kiosk's supervisor ends
# on it as on 0 instead of restarting
EXIT_RECORDING_FAILED = 3
# Ctrl-C or a stopping signal cut the command short (README: "130 interrupted")
EXIT_INTERRUPTED = 130
# the reader of the command's output closed it early (``tabletop follow ... --out /dev/stdout |
# head``): nothing more to say, as for a program the shell saw end by SIGPIPE (128 + 13)
EXIT_OUTPUT_CLOSED = 141
# the signals that end a run cleanly (README: Ctrl-C, SIGTERM and SIGHUP, a closed terminal or
# a stopped session), in the installation and in the kiosk's supervisor alike
STOP_SIGNALS = tuple(getattr(signal, n) for n in early_stop.STOP_SIGNALS if hasattr(signal, n))


@contextlib.contextmanager
def catch_stop_signals(handler: Any, signals: Sequence[int] = STOP_SIGNALS) -> Iterator[None]:
    """Within the block ``handler`` handles ``signals``; the handlers it replaced are put back
    after. Only in the main thread (elsewhere nothing is installed: a test calling a command
    from another thread). A SIGHUP this process was started ignoring (``nohup tabletop run
    ... &``, to outlive the terminal) stays ignored, as for any program: caught, a logout
    would end the run."""
    old = {}
    if threading.current_thread() is threading.main_thread():
        for s in signals:
            if s == getattr(signal, "SIGHUP", None) and signal.getsignal(s) == signal.SIG_IGN:
                continue
            old[s] = early_stop.disposition_before(s, signal.signal(s, handler))
    try:
        yield
    finally:
        for s, h in old.items():
            signal.signal(s, h)


def one_line(message: object) -> str:
    """A message on one line (a library's may span several; an argument may hold control
    characters, shown escaped)."""
    text = " ".join(str(message).split())
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in text)


# modes of ``run`` that people take for commands of their own
RUN_MODES = {"studio": "tabletop run --studio", "kiosk": "tabletop run --kiosk"}


# a number, or a comma list of numbers, beginning with '-': a value such as ``--view -90,15`` or
# ``--table -1,0.8`` (refused with its own message), not an option (argparse's own pattern takes
# only a single number, so a list was "expected one argument")
_NUMBER = r"(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
NEGATIVE_VALUE = re.compile(rf"^-{_NUMBER}(?:,\s*-?{_NUMBER})*$")


class Parser(argparse.ArgumentParser):
    """argparse, but a usage error is one line (what is wrong, and where to read more), and a
    value list beginning with a minus sign is a value (:data:`NEGATIVE_VALUE`)."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = NEGATIVE_VALUE

    def error(self, message: str) -> None:  # type: ignore[override]
        hint = f"see {self.prog} --help"
        for mode, command in RUN_MODES.items():
            if self.prog == "tabletop" and f"invalid choice: '{mode}'" in message:
                hint = f"the {mode} is `{command}`"
        self.exit(EXIT_BAD_INPUT, f"{self.prog}: error: {one_line(message)} ({hint})\n")


def build_parser() -> argparse.ArgumentParser:
    parser = Parser(
        prog="tabletop",
        description="Tangible tabletop installation: pucks on a table drive projected characters.")
    parser.add_argument("--version", action="version", version=f"tabletop {__version__}")
    # a command is required: ``tabletop`` alone is a usage error (one line on stderr, status 2,
    # as ``tabletop calibrate`` without its step); ``tabletop --help`` is the help (stdout, 0)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=Parser,
                                required=True)
    for name in COMMANDS:
        try:
            module = importlib.import_module(f"tabletop.commands.{name}")
        except ModuleNotFoundError as exc:
            if exc.name == f"tabletop.commands.{name}":
                continue
            raise
        p = sub.add_parser(name, help=module.HELP, description=module.HELP)
        module.add_arguments(p)
        p.set_defaults(_main=module.main, _prog=f"tabletop {name}")
    return parser


def command_parser(parser: argparse.ArgumentParser,
                   args: argparse.Namespace) -> argparse.ArgumentParser:
    """The parser of the (sub)command ``args`` were parsed for: ``calibrate``'s step's for a
    step, ``parser`` itself when no command was given."""
    for action in parser._subparsers._group_actions if parser._subparsers else ():
        chosen = action.choices.get(getattr(args, action.dest, None) or "")
        if chosen is not None:
            return command_parser(chosen, args)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line (``argv``: the arguments, default ``sys.argv[1:]``); returns the
    exit status. A Ctrl-C at any point is one line and status 130, also while the commands'
    modules are still being imported (numpy, OpenCV: the first fraction of a second of every
    command), which is why this module imports nothing of the project's but the package
    itself at its top. Until the commands' modules are imported, from the package's first
    line, a stop signal ends the program at once with the same line and status
    (:func:`tabletop.early_stop.stop_early`): a KeyboardInterrupt raised in an extension
    module's import (numpy's) can surface as an ImportError with a traceback."""
    words = list(sys.argv[1:] if argv is None else argv)
    try:
        with _interrupts_kept(), _interrupt_on_stop_signals():
            return _main(words)
    except BrokenPipeError:
        _drop_stdout()
        return EXIT_OUTPUT_CLOSED
    except KeyboardInterrupt:
        _INTERRUPTED_BY.clear()
        command = f" {words[0]}" if words and words[0] in COMMANDS else ""
        print(f"tabletop{command}: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    finally:
        early_stop.release()


# the stop signal whose KeyboardInterrupt :func:`_interrupt` raised last
_INTERRUPTED_BY: list[int] = []
# the signals of KeyboardInterrupts a finaliser swallowed, to be sent again (_interrupts_kept)
_LOST: list[int] = []
_LOST_SAID = threading.Event()
_RESENDER: list[threading.Thread] = []


def _interrupt(signum: int, frame: Any) -> None:
    if early_stop.active():   # the program still imports its modules
        early_stop.stop_early(signum, frame)
    _INTERRUPTED_BY[:] = [signum]
    raise KeyboardInterrupt


def _resend_lost() -> None:
    """Send each lost interrupt's signal again, to the main thread, once the finaliser that
    swallowed it has returned."""
    import _thread
    while True:
        _LOST_SAID.wait()
        _LOST_SAID.clear()
        while _LOST:
            _thread.interrupt_main(_LOST.pop(0))


@contextlib.contextmanager
def _interrupts_kept() -> Iterator[None]:
    """Within the block, a KeyboardInterrupt raised while a finaliser runs (a ``__del__`` or
    a weakref callback: numba's typing frees many while an installation builds) is sent again
    as its signal. The interpreter swallows an exception a finaliser raises (printing
    "Exception ignored in ..." and a traceback), so a Ctrl-C, SIGTERM or SIGHUP landing there
    was lost and the command worked on. The signal is sent from a thread of its own: one
    raised within the hook would land in the hook, swallowed again; the hook's last act is
    to wake that thread, whose signal (it needs the interpreter's lock to send it) is then
    taken at the main thread's next check, past the hook."""
    default = sys.unraisablehook

    def hook(unraisable: Any) -> None:
        if not isinstance(unraisable.exc_value, KeyboardInterrupt):
            default(unraisable)
            return
        if not _RESENDER:
            _RESENDER.append(threading.Thread(target=_resend_lost, name="interrupts",
                                              daemon=True))
            _RESENDER[0].start()
        _LOST.append(_INTERRUPTED_BY[-1] if _INTERRUPTED_BY else signal.SIGINT)
        _LOST_SAID.set()

    sys.unraisablehook = hook
    try:
        yield
    finally:
        sys.unraisablehook = default


def _interrupt_on_stop_signals() -> contextlib.AbstractContextManager[None]:
    """SIGTERM and SIGHUP interrupt a command as Ctrl-C does (one line, status 130; ``status``
    and ``track`` of a camera end as on Ctrl-C), also while its modules are imported, where
    they would kill the process without a word (status 143 or 129). ``run`` and ``replay``
    put their own handlers over these while they run. (SIGINT: Python's own
    KeyboardInterrupt, or ignored in a script's background job.)"""
    return catch_stop_signals(_interrupt, [s for s in STOP_SIGNALS if s != signal.SIGINT])


def entry() -> None:
    """The program ``tabletop`` (and ``python -m tabletop``): :func:`main`, then the jobs still
    running in job threads (a take's training, a review sheet: behaviors.worker) finished
    within :data:`behaviors.worker.FINISH_S`, a Ctrl-C (SIGTERM, SIGHUP) meanwhile caught as
    everywhere else.
    Every end is ``os._exit`` with the command's status, after the log and the standard
    streams are flushed; a stop signal during that flush ends it with the command's failure
    status, or with 128 + the signal's number after a success
    (:func:`_exit_on_stop_signals`). The interpreter's finalisation must not run under a job
    thread still in native code (one that did not end in time, or a Ctrl-C while it ran); for
    an interrupted command, a Ctrl-C that landed in code an extension module runs through
    ``PyRun_String`` while it is imported leaves the interpreter's mark of an unhandled
    KeyboardInterrupt, and the interpreter then ends by SIGINT (status -2), not 130."""
    try:
        status: int | str | None = main()
    except SystemExit as exc:   # argparse's --help and --version
        status = exc.code
    worker = sys.modules.get("behaviors.worker")   # imported where jobs ran
    ended = True
    if worker is not None:
        try:
            with _interrupts_kept(), _interrupt_on_stop_signals():
                ended = worker.finish_jobs()
        except KeyboardInterrupt:
            print("tabletop: interrupted", file=sys.stderr)
            status = EXIT_INTERRUPTED
        else:
            if not ended:
                print("tabletop: a background job did not end in time; ending without it",
                      file=sys.stderr)
    if isinstance(status, str):   # sys.exit("why"), as the interpreter would say it
        print(status, file=sys.stderr)
    code = status if isinstance(status, int) else int(status is not None)
    _exit_on_stop_signals(code)
    import logging
    logging.shutdown()
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):
            pass
    os._exit(code)


def _exit_on_stop_signals(code: int) -> None:
    """From here to the process's end a stop signal ends it at once: with the command's own
    failure status ``code`` when it has one (3, a recording that failed, is what the kiosk's
    supervisor must see, and a SIGTERM it sends on Ctrl-C can land here), else with 128 + the
    signal's number, as the shell reports a program a signal ended: the flush it cut short may
    have lost the end of the log or of the output, so a 0 would claim a complete end it did
    not have. A signal the process was started ignoring (``nohup``'s SIGHUP, a script's
    background job's SIGINT) stays ignored here too. Every end goes through ``os._exit``,
    skipping the interpreter's finalisation: that took 0.6 s after a one-minute ``behave``
    (freeing what its modules hold), a stop signal landing in it ended the process by the
    signal without a word, and a non-daemon thread or an atexit hook that never ends hung it
    there. A signal that ends the process also ends a flush blocked on a reader that stopped
    reading."""
    if threading.current_thread() is threading.main_thread():
        for s in STOP_SIGNALS:
            if signal.getsignal(s) is not signal.SIG_IGN:
                signal.signal(s, lambda signum, _frame: os._exit(code or 128 + signum))


def _drop_stdout() -> None:
    """Point standard output at /dev/null, so the interpreter's last flush of what is left in
    its buffer (for a reader gone) does not print a second BrokenPipeError on its way out."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (OSError, ValueError):  # no real standard output (a test's capture): nothing to drop
        pass


def _empty_argument(command: argparse.ArgumentParser, words: list[str]) -> str | None:
    """The option or argument given an empty word (``tabletop replay "$F"`` with F unset):
    as a path it is the current folder, which it never named ("replay: .: is a folder").
    ``--record ''`` and ``--out ''`` are their commands' to say (with a file name to give)."""
    options = command._option_string_actions
    for i, word in enumerate(words):
        option = word[:-1] if word.endswith("=") and word[:-1] in options else None
        if word != "" and option is None:
            continue
        before = option or (words[i - 1] if i else "")
        if before in ("--record", "--out"):
            continue
        if before in options:
            return before
        names = [a.metavar or a.dest for a in command._actions if not a.option_strings]
        return str(names[0]) if names else "an argument"
    return None


def _main(words: list[str]) -> int:
    from tabletop.errors import InputError

    os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
    # OpenCV's own "[ WARN:0@...]" lines (a missing camera, a video back-end probing) are not for
    # the user: every failure is reported as one clear line of ours instead.
    os.environ.setdefault("OPENCV_LOG_LEVEL", "SILENT")
    os.environ.setdefault("OPENCV_VIDEOIO_DEBUG", "0")
    # FFmpeg's own log (read by OpenCV when it first opens a video; -8 is AV_LOG_QUIET): a file
    # named .png that is none printed "[png @ 0x...] Invalid PNG signature ..." above our line
    os.environ.setdefault("OPENCV_FFMPEG_LOGLEVEL", "-8")
    parser = build_parser()
    args, extra = parser.parse_known_args(words)
    early_stop.release()   # the modules are in: Ctrl-C is Python's KeyboardInterrupt again
    if extra:   # said by the command's own parser, which argparse leaves to the top one
        command_parser(parser, args).error(f"unrecognized arguments: {' '.join(extra)}")
    nul = [a for a in words if "\x00" in a]
    if nul:  # (a shell cannot pass one; a script building its arguments can)
        parser.error(f"argument {nul[0]!r} contains a NUL character: no path or value can")
    empty = _empty_argument(command_parser(parser, args), words)
    if empty is not None:
        print(f"{args._prog}: error: {empty}: the value is empty (an unset variable in a "
              "script?)", file=sys.stderr)
        return EXIT_BAD_INPUT
    try:
        return int(args._main(args) or 0)
    except InputError as exc:
        print(f"{args._prog}: error: {one_line(exc)}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except BrokenPipeError:
        raise                  # the reader left: no error of the input (main's quiet status)
    except OSError as exc:
        where = f" {exc.filename}:" if getattr(exc, "filename", None) else ""
        print(f"{args._prog}: error:{where} {one_line(exc.strerror or exc)}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:
        print(f"{args._prog}: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except MemoryError:
        print(f"{args._prog}: error: out of memory (is an input or a number far too large?)",
              file=sys.stderr)
        return EXIT_BAD_INPUT
    except Exception as exc:  # a bug, not bad input: one line, the traceback on request
        if os.environ.get("TABLETOP_DEBUG"):
            raise
        print(f"{args._prog}: internal error: {type(exc).__name__}: {one_line(exc)} "
              "(set TABLETOP_DEBUG=1 to see the traceback)", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
