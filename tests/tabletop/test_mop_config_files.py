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


@pytest.mark.parametrize("content, words", [
    ("hello", "notes.json: cannot read clip: Expecting value: line 1 column 1"),
    ('{"Loop": "wrap", "Frames": [[1, 2]]}', "notes.json: unknown key 'Frames'"),
])
def test_a_clip_file_that_is_no_clip_names_its_key(tmp_path, content, words):
    """It passed validation and stopped the build as "character 'd', action 'a': ..."."""
    (tmp_path / "notes.json").write_text(content)
    with pytest.raises(ConfigError) as info:
        validate_config(mop_config(str(CIRCLE), "notes.json"), "m.yaml", tmp_path)
    assert str(info.value).startswith("m.yaml: engines[0].characters[0].actions[0].motion: "
                                      f"{tmp_path}/{words}"), info.value
    validate_config(mop_config(str(CIRCLE), "walk"), "m.yaml", tmp_path)


def test_a_template_going_back_in_time_names_its_line(tmp_path):
    (tmp_path / "back.csv").write_text("t,dx,dy\n\n0,0,0\n0.1,0.1,0\n0.05,0.2,0\n")
    with pytest.raises(ConfigError) as info:
        validate_config(mop_config("back.csv", "walk"), "m.yaml", tmp_path)
    assert str(info.value) == ("m.yaml: engines[0].characters[0].actions[0].template: "
                               f"{tmp_path}/back.csv: line 5: column 't' must strictly "
                               "increase; 0.05 is not after 0.1 (line 4)")
