"""A stop signal while the program is still importing its package and command line (the first
~50-150 ms of every command) is a clean stop: one line, status 130, no traceback, as README
promises "from its first moment"."""

import functools
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from tests import children

SCRIPT = Path(sys.executable).with_name("tabletop")


def _stop_while_importing(command: list[str], sig: int,
                          after_s: float) -> tuple[int, str, str]:
    """Start ``command`` under ``-X importtime`` (each finished import is a line on stderr),
    wait for the line of the package ``tabletop`` (its first lines have run), then ``after_s``
    more, and send ``sig``. Returns (status, stderr, stdout)."""
    proc = children.popen([sys.executable, "-X", "importtime", *command],
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                          cwd=Path(__file__).parent)
    assert proc.stderr is not None
    seen = []
    for line in proc.stderr:
        seen.append(line)
        if line.rsplit("|", 1)[-1].strip() == "tabletop":   # (indented under tabletop.cli
            break                                            # when the script imports it)
    time.sleep(after_s)
    proc.send_signal(sig)
    out, rest = proc.communicate(timeout=60)
    said = [ln for ln in "".join(seen).splitlines() + rest.splitlines()
            if not ln.startswith("import time:")]
    return proc.returncode, "\n".join(said), out


def _after_trace(line: str) -> str:
    """A line of ``python -v``'s stderr, or the program's line that follows a piece of its
    trace: the interpreter writes a trace line in pieces, and the early stop's line written
    between two of them ends that piece's line (seen once in 60 at load 3: "# code object
    from '.../reprlib.cpython-311.pyc'tabletop status: interrupted")."""
    if line.startswith(("# ", "import ")) and line.endswith(": interrupted"):
        return line[line.rfind("tabletop"):]
    return line


@functools.cache
def whole_help(how: str) -> str:
    """What ``status --help`` prints when nothing stops it (run once per way of starting:
    the same for every signal)."""
    command = (["-m", "tabletop"] if how == "module" else [str(SCRIPT)]) + ["status", "--help"]
    return children.run(command if how == "script" else [sys.executable, *command],
                        capture_output=True, text=True, check=True).stdout


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM, signal.SIGHUP])
@pytest.mark.parametrize("how", ["module", "script"])
def test_a_stop_signal_while_the_program_imports_is_one_line_and_130(sig, how):
    command = (["-m", "tabletop"] if how == "module" else [str(SCRIPT)]) + ["status", "--help"]
    stopped = 0
    for after_s in (0.0, 0.02, 0.06, 0.12):
        status, said, out = _stop_while_importing(command, sig, after_s)
        if out == whole_help(how):  # the command had done its work (a signal as the interpreter
            continue                # ends, under load, may end it by the signal): nothing to stop
        assert status == 130, (after_s, status, said)
        assert "Traceback" not in said and said.count("\n") == 0, (after_s, said)
        assert said == "tabletop status: interrupted", (after_s, said)
        stopped += 1
    assert stopped >= 1, "no signal landed during the imports"


def test_importing_the_package_as_a_library_leaves_the_signals_alone():
    code = ("import signal, tabletop; "
            "print(signal.getsignal(signal.SIGTERM) is signal.SIG_DFL, "
            "signal.getsignal(signal.SIGINT) is signal.default_int_handler)")
    out = children.run([sys.executable, "-c", code], capture_output=True, text=True,
                       check=True).stdout
    assert out.split() == ["True", "True"]


def test_after_the_command_line_starts_ctrl_c_is_pythons_again():
    """The command line takes over: the early stop handles nothing once ``main`` runs (a
    Ctrl-C there is a KeyboardInterrupt the command may clean up after)."""
    code = "\n".join([
        "import sys, signal", "sys.argv = ['tabletop', 'status', '--help']",
        "import tabletop", "from tabletop import cli",
        "print(signal.getsignal(signal.SIGINT).__name__)",
        "try:\n    cli.main()\nexcept SystemExit:\n    pass",
        "print(signal.getsignal(signal.SIGINT) is signal.default_int_handler,"
        " signal.getsignal(signal.SIGTERM) is signal.SIG_DFL)"])
    res = children.run([sys.executable, "-c", code], capture_output=True, text=True)
    lines = res.stdout.split("\n")
    assert lines[0] == "stop_early"
    assert lines[-2].split() == ["True", "True"]


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
@pytest.mark.parametrize("how", ["module", "script"])
def test_a_stop_signal_while_the_interpreter_sets_up_its_paths_is_one_line_and_130(sig, how):
    """The environment ``make`` makes runs tabletop/early_stop.py from a ``.pth`` line, while
    ``site`` is still setting up the import path (the editable install's finder: 20-60 ms
    under load), before the package can load: a stop signal there is the same clean stop.
    (Without it: a KeyboardInterrupt traceback from ``site``, status 1, or an end by SIGTERM.)
    The signal is sent when ``python -v`` says site processes the ``.pth`` file after the
    early stop's (the editable install's, whose finder then imports for 10-40 ms)."""
    command = (["-m", "tabletop"] if how == "module" else [str(SCRIPT)]) + ["status", "--help"]
    proc = children.popen([sys.executable, "-v", *command],
                          stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                          cwd=Path(__file__).parent)
    assert proc.stderr is not None
    files: list[str] = []
    for line in proc.stderr:
        if line.startswith("Processing .pth file: "):
            files.append(Path(line.split(": ", 1)[1].strip().strip("'")).name)
            if len(files) > 1 and files[-2] == "00-tabletop-early-stop.pth":
                break
        elif line.startswith("Processing user site-packages") and files:
            break   # site has ended its .pth files
    proc.send_signal(sig)
    rest = proc.communicate(timeout=60)[1]
    assert "00-tabletop-early-stop.pth" in files, "the early stop's .pth is not installed"
    if files[-1] == "00-tabletop-early-stop.pth":
        pytest.skip("no .pth file comes after the early stop's (not an editable install)")
    said = [ln for ln in map(_after_trace, rest.splitlines())
            if ln.startswith("tabletop") or "Traceback" in ln
            or "Error" in ln or "KeyboardInterrupt" in ln]
    assert (proc.returncode, said) == (130, ["tabletop status: interrupted"])


def test_other_programs_of_the_environment_keep_their_signals():
    code = ("import signal; print(signal.getsignal(signal.SIGTERM) is signal.SIG_DFL, "
            "signal.getsignal(signal.SIGINT) is signal.default_int_handler)")
    out = children.run([sys.executable, "-c", code], capture_output=True, text=True,
                       check=True).stdout
    assert out.split() == ["True", "True"]
