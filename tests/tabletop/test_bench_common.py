"""The benches' command line (bench.common.check_flags): a wrong argument is refused before
minutes of measuring. The scripts' ``main`` runs in-process here (what it says and its exit);
``test_bench_flags.py`` runs every script in an interpreter of its own."""

import importlib
import sys

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


def bench_exit(name: str, args: list[str], monkeypatch) -> SystemExit:
    """How ``bench/NAME.py ARGS``'s ``main`` ended (it must end before measuring)."""
    monkeypatch.setattr(sys, "argv", [f"bench/{name}.py", *args])
    with pytest.raises(SystemExit) as ended:
        importlib.import_module(f"bench.{name}").main()
    return ended.value


def bench_help(name: str, capsys, monkeypatch) -> str:
    """What ``bench/NAME.py --help`` prints, once it exited 0 naming the sections."""
    capsys.readouterr()
    assert bench_exit(name, ["--help"], monkeypatch).code in (0, None)
    out = capsys.readouterr().out
    assert f"sections: {', '.join(SECTION_NAMES)}" in out
    return out


def test_follow_quality_answers_help_before_measuring(capsys, monkeypatch):
    out = bench_help("follow_quality", capsys, monkeypatch)
    assert "[--sigma=X]" in out and "sigma: a number in 0.001..100" in out
    assert "[--seed=X]" in out and "seed: a number in 0..999999" in out


def test_follow_quality_refuses_a_seed_that_is_no_whole_number(monkeypatch):
    # a message as the exit code: the interpreter prints it on stderr and exits 1
    refused = bench_exit("follow_quality", ["--seed=1.5"], monkeypatch)
    assert refused.code == "follow_quality: --seed: expected a whole number, got '1.5'"


def test_follow_seeds_takes_whole_seeds_the_sections_a_follower_and_refuses_the_rest():
    from bench.follow_seeds import SEEDS, parse
    assert parse([]) == (SEEDS, None, "puck") and SEEDS == (101, 102, 103, 104, 105, 106)
    assert parse(["--seeds=7,8", "--sections=sized,unrelated", "--follower=cli_scale"]) == (
        (7, 8), {"sized", "unrelated"}, "cli_scale")
    for args, said in ((["--seeds=7,x"], "follow_seeds: --seeds: expected a number in 0..999999, "
                        "got 'x'"),
                       (["--seeds=1.5"],
                        "follow_seeds: --seeds: expected whole numbers, got '1.5'"),
                       (["--seeds="], "follow_seeds: --seeds: expected a number in 0..999999, "
                        "got ''"),
                       (["--sections=sized,sizes"], "follow_seeds: --sections: unknown 'sizes'"),
                       (["--seed=7"], "follow_seeds: unknown argument '--seed=7'"),
                       (["--follower=paper"], "follow_seeds: --follower: unknown 'paper'"),
                       (["--follower=puck,cli_scale"],
                        "follow_seeds: --follower: expected one name, got 'puck,cli_scale'")):
        with pytest.raises(SystemExit) as refused:
            parse(args)
        assert str(refused.value.code).splitlines()[0] == said


def test_follow_seeds_answers_help_before_measuring(capsys, monkeypatch):
    out = bench_help("follow_seeds", capsys, monkeypatch)
    assert "[--seeds=X]" in out and "seeds: a number in 0..999999" in out
