"""A command-line length or time a thousand times too large, whose thousandth is in range, is
asked about as millimetres or milliseconds, as config.yaml's values are."""

import pytest

from tabletop.cli import main as cli


@pytest.mark.parametrize("args, said", [
    (["pose", "--describe", "--height", "300"],
     "--height '300' must be a number of metres from 0.01 to 20 (millimetres given?)"),
    (["pose", "--describe", "--table", "1200,800"],
     "--table '1200,800': width and height must be metres from 0.05 to 20 (millimetres given?)"),
    (["behave", "--train", "d.csv", "--input", "m.csv", "--out", "o.csv", "--table", "1200,800"],
     "--table '1200,800': width and height must be metres from 0.05 to 20 (millimetres given?)"),
    # no thousandth in range, or under the range: as before, without a question
    (["pose", "--describe", "--height", "50000"],
     "--height '50000' must be a number of metres from 0.01 to 20"),
    (["pose", "--describe", "--table", "1e9,1e9"],
     "--table '1e9,1e9': width and height must be metres from 0.05 to 20"),
    (["pose", "--describe", "--table", "1200,0.01"],
     "--table '1200,0.01': width and height must be metres from 0.05 to 20"),
])
def test_a_thousand_times_too_large_is_asked_about(args, said, capsys):
    assert cli(args) == 2
    err = capsys.readouterr().err.strip()
    assert err.endswith(said) and len(err.splitlines()) == 1, err
