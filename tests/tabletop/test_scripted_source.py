"""The scripted source's gesture files are read when its config is loaded, as a MOP template
is: a damaged one is refused naming the config key as well as the file and line (it was
refused at the build, in a kiosk's start too, naming the file alone)."""

import shutil
from pathlib import Path

import pytest

from tabletop.config import load_config
from tabletop.schema import ConfigError

GESTURES = Path(__file__).resolve().parents[2] / "examples" / "mop" / "gestures"


def test_a_damaged_gesture_file_is_refused_naming_its_key(tmp_path):
    shutil.copy(GESTURES / "line.csv", tmp_path / "line.csv")
    text = (GESTURES / "circle.csv").read_text()
    (tmp_path / "circle.csv").write_text(text[:-7])        # cut inside its last value
    cfg = tmp_path / "config.yaml"
    cfg.write_text("sources:\n  - kind: scripted\n    pucks: [1]\n    performers:\n"
                   "      - {puck: 2, home: [0.5, 0.4], gestures: [line.csv, circle.csv]}\n")
    with pytest.raises(ConfigError) as err:
        load_config(cfg)
    lines = len(text.splitlines())
    assert str(err.value).startswith(
        f"{cfg}: sources[0].performers[0].gestures[1]: {tmp_path / 'circle.csv'}: "
        f"line {lines}: column 'dy': ")
