"""Every subcommand's --help: an option with a default says it, and one with a unit names it."""

from __future__ import annotations

import argparse

import pytest

from tabletop.cli import build_parser


def _commands() -> dict[str, argparse.ArgumentParser]:
    """Every (sub)command's parser by its name: ``run``, ``calibrate board``, ..."""
    out = {}
    for name, p in _sub(build_parser()).items():
        steps = _sub(p)
        out.update({f"{name} {s}": q for s, q in steps.items()} if steps else {name: p})
    return out


def _sub(p: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    return next((a.choices for a in p._actions if isinstance(a, argparse._SubParsersAction)),
                {})


def _helps(command: str) -> dict[str, str]:
    """Option -> its help as printed (``%(default)s`` filled in)."""
    p = _commands()[command]
    fmt = p._get_formatter()
    return {a.option_strings[-1]: fmt._expand_help(a) if a.help else ""
            for a in p._actions if a.option_strings}


def test_an_option_with_a_default_says_it_in_its_help():
    quiet = (None, False, [], argparse.SUPPRESS)
    unsaid = [f"{c} {opt}" for c, p in _commands().items() for a in p._actions
              for opt in a.option_strings[-1:]
              if a.default not in quiet and not (
                  "default" in _helps(c)[opt] and str(a.default) in _helps(c)[opt])]
    assert unsaid == [], unsaid


@pytest.mark.parametrize("command, option, unit", [
    ("run", "--seconds", "seconds"), ("status", "--seconds", "seconds"),
    ("track", "--fps", "frames per second"), ("track", "--calibration", "pixels"),
    ("behave", "--rate", "Hz"), ("behave", "--table", "metres"), ("behave", "--seconds", "seconds"),
    ("behave", "--input", "seconds, table metres, radians"),
    ("behave", "--train-main", "seconds, table metres, radians"),
    ("behave", "--train-react", "seconds, table metres, radians"),
    ("follow", "--window", "template samples"),
    ("pose", "--rate", "steps per second"), ("pose", "--view", "degrees"),
    ("pose", "--table", "metres"), ("pose", "--height", "metres"),
    ("calibrate board", "--dpi", "dots per inch"), ("calibrate board", "--board", "_MM"),
    ("calibrate table", "--marker", "metres"), ("calibrate pattern", "--size", "pixels"),
    ("calibrate projector", "--table", "metres"), ("calibrate projector", "--size", "pixels"),
    ("calibrate check", "--tolerance", "mm"),
])
def test_an_option_with_a_unit_names_it_in_its_help(command, option, unit):
    assert unit in _helps(command)[option], _helps(command)[option]
