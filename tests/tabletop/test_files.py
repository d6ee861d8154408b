"""tabletop.files: a CSV cut short while it was written (a copy interrupted, a recorder stopped)
is refused naming its file and line, even where its cut last row still reads as numbers."""

import shutil
from pathlib import Path

import pytest

from tabletop.files import FileFormatError, read_csv_lines
from tabletop.plugins.mop_files import load_template

CIRCLE = Path(__file__).resolve().parents[2] / "examples" / "mop" / "gestures" / "circle.csv"


@pytest.mark.parametrize("cut", [2, 7, 8])   # '-0.000287' -> '-0.00028', '-0.', '-0'
def test_a_template_cut_inside_its_last_value_is_refused_naming_file_and_line(tmp_path, cut):
    text = CIRCLE.read_text()
    p = tmp_path / "circle.csv"
    p.write_text(text[:-cut])
    with pytest.raises(FileFormatError) as err:
        load_template(p, ("dx", "dy"), 30.0)
    lines = len(text.splitlines())
    assert str(err.value).startswith(f"{p}: line {lines}: column 'dy': ")
    assert "cut short" in str(err.value)


@pytest.mark.parametrize("cut, said", [(10, "'' is not a number"), (11, "2 values, expected 3"),
                                       (21, "1 value, expected 3")])
def test_a_row_cut_short_says_the_file_ends_there(tmp_path, cut, said):
    p = tmp_path / "circle.csv"
    p.write_text(CIRCLE.read_text()[:-cut])
    with pytest.raises(FileFormatError, match=f"line 62: .*{said}.*cut short"):
        read_csv_lines(p)


def test_whole_files_are_read_with_or_without_a_last_line_end(tmp_path):
    """A whole last row without its line end (an editor's file) reads, as do rows written with
    fewer digits where the file goes on, and a one-row file."""
    p = tmp_path / "c.csv"
    shutil.copy(CIRCLE, p)
    whole = read_csv_lines(p)[1]
    p.write_text(CIRCLE.read_text().rstrip("\n"))
    assert (read_csv_lines(p)[1] == whole).all()
    p.write_text("t,x\n0,0.25\n1,0.5\n2,0.75")
    assert read_csv_lines(p)[1][:, 1].tolist() == [0.25, 0.5, 0.75]
    p.write_text("t,x\n0,0.25\n1,0.5\n")
    assert len(read_csv_lines(p)[1]) == 2
    p.write_text("t,x\n0,1.5e-05\n1,2.5e-05")
    assert len(read_csv_lines(p)[1]) == 2
    p.write_text("t,x\n0,1.5e-05\n1,2.5e-0")
    with pytest.raises(FileFormatError, match="line 3: column 'x': '2.5e-0' has fewer digits"):
        read_csv_lines(p)
    p.write_text("t,x\n0,0.2")
    assert len(read_csv_lines(p)[1]) == 1


def test_yaml_parsed_by_libyaml_gives_what_the_python_parser_gives():
    """parse_yaml parses with libyaml (8x less CPU) where it gives the Python parser's answer:
    the project's YAML files alike, and the texts libyaml accepts but the Python parser
    refuses (a tab in a plain scalar, a complex key in a flow mapping, a comment right after a
    block scalar's indicator) or reads otherwise (a byte-order mark past the start) refused or
    read as the Python parser does."""
    import yaml

    from tabletop import files
    root = Path(__file__).resolve().parents[2]
    shipped = [p for p in root.glob("**/*.yaml") if ".venv" not in p.parts]
    assert len(shipped) >= 10
    for p in shipped:
        text = p.read_text()
        assert files.parse_yaml(text, p) == yaml.load(text, Loader=files.UniqueKeyLoader), p
    for text in ("a: demo\tstration.csv\n", "a: {b: 1 ? c}\n", "a: |#x\n  b\n"):
        assert yaml.load(text, Loader=files._C_LOADER) is not None      # libyaml: a value
        with pytest.raises(FileFormatError, match="YAML syntax error at line"):
            files.parse_yaml(text, "f.yaml")
    bom = "a: 1\n\ufeffb: 2\n"
    assert files.parse_yaml(bom, "f.yaml") == {"a": 1, "\ufeffb": 2}
    with pytest.raises(FileFormatError, match="f.yaml: YAML syntax error at line 2, column 1: "
                                              "key 'a' is given twice"):
        files.parse_yaml("a: 1\na: 2\n", "f.yaml")
