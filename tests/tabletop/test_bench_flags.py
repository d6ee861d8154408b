"""Every benchmark script answers its command line before measuring: ``--help`` prints a short
usage and exits 0, an unknown flag is refused naming it (a bench that read no argument ran
whole, minutes, for ``--help``). The scripts run in one interpreter, each stopped after 20 s
as one that went on measuring."""

import json
import subprocess
import sys
from pathlib import Path

from bench.__main__ import benchmarks, main as bench_main

ROOT = Path(__file__).resolve().parents[2]
BOGUS = "--no-such-flag"

# each script run as __main__ with one argument; what it exited with and printed
RUN_EACH = """
import contextlib, io, json, runpy, signal, sys

def measuring(*_):
    raise TimeoutError("still running")

signal.signal(signal.SIGALRM, measuring)
said = {}
for path in sys.argv[1:]:
    for arg in (%r, "--help"):
        sys.argv, out, err, code = [path, arg], io.StringIO(), io.StringIO(), "finished"
        signal.alarm(20)
        try:
            with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
                runpy.run_path(path, run_name="__main__")
        except SystemExit as stop:
            code = stop.code if stop.code is None or isinstance(stop.code, int) else 1
            err.write(str(stop.code))
        except TimeoutError:
            code = "still measuring after 20 s"
        finally:
            signal.alarm(0)
        said[path + " " + arg] = [code, out.getvalue(), err.getvalue()]
print(json.dumps(said))
""" % BOGUS


def test_every_bench_script_answers_help_and_refuses_a_wrong_flag_before_measuring():
    scripts = [str(p.relative_to(ROOT)) for p in benchmarks(soaks=True)]
    assert len(scripts) >= 30
    r = subprocess.run([sys.executable, "-c", RUN_EACH, *scripts], cwd=ROOT, text=True,
                       capture_output=True, timeout=900)
    said = json.loads(r.stdout.strip().splitlines()[-1])
    wrong = []
    for script in scripts:
        code, out, err = said[f"{script} {BOGUS}"]
        if code in (0, None, "finished") or BOGUS not in err or '{"' in out:
            wrong.append(f"{script} {BOGUS}: {code} {err[-200:]!r}")
        code, out, err = said[f"{script} --help"]
        if code not in (0, None) or "usage:" not in out or '{"' in out:
            wrong.append(f"{script} --help: {code} {out[-200:]!r}")
    assert not wrong, "\n".join(wrong)


def test_the_bench_runner_answers_help_and_refuses_a_wrong_flag(capsys):
    assert bench_main(["--help"]) == 0
    assert capsys.readouterr().out.startswith("usage: python -m bench")
    assert bench_main([BOGUS]) == 2
    assert capsys.readouterr().err.splitlines()[0] == f"bench: unknown argument {BOGUS!r}"
