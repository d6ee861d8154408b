"""``tabletop behave``: real CSV files in, the DESIGN.md contract out; bad files, arguments and
parameters refused in one line (behaviour folders and tables: test_pm_behave_folders.py)."""

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from tabletop.files import read_csv, write_csv
from tests.puppet_master import demos as pm_demos
from tests.puppet_master.behave_cli import DEMO_HEADER, MAIN_HEADER, behave, write_files


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    return write_files(tmp_path_factory.mktemp("behave"))


def test_output_follows_the_contract(files):
    d, main = files
    assert behave("--train", d / "demo.csv", "--input", d / "main.csv", "--out", d / "out.csv") == 0
    header, out = read_csv(d / "out.csv")
    assert header == ["t", "react_x", "react_y", "react_dir"]
    t0, t1 = main[0, 0], main[-1, 0]
    assert out[0, 0] == t0 and np.allclose(np.diff(out[:, 0]), 0.025)
    assert out.shape[0] == math.floor((t1 - t0) * 40 + 1e-9) + 1
    assert np.all(np.abs(out[:, 3]) <= math.pi)
    # first row: the demonstration's start relation (0.3 m behind) carried onto MAIN's first pose
    back = main[0, 1:3] - 0.3 * np.array([math.cos(main[0, 3]), math.sin(main[0, 3])])
    assert np.hypot(*(out[0, 1:3] - back)) < 1e-6
    # default table: the demonstration's bounds
    _, demo = read_csv(d / "demo.csv")
    xs, ys = demo[:, [1, 4]], demo[:, [2, 5]]
    assert out[:, 1].min() >= xs.min() - 1e-9 and out[:, 1].max() <= xs.max() + 1e-9
    assert out[:, 2].min() >= ys.min() - 1e-9 and out[:, 2].max() <= ys.max() + 1e-9

def test_truncating_the_future_leaves_earlier_rows_unchanged(files):
    d, main = files
    behave("--train", d / "demo.csv", "--input", d / "main.csv", "--out", d / "full.csv",
           "--table", "1.6,1.0")
    cut = main[:200]
    write_csv(d / "cut.csv", MAIN_HEADER, cut.tolist())
    assert behave("--train", d / "demo.csv", "--input", d / "cut.csv", "--out", d / "part.csv",
                  "--table", "1.6,1.0") == 0
    full = (d / "full.csv").read_text().splitlines()
    part = (d / "part.csv").read_text().splitlines()
    assert len(part) < len(full)
    assert part == full[:len(part)]                      # byte for byte
    assert float(part[-1].split(",")[0]) <= cut[-1, 0]

def test_rate_and_table_options(files):
    d, _ = files
    assert behave("--train", d / "demo.csv", "--input", d / "main.csv", "--out", d / "r20.csv",
                  "--rate", "20", "--table", "0.9,0.7") == 0
    _, out = read_csv(d / "r20.csv")
    assert np.allclose(np.diff(out[:, 0]), 0.05)
    assert out[:, 1].max() <= 0.9 and out[:, 2].max() <= 0.7 and out[:, 1:3].min() >= 0.0

def _bad(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text)
    return p

@pytest.mark.parametrize("what, make, words", [
    ("short", lambda d: "\n".join([",".join(DEMO_HEADER)] + [
        f"{i * 0.025},0.5,0.5,0,0.2,0.5,0" for i in range(20)]), ["demo.csv", "lasts", "window"]),
    ("nan", lambda d: "\n".join([",".join(DEMO_HEADER)] + [
        f"{i * 0.025},0.5,0.5,0,0.2,{'nan' if i == 5 else 0.5},0" for i in range(100)]),
     ["demo.csv", "line 7", "react_y"]),
    ("order", lambda d: "\n".join([",".join(DEMO_HEADER)] + [
        f"{t},0.5,0.5,0,0.2,0.5,0" for t in [0, 0.1, 0.05] + [0.2 + 0.025 * i for i in range(60)]]),
     ["demo.csv", "strictly increase", "line 4"]),
    ("column", lambda d: "\n".join([",".join(DEMO_HEADER[:-1])] + [
        f"{i * 0.025},0.5,0.5,0,0.2,0.5" for i in range(100)]),
     ["demo.csv", "missing", "react_dir"]),
    ("long", lambda d: "\n".join([",".join(DEMO_HEADER)] + [
        f"{t},0.5,0.5,0,0.2,0.5,0" for t in [0.025 * i for i in range(60)] + [4000.0]]),
     ["demo.csv: demonstration lasts 4000 s; at most 3600 s can be trained"]),
    ("milliseconds", lambda d: "\n".join([",".join(DEMO_HEADER)] + [   # a 100 s take in ms
        f"{25.0 * i},0.5,0.5,0,0.2,0.5,0" for i in range(4000)]),
     ["lasts 99975 s; at most 3600 s can be trained; its samples are 25 s apart (median); "
      "times are seconds (milliseconds given?)"]),
    ("far", lambda d: "\n".join([",".join(DEMO_HEADER)] + [
        f"{i * 0.025},0.5,0.5,0,{'1e300' if i == 30 else 0.2},0.5,0" for i in range(100)]),
     ["demo.csv: line 32: column 'react_x': 1e+300 m is beyond 1000 m"]),
])
def test_bad_demonstrations_exit_2_with_one_clear_line(tmp_path, files, capsys, what, make, words):
    d, _ = files
    demo = _bad(tmp_path, "demo.csv", make(d))
    assert behave("--train", demo, "--input", d / "main.csv", "--out", tmp_path / "o.csv") == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "Traceback" not in err and "--param" not in err
    for w in words:
        assert w in err
    assert not (tmp_path / "o.csv").exists()

def test_bad_main_and_arguments(tmp_path, files, capsys):
    d, _ = files
    main = _bad(tmp_path, "main.csv", "t,main_x,main_y\n0,1,1\n")
    assert behave("--train", d / "demo.csv", "--input", main, "--out", tmp_path / "o.csv") == 2
    assert "main_dir" in capsys.readouterr().err
    main = _bad(tmp_path, "main2.csv", "t,main_x,main_y,main_dir\n1,0.5,0.5,0\n0.5,0.5,0.5,0\n")
    assert behave("--train", d / "demo.csv", "--input", main, "--out", tmp_path / "o.csv") == 2
    assert "strictly increase" in capsys.readouterr().err
    for opt, val in (("--rate", "0"), ("--rate", "fast"), ("--table", "1.6"), ("--table", "-1,1")):
        assert behave("--train", d / "demo.csv", "--input", d / "main.csv",
                      "--out", tmp_path / "o.csv", f"{opt}={val}") == 2
        assert opt in capsys.readouterr().err
    assert behave("--train", tmp_path / "none.csv", "--input", d / "main.csv",
                  "--out", tmp_path / "o.csv") == 2
    assert "not found" in capsys.readouterr().err
    main = _bad(tmp_path, "main3.csv", "t,main_x,main_y,main_dir\n0,0.5,0.5,0\n0.5,0.5,-2e3,0\n")
    assert behave("--train", d / "demo.csv", "--input", main, "--out", tmp_path / "o.csv") == 2
    assert "main3.csv: line 3: column 'main_y': -2000.0 m is beyond 1000 m" in \
        capsys.readouterr().err

def test_the_installed_command_runs_without_pygame(files):
    d, _ = files
    code = ("import sys, tabletop.cli as c; rc = c.main(sys.argv[1:]); "
            "assert 'pygame' not in sys.modules; sys.exit(rc)")
    res = subprocess.run([sys.executable, "-c", code, "behave", "--train", str(d / "demo.csv"),
                          "--input", str(d / "main.csv"), "--out", str(d / "sub.csv")],
                         capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr
    # the in-process run of the same files (made here too: tests may run in any order or worker)
    assert behave("--train", d / "demo.csv", "--input", d / "main.csv",
                  "--out", d / "in_process.csv") == 0
    assert (d / "sub.csv").read_text() == (d / "in_process.csv").read_text()

def test_every_behaviour_parameter_can_be_given(files, tmp_path):
    from dataclasses import fields

    from behaviors.puppet_master.engine import Params
    d, main = files
    write_csv(tmp_path / "short.csv", MAIN_HEADER, main[:90].tolist())     # 3 s
    base = ["--train", d / "demo.csv", "--input", tmp_path / "short.csv", "--table", "1.6,1.0"]
    behave(*base, "--out", tmp_path / "default.csv")
    for f in fields(Params):
        value = getattr(Params(), f.name)
        assert behave(*base, "--out", tmp_path / "p.csv", "--param", f"{f.name}={value}") == 0
        # the default given explicitly changes nothing
        assert (tmp_path / "p.csv").read_text() == (tmp_path / "default.csv").read_text(), f.name
    # a parameter changes the output: a 3:1 situation:coherence ratio
    assert behave(*base, "--out", tmp_path / "r3.csv", "--param", "ratio=3",
                  "--param", "smooth=5") == 0
    assert (tmp_path / "r3.csv").read_text() != (tmp_path / "default.csv").read_text()

def test_the_help_names_every_parameter():
    from dataclasses import fields

    from behaviors.puppet_master.engine import Params
    res = subprocess.run([sys.executable, "-m", "tabletop", "behave", "--help"],
                         capture_output=True, text=True, timeout=120,
                         cwd=Path(__file__).resolve().parents[2])
    assert res.returncode == 0, res.stderr
    text = " ".join(res.stdout.split())               # (argparse wraps the help)
    names = text.split("NAME is one of (default): ", 1)[1].split("; their ranges", 1)[0]
    said = dict(item[:-1].split(" (", 1) for item in names.split(", "))
    assert list(said) == sorted(f.name for f in fields(Params))
    # each with its default, its unit, and what a 0 that is not a plain zero stands for
    assert said["window"] == "40 samples" and said["ratio"] == "1" and said["rate_hz"] == "40 Hz"
    assert said["min_speed"] == "0.01 m/s" and said["max_turn_rate"] == "the demonstration's"
    assert said["edge_percentile"] == "off" and said["w_velocity"] == "1"
    assert all(abs(float(v.split()[0]) - getattr(Params(), k)) <= 1e-5 * getattr(Params(), k)
               for k, v in said.items() if v[0].isdigit())     # (shown to 6 digits)

@pytest.mark.parametrize("param, words", [
    ("bogus=1", ["--param bogus", "unknown parameter", "ratio"]),
    ("smoth=5", ["--param smoth (smooth?): unknown parameter"]),     # a typo: the likely name
    ("window=4.5", ["--param window", "integer"]),
    ("ratio=fast", ["--param ratio", "number"]),
    ("ratio", ["--param 'ratio'", "NAME=VALUE"]),
    ("ratio=-1", ["--param", "ratio", "> 0"]),
    ("window=1", ["--param", "window", ">= 2"]),
    # trained for minutes (100 kHz) or ran out of memory (2**50 samples of padding) before
    ("rate_hz=100000", ["--param", "rate_hz", "1 to 1000 Hz"]),
    ("rate_hz=1e-300", ["--param", "rate_hz", "1 to 1000 Hz"]),
    # counted as rows of the main path first: "main.csv: ... inf rows at inf Hz"
    ("rate_hz=inf", ["--param", "rate_hz", "not a finite number"]),
    ("rate_hz=1e6", ["--param", "rate_hz", "1 to 1000 Hz"]),
    ("detail_levels=50", ["--param", "detail_levels", "1 to 10"]),
    # a window longer than the demonstration: the error named the file alone, as if the
    # demonstration were too short
    ("window=100000", ["--param window, ", "demo.csv: demonstration lasts",
                       "a window of 100000 samples at 40 Hz"]),
    # a smooth of 10**8 samples held 1.7 GB and ran for over ten minutes; a weight of 1e20
    # overflowed the training vectors (numpy's warnings on stderr, a run made of them)
    ("smooth=10001", ["--param", "smooth", "from 1 to 10000"]),
    ("patch=10001", ["--param", "patch", "from 1 to 10000"]),
    ("share_window=10001", ["--param", "share_window", "from 1 to 10000"]),
    ("w_velocity=1e20", ["--param", "w_velocity", "from 0 to 1e+06"]),
    ("w_room=1e300", ["--param", "w_room", "from 0 to 1e+06"]),
    # each ran to the end and wrote a reactor, 1e300 as well as 1 (a typo, another unit)
    ("min_speed=5", ["--param", "min_speed: 5.0 must be from 0 to 1 m/s"]),
    ("detail_clip=100", ["--param", "detail_clip: 100.0 must be over 0 and at most 3.14159 rad"]),
    ("ratio=1e300", ["--param", "ratio: 1e+300 must be from 0.001 to 1000"]),
    ("ratio=1e-300", ["--param", "ratio: 1e-300 must be from 0.001 to 1000"]),
    ("balance_gain=1e300", ["--param", "balance_gain: 1e+300 must be over 0 and at most 30"]),
    ("max_extrapolation=100", ["--param", "max_extrapolation: 100.0 must be from 0 to 1 s "
                               "(milliseconds given?)"]),
    ("catch_up=1e300", ["--param", "catch_up: 1e+300 must be from 0 to 40 1/s"]),
    ("half_life=1e300", ["--param", "half_life: 1e+300 must be from 0 to 10000 samples"]),
    ("max_turn_rate=1e300", ["--param", "max_turn_rate: 1e+300 must be from 0",
                             "to 125.664 rad/s (a half turn a step at rate_hz 40)"]),
    ("catch_up=-inf", ["--param", "catch_up: -inf is not a finite number"]),
])
def test_bad_parameters_exit_2_with_one_clear_line(files, tmp_path, capsys, param, words):
    d, _ = files
    assert behave("--train", d / "demo.csv", "--input", d / "main.csv", "--out",
                  tmp_path / "o.csv", "--param", param) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "Traceback" not in err
    for w in words:
        assert w in err, err
    assert not (tmp_path / "o.csv").exists()

@pytest.mark.parametrize("param, words", [
    # a refusal names the field's unit: "min_speed: -0.01 must be >= 0" said nothing of m/s
    ("min_speed=-0.01", "min_speed: -0.01 must be >= 0 m/s"),
    ("max_extrapolation=-1", "max_extrapolation: -1.0 must be >= 0 s"),
    ("detail_clip=0", "detail_clip: 0.0 must be > 0 rad"),
    ("window=1", "window: 1 must be an integer >= 2 samples"),
    ("smooth=20000", "smooth: 20000 must be an integer from 1 to 10000 samples"),
])
def test_a_refused_parameter_names_its_unit(files, tmp_path, capsys, param, words):
    d, _ = files
    assert behave("--train", d / "demo.csv", "--input", d / "main.csv", "--out",
                  tmp_path / "o.csv", "--param", param) == 2
    assert words in capsys.readouterr().err


def test_sequential_training_from_files(files, tmp_path, capsys):
    d, _ = files
    demo = pm_demos.follow_behind(pm_demos.main_path(41, 30))
    # the main take at 60 Hz; the reactor take at 30 Hz against its playback, same time base
    write_csv(tmp_path / "main_take.csv", MAIN_HEADER, demo[:, :4].tolist())
    write_csv(tmp_path / "react_take.csv", ["t", "react_x", "react_y", "react_dir"],
              demo[::2, [0, 4, 5, 6]].tolist())
    assert behave("--train-main", tmp_path / "main_take.csv", "--train-react",
                  tmp_path / "react_take.csv", "--input", d / "main.csv", "--out",
                  tmp_path / "seq.csv", "--table", "1.6,1.0") == 0
    _, seq = read_csv(tmp_path / "seq.csv")
    assert behave("--train", d / "demo.csv", "--input", d / "main.csv",
                  "--out", tmp_path / "two.csv") == 0
    _, two = read_csv(tmp_path / "two.csv")
    assert seq.shape == two.shape
    # the same character: following 0.3 m behind as the two-puck demonstration's output does
    main = np.loadtxt(d / "main.csv", delimiter=",", skiprows=1)
    for out in (seq, two):
        mx = np.interp(out[:, 0], main[:, 0], main[:, 1])
        my = np.interp(out[:, 0], main[:, 0], main[:, 2])
        assert 0.2 < np.median(np.hypot(out[:, 1] - mx, out[:, 2] - my)) < 0.4
    # both takes are needed, and they must overlap in time
    assert behave("--train-main", tmp_path / "main_take.csv", "--input", d / "main.csv",
                  "--out", tmp_path / "o.csv") == 2
    assert "--train-react" in capsys.readouterr().err
    late = demo[::2, [0, 4, 5, 6]].copy()
    late[:, 0] += 100.0
    write_csv(tmp_path / "late.csv", ["t", "react_x", "react_y", "react_dir"], late.tolist())
    assert behave("--train-main", tmp_path / "main_take.csv", "--train-react",
                  tmp_path / "late.csv", "--input", d / "main.csv",
                  "--out", tmp_path / "o.csv") == 2
    assert "does not overlap" in capsys.readouterr().err
    # a main take too short to pair names it too: it named the 30 s reactor take alone
    # ("react_take.csv: demonstration lasts 0.483 s")
    write_csv(tmp_path / "short.csv", MAIN_HEADER, demo[:30, :4].tolist())
    assert behave("--train-main", tmp_path / "short.csv", "--train-react",
                  tmp_path / "react_take.csv", "--input", d / "main.csv", "--out",
                  tmp_path / "o.csv") == 2
    err = capsys.readouterr().err
    assert "short.csv, " in err and "react_take.csv (paired): demonstration lasts" in err
    # a reactor take in milliseconds is refused naming both takes; one recorded on its own
    # clock, 3 s after the main's, trains with the part outside the playback said
    ms = demo[::2, [0, 4, 5, 6]] * [1000.0, 1.0, 1.0, 1.0]
    write_csv(tmp_path / "ms.csv", ["t", "react_x", "react_y", "react_dir"], ms.tolist())
    assert behave("--train-main", tmp_path / "main_take.csv", "--train-react", tmp_path / "ms.csv",
                  "--input", d / "main.csv", "--out", tmp_path / "o.csv") == 2
    err = capsys.readouterr().err
    assert "main_take.csv, " in err and "ms.csv: " in err and "milliseconds given" in err
    own = demo[::2, [0, 4, 5, 6]] + [3.0, 0.0, 0.0, 0.0]
    write_csv(tmp_path / "own.csv", ["t", "react_x", "react_y", "react_dir"], own.tolist())
    assert behave("--train-main", tmp_path / "main_take.csv", "--train-react", tmp_path / "own.csv",
                  "--input", d / "main.csv", "--out", tmp_path / "o.csv", "--table", "1.6,1.0") == 0
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "own.csv: " in err and "left out" in err

@pytest.mark.parametrize("rate", ["--rate=1", "--param=rate_hz=1", "--param=rate_hz=2"])
def test_the_lowest_rates_train_and_generate(files, tmp_path, rate):
    # at 1 Hz the main's 0.5 s still/moving read rounded to no sample: every demonstration
    # failed with an internal IndexError (exit 1), also when a behaviour folder said rate_hz: 1
    d, main = files
    assert behave("--train", d / "demo.csv", "--input", d / "main.csv", "--out",
                  tmp_path / "o.csv", "--table", "1.6,1.0", "--param", "window=10", rate) == 0
    _, out = read_csv(tmp_path / "o.csv")
    hz = float(rate.rpartition("=")[2])
    assert np.allclose(np.diff(out[:, 0]), 1.0 / hz)
    assert np.isfinite(out).all() and len(out) == int((main[-1, 0] - main[0, 0]) * hz) + 1

def test_positions_in_mm_are_refused_naming_the_file(files, tmp_path, capsys):
    """A demonstration (or a main path) recorded in millimetres trained and generated without
    a word: the reactor hundreds of metres from a main given in metres."""
    d, main = files
    _, demo = read_csv(d / "demo.csv")
    mm = demo.copy()
    mm[:, [1, 2, 4, 5]] *= 700.0      # a take within 0.95 m of the corner (over 1000: refused)
    write_csv(tmp_path / "demo_mm.csv", DEMO_HEADER, mm.tolist())
    write_csv(tmp_path / "main.csv", MAIN_HEADER, main[:60].tolist())
    main_mm = main[:60].copy()
    main_mm[:, 1:3] *= 1000.0
    write_csv(tmp_path / "main_mm.csv", MAIN_HEADER, main_mm.tolist())
    for train, path, table in ((tmp_path / "demo_mm.csv", "main.csv", []),
                               (tmp_path / "demo_mm.csv", "main.csv", ["--table", "1.6,1.0"]),
                               (d / "demo.csv", "main_mm.csv", [])):
        assert behave("--train", train, "--input", tmp_path / path,
                      "--out", tmp_path / "o.csv", *table) == 2
        err = capsys.readouterr().err.splitlines()
        bad = train if path == "main.csv" else tmp_path / path
        assert len(err) == 1 and err[0].startswith(f"tabletop behave: error: {bad}: ")
        assert "more than any table (20 m); positions are table metres" in err[0], err
    assert not (tmp_path / "o.csv").exists()

def test_positions_in_mm_that_barely_move_are_refused_naming_the_file(files, tmp_path, capsys):
    """A main path in millimetres standing near (600, 400) mm spans under 20 and passed the
    span check: the reactor was generated hundreds of metres from it. Positions farther from
    the origin than any table side (20 m) are refused, the file named."""
    d, main = files
    rng = np.random.default_rng(3)
    still = main[:60].copy()
    still[:, 1:3] = np.array([600.0, 400.0]) + rng.uniform(-5.0, 5.0, (60, 2))
    assert float(np.ptp(still[:, 1:3], axis=0).max()) < 20.0
    write_csv(tmp_path / "still_mm.csv", MAIN_HEADER, still.tolist())
    _, demo = read_csv(d / "demo.csv")
    small = demo.copy()                 # a small gesture recorded in mm, 0.5 m from the corner
    for c in (1, 2, 4, 5):
        small[:, c] = 500.0 + 5.0 * (demo[:, c] - demo[:, c].mean())
    assert float(np.ptp(small[:, [1, 2, 4, 5]], axis=0).max()) < 20.0
    write_csv(tmp_path / "small_mm.csv", DEMO_HEADER, small.tolist())
    write_csv(tmp_path / "main.csv", MAIN_HEADER, main[:60].tolist())
    for train, path in ((d / "demo.csv", tmp_path / "still_mm.csv"),
                        (tmp_path / "small_mm.csv", tmp_path / "main.csv")):
        assert behave("--train", train, "--input", path, "--out", tmp_path / "o.csv",
                      "--table", "1.6,1.0") == 2
        err = capsys.readouterr().err.splitlines()
        bad = path if train == d / "demo.csv" else train
        assert len(err) == 1 and err[0].startswith(f"tabletop behave: error: {bad}: "), err
        assert "beyond any table side (20 m); positions are table metres" in err[0], err
        assert "millimetres given?" in err[0]
    assert not (tmp_path / "o.csv").exists()
    assert behave("--train", d / "demo.csv", "--input", tmp_path / "main.csv",
                  "--out", tmp_path / "o.csv", "--table", "1.6,1.0") == 0


def test_a_demonstration_whose_reactor_never_moves_is_said(files, tmp_path, capsys):
    # the reactor puck left lying (a millimetre of jitter) while the main moved: the reactor
    # generated stands still, which was written without a word
    d, _ = files
    demo = pm_demos.follow_behind(pm_demos.main_path(41, 30))
    demo[:, 4:7] = demo[0, 4:7]
    demo[::2, 4] += 0.001
    write_csv(tmp_path / "still.csv", DEMO_HEADER, demo.tolist())
    assert behave("--train", tmp_path / "still.csv", "--input", d / "main.csv", "--out",
                  tmp_path / "o.csv", "--table", "1.6,1.0") == 0
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and ("still.csv: the demonstration's reactor never moves (0.1 cm "
                                     "from its first pose, turned 0.00 rad)") in err, err
    _, still = read_csv(tmp_path / "o.csv")
    assert behave("--train", d / "demo.csv", "--input", d / "main.csv", "--out",
                  tmp_path / "o.csv", "--table", "1.6,1.0") == 0
    assert capsys.readouterr().err == ""
    _, moving = read_csv(tmp_path / "o.csv")
    path = [float(np.hypot(*np.diff(o[:, 1:3], axis=0).T).sum()) for o in (still, moving)]
    assert path[0] < 0.2 * path[1], path     # it hardly moves (pushed aside by its main)


def test_directions_in_degrees_are_said(files, tmp_path, capsys):
    # a demonstration and a main path with their directions in degrees trained a look that
    # turned about a radian a step, without a word
    d, main = files
    demo = pm_demos.follow_behind(pm_demos.main_path(41, 30))
    demo[:, [3, 6]] = np.degrees(demo[:, [3, 6]])
    write_csv(tmp_path / "deg.csv", DEMO_HEADER, demo.tolist())
    deg = main.copy()
    deg[:, 3] = np.degrees(deg[:, 3])
    write_csv(tmp_path / "main_deg.csv", MAIN_HEADER, deg.tolist())
    assert behave("--train", tmp_path / "deg.csv", "--input", tmp_path / "main_deg.csv",
                  "--out", tmp_path / "o.csv", "--table", "1.6,1.0") == 0
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 3, err
    assert "deg.csv: column 'main_dir' reaches " in err[0] and "(degrees given?)" in err[0]
    assert "deg.csv: column 'react_dir' reaches " in err[1]
    assert "main_deg.csv: column 'main_dir' reaches " in err[2]
    _, out = read_csv(tmp_path / "o.csv")
    look = np.abs(np.angle(np.exp(1j * np.diff(out[:, 3]))))
    assert float(np.mean(look)) > 0.3, float(np.mean(look))     # what the lines warn of
    unwrapped = main.copy()   # radians unwrapped past a turn are read right: the line only asks
    unwrapped[:, 3] = np.unwrap(unwrapped[:, 3]) + 2 * np.pi
    assert float(np.abs(unwrapped[:, 3]).max()) > 2 * np.pi + 1e-6
    write_csv(tmp_path / "main_unwrapped.csv", MAIN_HEADER, unwrapped.tolist())
    assert behave("--train", d / "demo.csv", "--input", tmp_path / "main_unwrapped.csv",
                  "--out", tmp_path / "o.csv") == 0
    said = capsys.readouterr().err
    assert "main_unwrapped.csv: column 'main_dir' reaches" in said and said.count("\n") == 1


def test_a_main_path_timed_in_milliseconds_is_said(files, tmp_path, capsys):
    # a 20 s main path in milliseconds generated 798,668 rows without a word
    d, main = files
    ms = main[:7].copy()                            # 0.2 s at 30 Hz, in milliseconds: 200 s
    ms[:, 0] = (ms[:, 0] - ms[0, 0]) * 1000.0
    write_csv(tmp_path / "main_ms.csv", MAIN_HEADER, ms.tolist())
    assert behave("--train", d / "demo.csv", "--input", tmp_path / "main_ms.csv", "--out",
                  tmp_path / "o.csv") == 0
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "main_ms.csv: the main path's samples are 33.3333 s apart " \
        "(median); times are seconds (milliseconds given?)" in err, err
    _, out = read_csv(tmp_path / "o.csv")
    assert len(out) == 8001                       # what the line warns of: 200 s at 40 Hz
    # a 60 s path in milliseconds is refused as too long: the refusal says why it may be
    long = main[np.arange(1800) % len(main)].copy()
    long[:, 0] = np.arange(1800) / 30.0 * 1000.0
    write_csv(tmp_path / "long_ms.csv", MAIN_HEADER, long.tolist())
    assert behave("--train", d / "demo.csv", "--input", tmp_path / "long_ms.csv", "--out",
                  tmp_path / "o2.csv") == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "long_ms.csv: the main path spans 59966.7 s" in err and \
        "rows are generated; its samples are 33.3333 s apart (median); times are seconds " \
        "(milliseconds given?)" in err, err
