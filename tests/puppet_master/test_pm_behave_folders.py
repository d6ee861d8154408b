"""``tabletop behave`` on behaviour folders: trained with their saved parameters and table, the
table given by ``--param`` or ``--table`` checked and combined with the folder's, and a
library, a misspelt behaviour or a behaviour file given as the demonstration named."""

import shutil

import pytest

from tabletop.files import write_csv
from tests.puppet_master.behave_cli import MAIN_HEADER, SHIPPED, behave, write_files


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    return write_files(tmp_path_factory.mktemp("behave"))


def test_a_behaviour_folder_trains_with_its_saved_parameters(files, tmp_path, capsys):
    # the shipped afraid character is saved with edge_percentile 50 on a 1.2 x 0.8 m table;
    # its CSV alone (all --train took) made another character than the installation plays
    d, main = files
    folder = SHIPPED / "afraid"
    before = {p.name: p.read_bytes() for p in folder.iterdir()}
    write_csv(tmp_path / "main.csv", MAIN_HEADER, main[:150].tolist())       # 5 s
    base = ["--input", tmp_path / "main.csv"]
    assert behave("--train", folder, *base, "--out", tmp_path / "folder.csv") == 0
    saved = ["--param", "edge_percentile=50", "--param", "table_width=1.2", "--param",
             "table_height=0.8", "--table", "1.2,0.8"]
    assert behave("--train", folder / "demonstration.csv", *base, *saved,
                  "--out", tmp_path / "given.csv") == 0
    assert behave("--train", folder / "demonstration.csv", *base, "--out",
                  tmp_path / "csv.csv") == 0
    assert (tmp_path / "folder.csv").read_text() == (tmp_path / "given.csv").read_text()
    assert (tmp_path / "folder.csv").read_text() != (tmp_path / "csv.csv").read_text()
    # --param is over the folder's own; --rate too
    assert behave("--train", folder, *base, "--param", "edge_percentile=0", "--rate", "20",
                  "--out", tmp_path / "over.csv") == 0
    assert behave("--train", folder / "demonstration.csv", *base, "--param",
                  "table_width=1.2", "--param", "table_height=0.8", "--table", "1.2,0.8",
                  "--rate", "20", "--out", tmp_path / "over_given.csv") == 0
    assert (tmp_path / "over.csv").read_text() == (tmp_path / "over_given.csv").read_text()
    # the folder's files are inputs: never written over; a folder that is no behaviour says so
    for name in ("demonstration.csv", "behavior.yaml"):
        assert behave("--train", folder, *base, "--out", folder / name) == 2
        assert "is the input file" in capsys.readouterr().err
    assert {p.name: p.read_bytes() for p in folder.iterdir()} == before
    assert behave("--train", tmp_path, *base, "--out", tmp_path / "o.csv") == 2
    assert "behavior.yaml" in capsys.readouterr().err

def test_a_folder_naming_its_own_demonstration_file_is_read_once(files, tmp_path, capsys):
    """A behaviour whose behavior.yaml names its demonstration ``take-3.csv``: the stored
    behaviour carries that file (``behave`` read behavior.yaml a second time for it), and
    ``--out`` naming it is refused, the file left as it was."""
    import yaml

    from tabletop import library
    d, main = files
    folder = tmp_path / "lib" / "pet"
    shutil.copytree(SHIPPED / "lover", folder)
    (folder / "demonstration.csv").rename(folder / "take-3.csv")
    desc = yaml.safe_load((folder / "behavior.yaml").read_text())
    desc["data"]["demonstration"] = "take-3.csv"
    (folder / "behavior.yaml").write_text(yaml.safe_dump(desc))
    stored = library.load_behavior(folder)
    assert stored.data_file == folder / "take-3.csv"
    before = (folder / "take-3.csv").read_bytes()
    write_csv(tmp_path / "main.csv", MAIN_HEADER, main[:60].tolist())
    assert behave("--train", folder, "--input", tmp_path / "main.csv",
                  "--out", folder / "take-3.csv") == 2
    assert "is the input file" in capsys.readouterr().err
    assert (folder / "take-3.csv").read_bytes() == before
    assert behave("--train", folder, "--input", tmp_path / "main.csv",
                  "--out", tmp_path / "o.csv") == 0

def test_a_folders_table_given_by_param_is_the_table_it_plays_on(files, tmp_path):
    """--param table_width/table_height over a behaviour folder's own: it trained on that
    table and was generated on the folder's stored one."""
    d, main = files
    write_csv(tmp_path / "main.csv", MAIN_HEADER, main[:150].tolist())
    given = ["--param", "table_width=1.6", "--param", "table_height=1.0"]
    base = ["--train", SHIPPED / "afraid", "--input", tmp_path / "main.csv"]
    assert behave(*base, *given, "--out", tmp_path / "param.csv") == 0
    assert behave(*base, *given, "--table", "1.6,1.0", "--out", tmp_path / "both.csv") == 0
    assert (tmp_path / "param.csv").read_text() == (tmp_path / "both.csv").read_text()

def test_a_library_or_a_misspelt_behaviour_names_the_librarys_behaviours(files, tmp_path,
                                                                          capsys):
    """--train naming the library itself said "library/behavior.yaml: not found", and a
    misspelt behaviour "demonstration CSV not found": neither named what there is."""
    d, main = files
    write_csv(tmp_path / "main.csv", MAIN_HEADER, main[:60].tolist())
    base = ["--input", tmp_path / "main.csv", "--out", tmp_path / "o.csv"]
    assert behave("--train", SHIPPED / "lovr", *base) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and f"did you mean {SHIPPED / 'lover'}?" in err[0]
    assert "afraid, bully, lover, playful_friend, stalker" in err[0]
    assert behave("--train", SHIPPED, *base) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and "a behaviour library, not a behaviour" in err[0]
    assert f"e.g. {SHIPPED / 'afraid'}" in err[0]
    assert not (tmp_path / "o.csv").exists()
    assert behave("--train", SHIPPED / "lover", *base) == 0

@pytest.mark.parametrize("given, words", [
    (["--table", "1e9,1e9"],
     ["--table '1e9,1e9': width and height must be metres from 0.05 to 20"]),
    (["--param", "table_width=1e9", "--param", "table_height=1e9"],
     ["--param table_width='1e9': width and height must be metres from 0.05 to 20"]),
    (["--param", "table_width=1.6", "--param", "table_height=-1"],
     ["--param table_height='-1': width and height must be metres from 0.05 to 20"]),
    (["--param", "table_width=nan", "--param", "table_height=1"],
     ["--param table_width='nan'", "from 0.05 to 20"]),
    # one side alone, a CSV demonstration storing none: Behavior ignored it without a word
    (["--param", "table_width=1.6"],
     ["--param table_width=1.6 without table_height", "needs both"]),
    (["--param", "table_height=1", "--table", "1.6,1.0"],
     ["--param table_height=1 without table_width", "needs both"]),
])
def test_a_table_given_by_param_is_checked_as_table_is(files, tmp_path, capsys, given, words):
    d, _ = files
    assert behave("--train", d / "demo.csv", "--input", d / "main.csv", "--out",
                  tmp_path / "o.csv", *given) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and err[0].startswith("tabletop behave: error: --"), err
    for w in words:
        assert w in err[0], err
    assert not (tmp_path / "o.csv").exists()

def test_one_table_side_by_param_over_a_folders_table_takes_the_others(files, tmp_path):
    """--param table_width alone over a behaviour folder (afraid: 1.2 x 0.8 m) is its table
    with the folder's height: the same rows as both given."""
    d, main = files
    write_csv(tmp_path / "main.csv", MAIN_HEADER, main[:150].tolist())
    base = ["--train", SHIPPED / "afraid", "--input", tmp_path / "main.csv"]
    assert behave(*base, "--param", "table_width=1.6", "--out", tmp_path / "one.csv") == 0
    assert behave(*base, "--param", "table_width=1.6", "--param", "table_height=0.8",
                  "--out", tmp_path / "both.csv") == 0
    assert behave(*base, "--out", tmp_path / "stored.csv") == 0
    assert (tmp_path / "one.csv").read_text() == (tmp_path / "both.csv").read_text()
    assert (tmp_path / "one.csv").read_text() != (tmp_path / "stored.csv").read_text()

def test_a_behaviour_file_given_as_the_demonstration_names_what_to_give(files, tmp_path,
                                                                        capsys):
    """--train LIB/NAME/behavior.yaml was read as a CSV and refused naming only its "header";
    it is said to be a behaviour file, with the folder and its demonstration CSV to give."""
    d, main = files
    write_csv(tmp_path / "main.csv", MAIN_HEADER, main[:60].tolist())
    folder = tmp_path / "lover"
    shutil.copytree(SHIPPED / "lover", folder)
    base = ["--input", tmp_path / "main.csv", "--out", tmp_path / "o.csv"]
    assert behave("--train", folder / "behavior.yaml", *base) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and "a behaviour file, not a demonstration CSV" in err[0], err
    assert f"--train {folder}" in err[0] and str(folder / "demonstration.csv") in err[0], err
    assert behave("--train", folder / "demonstration.csv", *base) == 0    # as it says


def test_a_folders_parameter_out_of_range_is_named_at_its_key(files, tmp_path, capsys):
    """A value training refuses in a folder's behavior.yaml (window: 1), or a window longer
    than its demonstration, is said at ``behavior.yaml: parameters.NAME`` (it named the folder
    only); the same value given by --param is said as --param's."""
    d, main = files
    write_csv(tmp_path / "main.csv", MAIN_HEADER, main[:60].tolist())
    folder = tmp_path / "lover"
    shutil.copytree(SHIPPED / "lover", folder)
    yaml_file = folder / "behavior.yaml"
    text = yaml_file.read_text()
    assert "window: 40\n" in text
    base = ["--train", folder, "--input", tmp_path / "main.csv", "--out", tmp_path / "o.csv"]
    for value, words in ((1, "parameters.window: 1 must be an integer >= 2"),
                         (3000, "parameters.window, parameters.rate_hz: demonstration lasts")):
        yaml_file.write_text(text.replace("window: 40\n", f"window: {value}\n"))
        assert behave(*base) == 2
        err = capsys.readouterr().err.splitlines()
        assert len(err) == 1 and f"error: {yaml_file}: {words}" in err[0], err
    assert behave(*base, "--param", "window=0") == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and "error: --param: behaviour parameter window: 0" in err[0], err
    assert behave(*base, "--param", "window=20") == 0     # over the file's: trained
    assert not capsys.readouterr().err
