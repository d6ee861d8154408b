"""The MOP engine's files refused when the config is loaded, naming the key, the file and the
line: a kiosk refuses such an edit and keeps the running table."""

from pathlib import Path

import pytest

from tabletop.config import validate_config
from tabletop.schema import ConfigError

CIRCLE = Path(__file__).resolve().parents[2] / "examples" / "mop" / "gestures" / "circle.csv"


def mop_config(template: str, motion: str) -> dict:
    return {"sources": [{"kind": "scripted", "pucks": [1]}],
            "engines": [{"kind": "mop", "performers": [
                {"name": "p", "inputs": [{"kind": "puck", "id": 1, "features": ["dx", "dy"]}]}],
                "characters": [{"name": "d", "kind": "skeleton", "performer": "p",
                                "actions": [{"name": "a", "template": template,
                                             "motion": motion}]}]}]}


def test_a_template_going_back_in_time_names_its_line(tmp_path):
    (tmp_path / "back.csv").write_text("t,dx,dy\n\n0,0,0\n0.1,0.1,0\n0.05,0.2,0\n")
    with pytest.raises(ConfigError) as info:
        validate_config(mop_config("back.csv", "walk"), "m.yaml", tmp_path)
    assert str(info.value) == ("m.yaml: engines[0].characters[0].actions[0].template: "
                               f"{tmp_path}/back.csv: line 5: column 't' must strictly "
                               "increase; 0.05 is not after 0.1 (line 4)")
