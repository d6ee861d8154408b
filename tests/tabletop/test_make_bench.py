"""``make bench`` as an operator runs it: every benchmark's last line, and a failing benchmark
fails the run (the shell loop it replaced printed the failure's last line and exited 0)."""

import math
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from bench.__main__ import benchmarks

ROOT = Path(__file__).resolve().parents[2]


def test_every_benchmark_script_is_run_and_no_helper_module(tmp_path):
    names = [p.name for p in benchmarks()]
    assert {"loop.py", "view.py", "osc.py", "tracking.py", "kiosk.py"} <= set(names)
    assert not {"common.py", "xwindow.py", "__init__.py", "__main__.py"} & set(names)
    (tmp_path / "helper.py").write_text("X = 1\n")
    (tmp_path / "real.py").write_text('if __name__ == "__main__":\n    print("{}")\n')
    assert [p.name for p in benchmarks(tmp_path)] == ["real.py"]


def test_the_soaks_run_only_when_asked_for(tmp_path):
    """``make bench`` is the speed figures; the soaks (the 20-minute gallery soak among them)
    run with ``SOAKS=1`` or when named."""
    names = [p.name for p in benchmarks()]
    assert not [n for n in names if "soak" in n]
    with_soaks = {p.name for p in benchmarks(soaks=True)}
    assert {"gallery_soak.py", "soak.py", "mop_soak.py", "edit_soak.py"} <= with_soaks
    assert with_soaks - {"gallery_soak.py", "soak.py", "mop_soak.py", "edit_soak.py"} == set(names)
    (tmp_path / "long_soak.py").write_text('if __name__ == "__main__":\n    print("{}")\n')
    assert benchmarks(tmp_path) == [] and len(benchmarks(tmp_path, soaks=True)) == 1
    if shutil.which("make") is None:
        pytest.skip("make is not installed")
    stamp = tmp_path / "installed"   # newer than pyproject.toml: nothing to install
    stamp.touch()
    for soaks, words in (([], ["-m", "bench"]), (["SOAKS=1"], ["-m", "bench", "--soaks"])):
        dry = subprocess.run(["make", "-n", "-s", "-C", str(ROOT), "bench", f"STAMP={stamp}",
                              f"PY={sys.executable}", *soaks], capture_output=True, text=True,
                             timeout=60)
        assert dry.returncode == 0, dry.stderr
        assert [ln.split()[1:] for ln in dry.stdout.splitlines()] == [words]


def test_make_bench_prints_each_last_line_and_fails_when_one_fails(tmp_path):
    if shutil.which("make") is None:
        pytest.skip("make is not installed")
    stamp = ROOT / ".venv" / ".installed"
    if subprocess.run(["make", "-q", "-C", str(ROOT), str(stamp)]).returncode != 0:
        pytest.skip("the project's environment is not installed (make would install it)")
    ok, bad = tmp_path / "ok.py", tmp_path / "bad.py"
    ok.write_text('print("warming up")\nprint(\'{"bench": "ok"}\')\n')
    bad.write_text('print(\'{"bench": "half"}\')\nraise SystemExit("bad.py: broken")\n')
    out = subprocess.run(["make", "-s", "-C", str(ROOT), "bench", f"PY={sys.executable}",
                          f"BENCHES={bad} {ok}"], capture_output=True, text=True, timeout=120)
    assert out.returncode != 0
    assert out.stdout.splitlines() == [f"== {bad}", '{"bench": "half"}',
                                       f"== {ok}", '{"bench": "ok"}']
    assert f"bench: failed: {bad}: exit status 1" in out.stderr
    good = subprocess.run(["make", "-s", "-C", str(ROOT), "bench", f"PY={sys.executable}",
                           f"BENCHES={ok}"], capture_output=True, text=True, timeout=120)
    assert good.returncode == 0 and good.stdout.splitlines()[-1] == '{"bench": "ok"}'
    missing = subprocess.run([sys.executable, "-m", "bench", str(tmp_path / "nope.py")],
                             cwd=ROOT, capture_output=True, text=True, timeout=60)
    assert missing.returncode == 2 and missing.stderr.strip() == (
        f"bench: no such benchmark: {tmp_path / 'nope.py'}")


def test_touch_pose_compare_without_its_older_commit_is_one_line_or_a_skip(tmp_path,
                                                                          monkeypatch, capsys):
    """A wrong COMMIT_OR_FOLDER is one line and a failure; the default commit missing from this
    copy (a shallow clone, an unpacked archive) skips with the reason, as ``make bench`` needs."""
    out = subprocess.run([sys.executable, "bench/touch_pose_compare.py", "no-such-commit"],
                         cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert out.returncode == 1 and "Traceback" not in out.stderr
    (line,) = out.stderr.strip().splitlines()
    assert line.startswith(
        f"bench/touch_pose_compare.py: no-such-commit: not a folder, nor a commit of {ROOT} (")
    from bench import touch_pose_compare
    # main() names its own XDG_CACHE_HOME (a temporary folder, removed after it): given back at
    # the end, else every process this worker starts later finds no compiled kernels and
    # builds them again (a `tabletop run` 14.7 CPU s instead of 0.7, measured)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))   # (recorded: undone at the end)
    monkeypatch.setattr(touch_pose_compare, "BEFORE", "0" * 40)
    monkeypatch.setattr(sys, "argv", ["bench/touch_pose_compare.py"])
    touch_pose_compare.main()
    import json
    last = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert last["bench"] == "touch_pose_compare" and "0000000000" in last["figures"]["skipped"]


def test_the_gallery_soaks_memory_slope_leaves_out_the_warm_up():
    """The slope is taken after ``settle_s``: a kiosk that grows 20 KB/s while its caches and
    histories fill, then stays (in 1 MB heap steps), reads about 0; one that keeps growing
    1.5 KB/s reads that, not the warm-up's rate."""
    from bench.gallery_soak import rss_slope_kb_s

    def run(mb_at):
        return [{"t_s": t, "installation": {"rss_mb": round(mb_at(t), 2)}}
                for t in range(20, 1201, 20)]

    warm = run(lambda t: 400 + min(t, 700) * 20 / 1024 + 0.3 * ((t // 100) % 2))
    steady = run(lambda t: 400 + min(t, 700) * 20 / 1024 + t * 1.5 / 1024)
    assert abs(rss_slope_kb_s(warm, 720.0)) < 0.5
    assert rss_slope_kb_s(warm[:45], 0.0) > 5.0   # a 15-minute run's half without settling
    assert 1.4 < rss_slope_kb_s(steady, 720.0) < 1.6
    assert math.isnan(rss_slope_kb_s(warm[:30], 720.0))   # too few samples after settle_s
