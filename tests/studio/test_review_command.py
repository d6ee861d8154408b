"""``tabletop review``: a studio session log drawn as a contact sheet of its tries; what is no
session log (a bad line or field, a recording, a take, a sheet, a device) refused in one line."""

from pathlib import Path

import numpy as np
import pytest

from tabletop.cli import main as cli

ROOT = Path(__file__).resolve().parents[2]


def test_review_refuses_a_bad_session_log_in_one_line(tmp_path, capsys):
    log = tmp_path / "s.jsonl"
    log.write_text('{"target": "pet"}\nnot json\n{"target": "pet"}\n')
    assert cli(["review", str(log)]) == 2
    err = capsys.readouterr().err
    assert "s.jsonl:2" in err and len(err.splitlines()) == 1
    assert cli(["review", str(tmp_path / "missing.jsonl")]) == 2


@pytest.mark.parametrize("line, words", [
    ('{"target": "pet", "duration_s": "x"}', "duration_s is 'x', expected a number of seconds"),
    ('{"target": "pet", "training_s": -1}', "training_s is '-1', expected a number"),
    ('{"target": ["pet"]}', "target is \"['pet']\", expected a string"),
    ("not json", "not a session log line"),
    ("[" * 100_000, "not a session log line (nested too deep"),
])
def test_review_names_a_bad_field_of_a_complete_last_line(tmp_path, capsys, line, words):
    # (a wrong field was an internal error; a complete last line that is wrong was skipped as
    # if a power cut had cut it: only a line without its newline is)
    log = tmp_path / "s.jsonl"
    log.write_text('{"target": "pet", "outcome": "kept", "duration_s": 4.0}\n' + line + "\n")
    assert cli(["review", str(log)]) == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and "s.jsonl:2: " in err and words in err, err
    log.write_text('{"target": "pet", "outcome": "kept", "duration_s": 4.0}\n' + line[:12])
    assert cli(["review", str(log)]) == 0               # cut short: the tries before it


@pytest.mark.parametrize("text, code, words", [
    ("KEPT\n\n  \n", 0, None),    # an editor's blank lines at the end
    ("KEPT\n\nKEPT\n", 2, "s.jsonl:2: a blank line between tries"),
    ('{"format": "tabletop-session", "version": 3}\n', 2,
     "s.jsonl: a session recording (`tabletop replay` plays it), not a studio session log"),
])
def test_review_of_blank_lines_and_of_a_recording(tmp_path, capsys, text, code, words):
    # (a blank line said JSON's "Expecting value"; a recording "not a session log line (not a
    # try)")
    log = tmp_path / "s.jsonl"
    log.write_text(text.replace("KEPT", '{"target": "pet", "outcome": "kept", "duration_s": 4}'))
    assert cli(["review", str(log), "--out", str(tmp_path / "sheet.png")]) == code
    err = capsys.readouterr().err.strip().splitlines()
    assert (err == []) if words is None else (len(err) == 1 and words in err[0]), err


@pytest.mark.parametrize("columns, words", [
    ("", "--columns: the value is empty"),            # (both were argparse's "invalid int
    ("x", "--columns 'x' is not a whole number"),     # value: ''", unlike every other number)
    ("0", "--columns '0' must be a whole number of sheets per row from 1 to 1e+06"),
])
def test_review_columns_that_are_no_count_are_named(tmp_path, capsys, columns, words):
    log = tmp_path / "s.jsonl"
    log.write_text('{"target": "pet", "outcome": "kept", "duration_s": 4.0}\n')
    assert cli(["review", str(log), "--columns", columns]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"tabletop review: error: {words}"), err


@pytest.mark.parametrize("name", ["sheet.jpg", "sheet.txt", "sheet"])
def test_review_refuses_a_sheet_name_that_is_no_png(tmp_path, capsys, name):
    # the sheet is PNG bytes: under a .jpg name a viewer refuses or misreads it
    log = tmp_path / "s.jsonl"
    log.write_text('{"target": "pet", "outcome": "kept", "duration_s": 4.0}\n')
    assert cli(["review", str(log), "--out", str(tmp_path / name)]) == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and "written as PNG" in err and "sheet.png" in err, err
    assert not (tmp_path / name).exists()


def test_review_sheet_title_stays_on_the_sheet(tmp_path):
    # the summary was one centred line wider than a one-try sheet: cut at both edges
    import matplotlib.image as mpimg
    log = tmp_path / "session-20261203-071321.jsonl"
    log.write_text('{"target": "lover", "outcome": "kept", "name": "lover", "duration_s": 10.7, '
                   '"samples": 246, "training_s": 0.217}\n')
    out = tmp_path / "sheet.png"
    assert cli(["review", str(log), "--out", str(out)]) == 0
    img = mpimg.imread(str(out))[..., :3].sum(axis=2)           # white 3.0, text darker
    top = img[: img.shape[0] // 8]                               # the title's band
    assert (top < 2.0).any()                                     # the title is drawn
    assert (top[:, :4] > 2.9).all() and (top[:, -4:] > 2.9).all()   # within the edges


def test_review_with_more_columns_than_tries_draws_the_tries_wide(tmp_path, capsys):
    """--columns 100000 on a two-try log drew a figure 100,000 sheets wide (minutes, gigabytes);
    the sheet is as wide as its tries."""
    import matplotlib.image as mpimg
    log = tmp_path / "s.jsonl"
    log.write_text('{"target": "pet", "outcome": "kept"}\n{"target": "pet"}\n')
    widths = []
    for columns in ("2", "100000"):
        out = tmp_path / f"sheet-{columns}.png"
        assert cli(["review", str(log), "--columns", columns, "--out", str(out)]) == 0
        widths.append(mpimg.imread(str(out)).shape[1])
    assert widths[0] == widths[1] and "2 tries, 1 kept" in capsys.readouterr().out


def test_an_action_review_sheet_shows_the_take_and_its_followed_progress(tmp_path):
    from tabletop.files import read_csv
    from tabletop.studio.review import followed_progress, review_sheet
    _, g = read_csv(ROOT / "examples" / "mop" / "gestures" / "circle.csv")
    take = g[::2, 1:3]                     # dx, dy at 30 Hz
    truth, got = followed_progress(take)
    assert np.abs(truth - got)[len(got) // 4:].mean() < 0.1   # the follower keeps up
    review_sheet("action", take, tmp_path / "try.png", title="lizard: kept take1")
    assert (tmp_path / "try.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_review_cells_are_as_tall_as_their_sheets(tmp_path):
    """The contact sheet's cells were 400 x 360 px for sheets of 640 x 288 scaled to 176 px
    tall: 146 px of every cell blank, the sheet half empty. A cell is its caption and its
    sheet: no white band between one row's sheets and the next row's caption."""
    import matplotlib.image as mpimg
    import numpy as np
    from PIL import Image
    Image.new("RGB", (640, 288), (90, 90, 90)).save(tmp_path / "try.png")
    log = tmp_path / "s.jsonl"
    log.write_text('{"target": "pet", "outcome": "kept", "review": "try.png"}\n' * 3)
    out = tmp_path / "sheet.png"
    assert cli(["review", str(log), "--columns", "1", "--out", str(out)]) == 0
    img = mpimg.imread(str(out))[..., :3].sum(axis=2)
    grey = np.flatnonzero((np.abs(img - 3 * 90 / 255) < 0.05).sum(axis=1) > 300)  # sheets' rows
    assert len(grey) >= 3 * 150, len(grey)
    white = (img > 2.95).all(axis=1)
    runs, n = [], 0
    for w in white[grey[0]:]:            # from the first sheet down: blank rows in a row
        n = n + 1 if w else 0
        runs.append(n)
    assert max(runs) < 40, max(runs)     # a caption's margins, never a blank band
    assert img.shape[0] < 3 * 260, img.shape


def test_review_and_replay_given_the_studios_other_files_name_the_one_to_give(tmp_path,
                                                                             capsys):
    """A take saved at quit or a review sheet given to ``review`` said "not a session log line
    (Expecting value: line 1 column 1 (char 0))", and a studio session log given to ``replay``
    "line 1: not a tabletop-session header": each names what it is and the file to give."""
    log = tmp_path / "session-20260101-120000.jsonl"
    log.write_text('{"target": "pet", "outcome": "quit", "duration_s": 4.0, '
                   '"take": "session-20260101-120000-take001.csv"}\n')
    (tmp_path / "session-20260101-120000-take001.csv").write_text("t,main_x\n0,0\n")
    (tmp_path / "session-20260101-120000-take001-react.csv").write_text("t,react_x\n0,0\n")
    (tmp_path / "session-20260101-120000-try001.png").write_bytes(b"\x89PNG\r\n\x1a\n\0\0")
    assert cli(["review", str(tmp_path)]) == 2       # the studio folder: its latest log named
    assert capsys.readouterr().err.splitlines()[-1].endswith(
        f"{tmp_path}: is a folder, expected a studio session log (.jsonl); its latest is {log}")
    for name, what in (("take001.csv", "a take saved at quit"),
                       ("take001-react.csv", "a take saved at quit"),
                       ("try001.png", "a try's review sheet")):
        assert cli(["review", str(tmp_path / f"session-20260101-120000-{name}")]) == 2
        err = capsys.readouterr().err.splitlines()
        assert len(err) == 1 and f"{name}: {what}, not a studio session log; its log is " \
            f"{log}" in err[0], err
    assert cli(["replay", str(log), "--headless", "--fast"]) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and f"{log}: a studio session log (its tries: `tabletop review` " \
        "draws them), not a session recording" in err[0], err
    assert cli(["review", str(log), "--out", str(tmp_path / "sheet.png")]) == 0   # as said


def test_review_tells_a_recording_by_its_first_line_and_refuses_what_is_no_log(tmp_path,
                                                                                capsys):
    """A session recording given to review was read whole before it was told apart by its
    first line (266 MB: 14 s and 573 MB of memory; a kiosk's hour 1.9 GB); a device was "not
    found"."""
    import tracemalloc
    rec = tmp_path / "rec.jsonl"
    with rec.open("wb") as f:
        f.write(b'{"format": "tabletop-session", "version": 2}\n')
        f.truncate(150 * 2**20)                    # (sparse: made at once)
    tracemalloc.start()
    try:
        assert cli(["review", str(rec)]) == 2
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "rec.jsonl: a session recording (`tabletop replay` plays it)" \
        in err[0], err
    assert peak < 20 * 2**20, peak                 # its first line, not its 150 MB
    big = tmp_path / "big.jsonl"
    with big.open("wb") as f:
        f.write(b'{"target": "pet", "outcome": "kept", "duration_s": 4}\n')
        f.truncate(129 * 2**20)
    assert cli(["review", str(big)]) == 2
    assert ("big.jsonl: 135,266,304 bytes, more than a studio session log holds (at most "
            "134,217,728); not read") in capsys.readouterr().err
    assert cli(["review", "/dev/null"]) == 2
    assert "/dev/null: not a regular file" in capsys.readouterr().err


def test_a_review_sheet_the_log_names_but_that_is_gone_or_damaged_is_said_in_its_cell(tmp_path):
    """A try whose sheet was deleted or cut short showed a blank cell, like a try that never
    had one: the designer could not tell a lost sheet from none."""
    import matplotlib.image as mpimg
    from tabletop.studio import review as rv
    (tmp_path / "bad.png").write_bytes(b"\x89PNG\r\n\x1a\n" + b"\0" * 40)
    log = tmp_path / "s.jsonl"
    log.write_text('{"target": "pet", "outcome": "kept"}\n'
                   '{"target": "pet", "outcome": "kept", "review": "gone.png"}\n'
                   '{"target": "pet", "outcome": "kept", "review": "bad.png"}\n')
    out = tmp_path / "sheet.png"
    assert cli(["review", str(log), "--columns", "1", "--out", str(out)]) == 0
    img = mpimg.imread(str(out))[..., :3].sum(axis=2)
    caption_h = rv._text_px("a\nb", rv.CAPTION_PT) + rv.PAD_PX
    cell_h = round((rv.CELL_IN * rv.DPI - 2 * rv.PAD_PX) * rv.SHEET_ASPECT + caption_h
                   + 2 * rv.PAD_PX)
    cells = img[-3 * cell_h:].reshape(3, cell_h, -1)
    inked = [(cell[round(caption_h) + 2 * rv.PAD_PX:] < 2.5).sum() for cell in cells]
    assert inked[0] == 0 and inked[1] > 100 and inked[2] > 100, inked
