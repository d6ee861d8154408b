"""Bad command-line options found at start-up: one line naming the option (or the input file
and its line), a non-zero exit, and nothing of OpenCV's or Python's internals (bad configs:
test_validation.py)."""

import pytest

from tabletop.cli import main as tabletop
from tests.tabletop.test_validation import cli, one_line


def test_a_huge_camera_index(tmp_path, capfd):
    code, err = cli(capfd, "track", "99999999999", "--out", tmp_path / "o.jsonl")
    line = one_line(err)
    assert code == 2 and "INPUT '99999999999'" in line and "0 to 1023" in line


@pytest.mark.parametrize("option, value, words", [
    ("--rate", "1e9", ["--rate '1e9'", "from 1 to 1000"]),
    ("--rate", "nan", ["--rate 'nan'"]),
    ("--table", "1e-300,1", ["--table", "from 0.05 to 20"]),
])
def test_behave_numbers_in_range(tmp_path, capfd, demo, option, value, words):
    code, err = cli(capfd, "behave", "--train", demo, "--input", demo, "--out",
                    tmp_path / "o.csv", option, value)
    line = one_line(err)
    assert code == 2
    for w in words:
        assert w in line


def test_behave_unsorted_times_name_the_file_line(tmp_path, capfd, demo):
    main = tmp_path / "main.csv"
    main.write_text("t,main_x,main_y,main_dir\n\n0,0.3,0.4,0\n60,0.3,0.4,0\n# \n59.9,0.3,0.4,0\n"
                    .replace("# \n", "\n"))
    code, err = cli(capfd, "behave", "--train", demo, "--input", main, "--out", tmp_path / "o.csv")
    line = one_line(err)
    assert code == 2 and "main.csv: line 6:" in line and "59.9 is not after 60.0 (line 4)" in line
    assert "np.float64" not in line


@pytest.mark.parametrize("option, value", [("--sigma", "1e-300"), ("--sigma", "inf"),
                                           ("--window", "0"), ("--window", "2.5"),
                                           ("--window", "1e12")])
def test_follow_numbers_in_range(tmp_path, capfd, option, value):
    tpl = tmp_path / "a.csv"
    tpl.write_text("x,y\n0,0\n1,1\n2,2\n")
    code, err = cli(capfd, "follow", "--template", f"a={tpl}", "--input", tpl, "--out",
                    tmp_path / "o.csv", option, value)
    line = one_line(err)
    assert code == 2 and f"{option} '{value}'" in line


def test_pose_describe_takes_no_input(tmp_path, capfd):
    # --input was silently ignored by --describe (no poses of it were written)
    touches = tmp_path / "t.csv"
    touches.write_text("t,id,x,y\n0,1,0.6,0.5\n")
    code, err = cli(capfd, "pose", "--describe", "--input", touches, "--out", tmp_path / "d.json")
    line = one_line(err)
    assert code == 2 and "--describe" in line and str(touches) in line, line
    assert not (tmp_path / "d.json").exists()


@pytest.mark.parametrize("rows, words", [
    ("0,1,0.6,0.5\n# \n0,1,0.7,0.5\n", "line 4: finger 1 is given twice at t = 0 s"),
    ("0,1,0.6,0.5\n\n1,1.5,0.6,0.5\n", "line 4: id 1.5 must be a whole number"),
    ("1,1,0.6,0.5\n0,1,0.6,0.5\n", "line 3: time 0 s goes back from 1 s (line 2;"),
])
def test_pose_touches_name_the_file_line(tmp_path, capfd, rows, words):
    # they said "data row N" (blank lines not counted) where every other CSV says its line;
    # a finger given twice at one time was taken silently (the last row won)
    touches = tmp_path / "t.csv"
    touches.write_text("t,id,x,y\n" + rows.replace("# \n", "\n"))
    code, err = cli(capfd, "pose", "--input", touches, "--out", tmp_path / "p.jsonl")
    line = one_line(err)
    assert code == 2 and f"{touches}: {words}" in line, line


@pytest.mark.parametrize("rows", [0, 1])
def test_follow_template_too_short_says_what_it_needs(tmp_path, capfd, rows):
    # an empty template said "needs at least 1" row, a one-row one "needs at least 2"
    tpl = tmp_path / "a.csv"
    tpl.write_text("x,y\n" + "0,0\n" * rows)
    code, err = cli(capfd, "follow", "--template", f"a={tpl}", "--input", tpl, "--out",
                    tmp_path / "o.csv")
    line = one_line(err)
    assert code == 2 and f"{tpl}: " in line and "needs at least 2" in line, line


def test_a_usage_error_is_one_line(capfd):
    with pytest.raises(SystemExit) as info:
        tabletop(["behave", "--rate"])
    err = capfd.readouterr().err
    assert info.value.code == 2 and "--rate" in one_line(err)


@pytest.mark.parametrize("argv, words", [
    (["studio"], "invalid choice: 'studio'", ),
    (["kiosk", "--seconds", "5"], "invalid choice: 'kiosk'"),
    (["run", "--studio2"], "tabletop run: error: unrecognized arguments: --studio2 "
                           "(see tabletop run --help)"),
    (["calibrate", "board", "--out", "b.png", "extra"],
     "tabletop calibrate board: error: unrecognized arguments: extra "
     "(see tabletop calibrate board --help)"),
])
def test_a_usage_error_points_to_the_right_command(capfd, argv, words):
    # `tabletop studio` is what a designer types: the studio is a mode of run; an unknown
    # option was blamed on `tabletop` and sent to its --help, not to the command's
    with pytest.raises(SystemExit) as info:
        tabletop(argv)
    line = one_line(capfd.readouterr().err)
    assert info.value.code == 2 and words in line, line
    if argv[0] in ("studio", "kiosk"):
        assert line.endswith(f"(the {argv[0]} is `tabletop run --{argv[0]}`)"), line


@pytest.mark.parametrize("option, value, words", [
    ("--rate", "1e9", ["--rate '1e9'", "from 1 to 1000"]),
    ("--rate", "0", ["--rate '0'"]),
    ("--table", "1e300,1", ["--table '1e300,1'", "from 0.05 to 20"]),
    ("--height", "1e300", ["--height '1e300'", "from 0.01 to 20"]),
])
def test_pose_numbers_in_range(tmp_path, capfd, option, value, words):
    """Numbers that made ``pose`` run for hours (2 s of touches at 1e9 Hz) or write overflowed
    poses are refused at once."""
    touches = tmp_path / "t.csv"
    touches.write_text("t,id,x,y\n0,1,0.6,0.5\n0.1,1,0.6,0.52\n")
    out = tmp_path / "p.jsonl"
    code, err = cli(capfd, "pose", "--input", touches, "--out", out, option, value)
    line = one_line(err)
    assert code == 2 and not out.exists()
    for w in words:
        assert w in line


def test_pose_touches_spanning_too_long_a_time(tmp_path, capfd):
    touches = tmp_path / "t.csv"
    touches.write_text("t,id,x,y\n0,1,0.6,0.5\n1e9,1,0.6,0.52\n")
    code, err = cli(capfd, "pose", "--input", touches, "--out", tmp_path / "p.jsonl")
    line = one_line(err)
    assert code == 2 and "t.csv: the touches span 1e+09 s" in line and "1,000,000 steps" in line


@pytest.mark.parametrize("command", [["run", "--config", "absent.yaml"], ["status", "127.0.0.1:9"]])
@pytest.mark.parametrize("value, words", [("x", "is not a number (seconds)"),
                                          ("nan", "from 0.001 to"), ("-2", "from 0.001 to")])
def test_seconds_said_alike_by_run_and_status(capfd, command, value, words):
    code, err = cli(capfd, *command, "--seconds", value)
    line = one_line(err)
    assert code == 2 and f"--seconds '{value}'" in line and words in line
