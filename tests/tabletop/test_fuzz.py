"""Property: whatever configs, CSVs, recordings and argument lists every command is given, it
either succeeds or prints exactly one line saying what is wrong and exits non-zero; never a
traceback, an "internal error", nor a line from OpenCV, libpng or Python itself."""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import signal
import tempfile
from pathlib import Path
from typing import Iterator

import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tabletop import cli

ROOT = Path(__file__).resolve().parents[2]

# TABLETOP_FUZZ_EXAMPLES=500 searches harder (minutes instead of seconds).
SETTINGS = settings(max_examples=int(os.environ.get("TABLETOP_FUZZ_EXAMPLES", "30")), deadline=None,
                    database=None,
                    suppress_health_check=[HealthCheck.function_scoped_fixture,
                                           HealthCheck.too_slow])
CALL_LIMIT_S = 60  # a command that takes longer on these small inputs is a bug


@contextlib.contextmanager
def alarm(seconds: int) -> Iterator[None]:
    def fire(signum, frame):
        raise TimeoutError(f"took more than {seconds} s")
    old = signal.signal(signal.SIGALRM, fire)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)


@contextlib.contextmanager
def workdir() -> Iterator[Path]:
    old = os.getcwd()
    with tempfile.TemporaryDirectory(prefix="tabletop-fuzz-") as tmp:
        os.chdir(tmp)
        try:
            yield Path(tmp)
        finally:
            os.chdir(old)


def check(capfd, argv: list[str], expect: str | None = None) -> int:
    """Run one command in this process; assert the property (and that its error names
    ``expect`` where given); return its exit status."""
    capfd.readouterr()
    with alarm(CALL_LIMIT_S):
        try:
            code = cli.main(argv)
        except SystemExit as exc:  # argparse: usage errors, --help
            code = exc.code if isinstance(exc.code, int) else 2
    err = capfd.readouterr().err
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert "Traceback" not in err and "internal error" not in err, (argv, err)
    foreign = [ln for ln in lines if not ln.startswith(("tabletop", "\rtrack", "track ["))]
    assert not foreign, (argv, err)
    if code != 0:
        errors = [ln for ln in lines if ": error:" in ln]
        assert len(errors) == 1, (argv, err)
        assert code not in (0, 1), (argv, code, err)  # 1: the CLI's "internal error"
    assert expect is None or expect in err, (argv, err)
    return code


# --- generated values ---------------------------------------------------------------------------

NUMBERS = ["0", "-1", "1", "0.5", "40", "1e9", "1e-300", "nan", "inf", "-inf", "99999999999",
           "1e400", "1,1", "0,0", "-1,5", "1e9,1e9", "nan,1", "1,2,3", "20,15"]
WORDS = ["", " ", "x", "-", "DICT_4X4_50", "DICT_NOPE", "7x5:40:30:DICT_5X5_100", "0x0:1:1:X",
         "a=b", "=x.csv", "NAME=", "é", "a" * 300]
FILES = ["binary.bin", "empty.csv", "folder", "absent.csv", "good.csv", "demo.csv", "bad.yaml",
         "good.yaml", "session.jsonl", "bad.jsonl", "image.png", "bad.png", "folder/out.csv",
         "../" * 30 + "x"]


def make_files(root: Path) -> None:
    (root / "binary.bin").write_bytes(bytes(range(256)) * 4)
    (root / "empty.csv").write_text("")
    (root / "folder").mkdir()
    (root / "good.csv").write_text("t,x,y\n0,0,0\n0.1,0.01,0\n0.2,0.02,0.01\n0.3,0.02,0.03\n")
    rows = ["t,main_x,main_y,main_dir,react_x,react_y,react_dir"]
    rows += [f"{i / 20},{0.3 + 0.004 * i},0.4,0,{0.5 + 0.002 * i},0.45,0" for i in range(40)]
    (root / "demo.csv").write_text("\n".join(rows) + "\n")
    (root / "bad.yaml").write_text("sources: [kind: [\n")
    (root / "good.yaml").write_text("sources: [{kind: scripted}]\nview: {enabled: false}\n")
    (root / "session.jsonl").write_text(
        json.dumps({"format": "tabletop-session", "version": 2, "files": {},
                    "config": {"sources": [{"kind": "scripted"}], "view": {"enabled": False}}})
        + "\n" + "".join(json.dumps({"seq": i, "t": i / 60}) + "\n" for i in range(10)))
    (root / "bad.jsonl").write_bytes(b'{"format": "tabletop-session", "version": 2}\n\xff\x00\n')
    import cv2
    import numpy as np
    cv2.imwrite(str(root / "image.png"), np.full((48, 64), 200, np.uint8))
    (root / "bad.png").write_bytes(b"\x89PNG\r\n\x1a\nnot really")


def option_table(parser: argparse.ArgumentParser, prefix: tuple[str, ...] = ()):
    """(argv prefix, options taking a value, flags, positional count) for every (sub)command."""
    subs = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    if subs:
        for name, sub in subs[0].choices.items():
            yield from option_table(sub, prefix + (name,))
        return
    valued, flags, positional = [], [], 0
    for a in parser._actions:
        if isinstance(a, argparse._HelpAction):
            continue
        if not a.option_strings:
            positional += 1
        elif a.nargs == 0:
            flags.append(a.option_strings[-1])
        else:
            valued.append(a.option_strings[-1])
    yield prefix, valued, flags, positional


COMMANDS = list(option_table(cli.build_parser()))

value = st.one_of(st.sampled_from(NUMBERS), st.sampled_from(WORDS), st.sampled_from(FILES),
                  st.text(max_size=12))


@st.composite
def argument_lists(draw) -> list[str]:
    prefix, valued, flags, positional = draw(st.sampled_from(COMMANDS))
    argv = list(prefix)
    argv += [draw(value) for _ in range(draw(st.integers(0, positional + 1)))]
    for _ in range(draw(st.integers(0, 5))):
        if valued and draw(st.booleans()):
            argv += [draw(st.sampled_from(valued)), draw(value)]
        elif flags:
            argv.append(draw(st.sampled_from(flags)))
    if prefix == ("run",):
        argv += ["--seconds", "0.05", "--headless"]
    return argv


@SETTINGS
@given(argv=argument_lists())
def test_argument_lists(capfd, argv):
    with workdir() as root:
        make_files(root)
        check(capfd, argv)


@pytest.mark.parametrize("argv", [["review", ""], ["review", "session.jsonl", "--out", ""],
                                  ["replay", ""], ["run", "--config", ""]])
def test_an_empty_path_is_refused_in_one_line(capfd, argv):
    # an empty path is the current folder ('review' once failed deriving its --out from it)
    with workdir() as root:
        make_files(root)
        (root / "session.jsonl").write_text("", encoding="utf-8")
        assert check(capfd, argv) != 0


@pytest.mark.parametrize("argv", [["run", "--config", "a\x00.yaml"],
                                  ["review", "session.jsonl", "--out", "x\x00.png"],
                                  ["track", "image.png", "--out", "p.jsonl",
                                   "--dictionary", "\x00"]])
def test_a_nul_character_in_an_argument_is_refused_in_one_line(capfd, argv):
    # (a shell cannot pass one; a script calling main() can: os.stat raised ValueError)
    with workdir() as root:
        make_files(root)
        assert check(capfd, argv, expect="NUL character") != 0


@pytest.mark.parametrize("argv", [
    ["follow", "--template", "a=good.csv", "--input", "good.csv", "--out", "./good.csv"],
    ["follow", "--template", "a=good.csv", "--input", "image.png", "--out", "folder/../good.csv"],
    ["behave", "--train", "demo.csv", "--input", "good.csv", "--out", "./demo.csv"],
    ["pose", "--input", "good.csv", "--out", "good.csv"],
    ["review", "session.jsonl", "--out", "./session.jsonl"],
    ["replay", "session.jsonl", "--no-view", "--fast", "--out", "session.jsonl"],
    ["track", "image.png", "--out", "./image.png"]])
def test_an_output_naming_an_input_is_refused_and_the_input_kept(capfd, argv):
    with workdir() as root:
        make_files(root)
        target = root / argv[-1]
        before = target.read_bytes()
        assert check(capfd, argv, expect="is the input file") != 0
        assert target.read_bytes() == before


# --- generated configs ----------------------------------------------------------------------------

LEAVES = st.one_of(st.none(), st.booleans(), st.integers(-10**6, 10**12),
                   st.floats(allow_nan=True, allow_infinity=True), st.sampled_from(WORDS + FILES),
                   st.lists(st.integers(-5, 100), max_size=4))
BASE = {
    "table": {"width": 1.2, "height": 0.8},
    "loop": {"rate_hz": 60},
    "sources": [{"kind": "scripted", "name": "visitor", "pucks": [1, 2], "seed": 0,
                 "performers": [{"puck": 3, "home": [0.5, 0.4], "gestures": ["good.csv"]}]}],
    "engines": [{"kind": "puppet_master", "name": "lover", "behavior": "lover",
                 "main": {"puck": 1}, "size": 0.08}],
    "tracking": {"dictionary": "DICT_4X4_50", "puck_ids": {"7": 1}},
    "view": {"enabled": False, "size": [320, 200], "sprites": {}},
    "recorder": {"enabled": False, "folder": "sessions", "max_mb": 1, "keep": 2},
    "calibration": None,
}


def paths_of(value, path=()):
    yield path
    if isinstance(value, dict):
        for k, v in value.items():
            yield from paths_of(v, path + (k,))
    elif isinstance(value, list):
        for i, v in enumerate(value):
            yield from paths_of(v, path + (i,))


MOP = yaml.safe_load((ROOT / "examples" / "mop.yaml").read_text())
MOP["view"] = {"enabled": False}


@st.composite
def configs(draw) -> str:
    cfg = json.loads(json.dumps(draw(st.sampled_from([BASE, MOP]))))
    for _ in range(draw(st.integers(1, 3))):
        paths = [p for p in paths_of(cfg) if p]
        path = draw(st.sampled_from(paths))
        parent = cfg
        for k in path[:-1]:
            parent = parent[k]
        how = draw(st.sampled_from(["replace", "delete", "add"]))
        if how == "replace":
            parent[path[-1]] = draw(LEAVES)
        elif how == "delete" and isinstance(parent, dict):
            del parent[path[-1]]
        elif isinstance(parent, dict):
            parent[draw(st.sampled_from(["extra", "kind", "name", "path", "calibration"]))] = \
                draw(LEAVES)
    text = yaml.safe_dump(cfg)
    if draw(st.integers(0, 9)) == 0:  # now and then, damage the text itself
        cut = draw(st.integers(0, len(text)))
        text = text[:cut] \
            + draw(st.sampled_from(["\t", ": :", "[", "\x00", "key: 1\nkey: 2\n"])) + text[cut:]
    return text


def copy_referenced(root: Path) -> None:
    """The files the base configs name: a behaviour and the MOP example's gestures and sheet."""
    import shutil
    shutil.copytree(ROOT / "behaviors" / "library" / "lover", root / "lover")
    shutil.copytree(ROOT / "examples" / "mop", root / "mop")


@SETTINGS
@given(text=configs())
def test_generated_configs(capfd, text):
    with workdir() as root:
        make_files(root)
        copy_referenced(root)
        (root / "kiosk.yaml").write_text(text)
        check(capfd, ["run", "--config", "kiosk.yaml", "--seconds", "0.05", "--headless"])


# --- generated CSVs -------------------------------------------------------------------------------

CELL = st.one_of(st.floats(-1e6, 1e6).map(repr), st.sampled_from(["", "nan", "inf", "x", "1e400",
                                                                   "-0", " 1 ", "1,5"]),
                 st.integers(-10, 10).map(str))


@st.composite
def csvs(draw, columns: list[str]) -> str:
    header = list(draw(st.permutations(columns)))
    if draw(st.integers(0, 4)) == 0:
        header = header[:-1] + [draw(st.sampled_from(["", "t", "extra", header[0]]))]
    rows = []
    n = draw(st.integers(0, 30))
    regular = draw(st.booleans())
    for i in range(n):
        if regular:
            row = [repr(i * 0.05) if c == "t" else repr(0.3 + 0.01 * i * (k % 3))
                   for k, c in enumerate(header)]
            if draw(st.integers(0, 9)) == 0:
                row[draw(st.integers(0, len(row) - 1))] = draw(CELL)
        else:
            row = [draw(CELL) for _ in header]
        rows.append(",".join(row))
    return "\n".join([",".join(header)] + rows) + draw(st.sampled_from(["\n", "", "\n\n"]))


DEMO = ["t", "main_x", "main_y", "main_dir", "react_x", "react_y", "react_dir"]


@SETTINGS
@given(demo=csvs(DEMO), main=csvs(DEMO[:4]))
def test_generated_behave_csvs(capfd, demo, main):
    with workdir() as root:
        (root / "demo.csv").write_text(demo)
        (root / "main.csv").write_text(main)
        check(capfd, ["behave", "--train", "demo.csv", "--input", "main.csv", "--out", "o.csv"])


@SETTINGS
@given(a=csvs(["t", "x", "y"]), b=csvs(["t", "x", "y"]), perf=csvs(["t", "x", "y"]))
def test_generated_follow_csvs(capfd, a, b, perf):
    with workdir() as root:
        for name, text in (("a", a), ("b", b), ("perf", perf)):
            (root / f"{name}.csv").write_text(text)
        check(capfd, ["follow", "--template", "a=a.csv", "--template", "b=b.csv", "--input",
                      "perf.csv", "--out", "o.csv"])


# --- generated recordings -------------------------------------------------------------------------

FRAME = st.fixed_dictionaries({
    "seq": st.one_of(st.integers(0, 10**6), st.sampled_from([-1, "3", None, 1.5])),
    "t": st.one_of(st.floats(-1, 1e3), st.sampled_from([1e12, "0", None, float("nan")])),
}, optional={
    "pucks": st.lists(st.fixed_dictionaries({"id": st.integers(0, 9), "x": LEAVES,
                                             "y": st.floats(0, 1),
                                             "angle": st.floats(-4, 4)}), max_size=3),
    "streams": st.dictionaries(st.text(max_size=3), st.lists(st.floats(), max_size=3), max_size=2),
    "commands": st.one_of(st.lists(st.sampled_from(["designer.record", "designer.keep", 3])),
                          st.just("x")),
    "focus": st.one_of(st.none(), st.text(max_size=4), st.integers()),
    "t0": st.one_of(st.floats(0, 1e6), st.just("x")),
})

HEADER = {"format": "tabletop-session", "version": 2, "files": {},
          "config": {"sources": [{"kind": "scripted"}], "view": {"enabled": False},
                     "engines": [{"kind": "puppet_master", "name": "lover",
                                  "behavior": "lover", "main": {"puck": 1}}]}}


@st.composite
def recordings(draw) -> bytes:
    header = json.loads(json.dumps(HEADER))
    for name in ("behavior.yaml", "demonstration.csv"):
        text = (ROOT / "behaviors" / "library" / "lover" / name).read_text()
        header["files"][f"lover/{name}"] = {"text": text}
    damage = draw(st.integers(0, 6))
    if damage == 0:
        header[draw(st.sampled_from(["version", "config", "files", "format"]))] = draw(LEAVES)
    elif damage == 1:
        header["files"][draw(st.sampled_from(["../x", "/etc/x", "a/../../b", ""]))] = {"text": "x"}
    elif damage == 2:
        header["files"]["lover/demonstration.csv"]["sha256"] = "0" * 64
    lines = [json.dumps(header).encode()]
    t = 0.0
    for i in range(draw(st.integers(0, 20))):
        if draw(st.integers(0, 5)) == 0:
            frame = draw(FRAME)
        else:
            t += draw(st.floats(0, 0.1))
            frame = {"seq": i, "t": t, "pucks": [{"id": 1, "x": 0.3 + t / 10, "y": 0.4,
                                                   "angle": 0.0}]}
        lines.append(json.dumps(frame).encode())
    if draw(st.integers(0, 5)) == 0:
        lines.append(draw(st.binary(max_size=20)))
    return b"\n".join(lines) + draw(st.sampled_from([b"\n", b""]))


@SETTINGS
@given(data=recordings())
def test_generated_recordings(capfd, data):
    with workdir() as root:
        (root / "s.jsonl").write_bytes(data)
        check(capfd, ["replay", "s.jsonl", "--fast", "--no-view", "--out", "r.jsonl"])


def test_a_folder_holding_an_unreadable_image_is_refused_in_one_line(capfd):
    # the folder's images are read in order: bad.png (a PNG signature, then no chunks) comes
    # before image.png; the error is the only line (no OpenCV "[ WARN:0@...]" lines above it)
    with workdir() as root:
        make_files(root)
        assert check(capfd, ["track", "", "--out", "0"]) != 0
        assert check(capfd, ["track", ".", "--out", "o.jsonl"]) != 0
