"""The benches' command line (bench.common.check_flags): a wrong argument is refused before
minutes of measuring."""

import subprocess
import sys
from pathlib import Path

import pytest

from bench.common import check_flags
from bench.follow_quality import SECTION_NAMES

SECTIONS = {"sections": SECTION_NAMES}


def test_a_wrong_command_line_is_refused_with_one_line_naming_it(capsys):
    check_flags("follow_quality", ["--debug", "--sections=sized,holds"], ["--debug"], SECTIONS)
    for args, said in ((["--sections=sized,sizes"], "follow_quality: --sections: unknown 'sizes'"),
                       (["--fast"], "follow_quality: unknown argument '--fast'"),
                       (["--sections="], "follow_quality: unknown argument '--sections='")):
        with pytest.raises(SystemExit) as refused:
            check_flags("follow_quality", args, ["--debug"], SECTIONS)
        assert str(refused.value.code).splitlines()[0] == said
    with pytest.raises(SystemExit) as helped:
        check_flags("follow_quality", ["--help"], ["--debug"], SECTIONS)
    assert helped.value.code == 0
    assert "sections: sized, holds, sequences" in capsys.readouterr().out


def test_a_number_option_is_refused_outside_its_range(capsys):
    numbers = {"sigma": (1e-3, 100.0)}
    check_flags("follow_quality", ["--sigma=0.15"], [], SECTIONS, numbers)
    for value in ("abc", "0", "", "nan"):
        with pytest.raises(SystemExit) as refused:
            check_flags("follow_quality", [f"--sigma={value}"], [], SECTIONS, numbers)
        assert str(refused.value.code).splitlines()[0] == (
            f"follow_quality: --sigma: expected a number in 0.001..100, got {value!r}")


def test_follow_quality_answers_help_before_measuring():
    bench = Path(__file__).resolve().parents[2] / "bench" / "follow_quality.py"
    r = subprocess.run([sys.executable, str(bench), "--help"], capture_output=True, text=True,
                       timeout=120)
    assert r.returncode == 0 and f"sections: {', '.join(SECTION_NAMES)}" in r.stdout
    assert "[--sigma=X]" in r.stdout and "sigma: a number in 0.001..100" in r.stdout
    assert "[--seed=X]" in r.stdout and "seed: a number in 0..999999" in r.stdout


def test_follow_quality_refuses_a_seed_that_is_no_whole_number():
    bench = Path(__file__).resolve().parents[2] / "bench" / "follow_quality.py"
    r = subprocess.run([sys.executable, str(bench), "--seed=1.5"], capture_output=True, text=True,
                       timeout=120)
    assert r.returncode == 1
    assert r.stderr.strip() == "follow_quality: --seed: expected a whole number, got '1.5'"
