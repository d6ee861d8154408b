"""Run the benchmarks (``make bench``): each ``bench/NAME.py`` that is a script, one after the
other in its own process, printing ``== bench/NAME.py`` and its last line (the JSON result).

A benchmark that fails is named at the end and the run exits 1, so a broken benchmark is not
mistaken for a finished one; the helper modules (``common.py``, ``xwindow.py``) are not run.
The soaks (``*soak.py``: the 20-minute real-time gallery soak, the simulated hour, the
follower's 200,000 steps) are long-run checks, not speed figures: they run only with
``--soaks`` (``make bench SOAKS=1``) or when named.

    python -m bench [--soaks] [bench/NAME.py ...]
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent


def is_soak(path: Path) -> bool:
    """A long-run check (``soak.py``, ``gallery_soak.py``, ``mop_soak.py``)."""
    return path.name.endswith("soak.py")


def benchmarks(folder: Path = HERE, soaks: bool = False) -> list[Path]:
    """The scripts of ``folder``: files run as ``__main__``, in name order; the soaks only
    with ``soaks``."""
    return [p for p in sorted(folder.glob("*.py"))
            if not p.name.startswith("_") and 'if __name__ == "__main__":' in p.read_text()
            and (soaks or not is_soak(p))]


def run(paths: list[Path]) -> list[str]:
    """Run each script with this interpreter; returns the failures, one line each."""
    failed = []
    for path in paths:
        print(f"== {path}", flush=True)
        proc = subprocess.run([sys.executable, str(path)], stdout=subprocess.PIPE, text=True)
        lines = proc.stdout.strip().splitlines()
        print(lines[-1] if lines else "(no output)", flush=True)
        if proc.returncode != 0:
            failed.append(f"{path}: exit status {proc.returncode}")
    return failed


def main(argv: list[str] | None = None) -> int:
    args = list(sys.argv[1:] if argv is None else argv)
    usage = "usage: python -m bench [--soaks] [bench/NAME.py ...]"
    if {"-h", "--help"} & set(args):
        print(usage)
        return 0
    flags = [a for a in args if a.startswith("-") and a != "--soaks"]
    if flags:   # not taken for a benchmark's name ("no such benchmark: --fast")
        print(f"bench: unknown argument {flags[0]!r}\n{usage}", file=sys.stderr)
        return 2
    soaks = "--soaks" in args
    args = [a for a in args if a != "--soaks"]
    paths = [Path(a) for a in args] if args else benchmarks(soaks=soaks)
    missing = [str(p) for p in paths if not p.is_file()]
    if missing:
        print(f"bench: no such benchmark: {', '.join(missing)}", file=sys.stderr)
        return 2
    failed = run(paths)
    for line in failed:
        print(f"bench: failed: {line}", file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    raise SystemExit(main())
