"""A huge value (a whole file pasted as one string, or a long list) refused by a config or
behaviour spec is quoted cut short, as the schema's shared message does: the refusal stays one
short line naming the key, not 10,000 characters of the value."""

import shutil
from pathlib import Path

import pytest
import yaml

from tabletop.config import validate_config
from tabletop.frames import InputError
from tabletop.library import load_behavior

HUGE = "x" * 10_000
LOVER = Path(__file__).resolve().parents[2] / "behaviors" / "library" / "lover"
SCRIPTED = {"kind": "scripted", "name": "visitor", "pucks": [1]}


def _short_line(message: str, key: str) -> None:
    assert "\n" not in message and len(message) < 400, message[:500]
    assert key in message and "characters)" in message, message


@pytest.mark.parametrize("change, key", [
    (lambda c: c["sources"].append(HUGE), "sources[1]"),
    (lambda c: c["sources"].append({"kind": "camera", "name": "c", "device": [0] * 5000}),
     "sources[1].device"),
    (lambda c: c["sources"].append({"kind": "osc", "name": "o", "port": 3400, "host": HUGE}),
     "sources[1].host"),
    (lambda c: c.update(tracking={"dictionary": HUGE}), "tracking.dictionary"),
    (lambda c: c["sources"][0].update(name=[0] * 5000), "sources[0].name"),
    (lambda c: c["engines"][0].update(main=HUGE), "engines[0].main"),
])
def test_a_huge_config_value_is_refused_in_one_short_line_naming_its_key(tmp_path, change, key):
    shutil.copytree(LOVER, tmp_path / "lover")
    cfg = {"sources": [dict(SCRIPTED)],
           "engines": [{"kind": "puppet_master", "name": "lover", "behavior": "lover",
                        "main": {"puck": 1}}]}
    change(cfg)
    with pytest.raises(InputError) as info:
        validate_config(cfg, "config.yaml", tmp_path)
    _short_line(str(info.value), key)


def test_a_huge_parameters_value_in_a_behaviour_file_is_refused_in_one_short_line(tmp_path):
    folder = tmp_path / "lover"
    shutil.copytree(LOVER, folder)
    meta = yaml.safe_load((folder / "behavior.yaml").read_text())
    meta["parameters"] = HUGE
    (folder / "behavior.yaml").write_text(yaml.safe_dump(meta))
    with pytest.raises(InputError) as info:
        load_behavior(folder, tries=1)
    _short_line(str(info.value), "parameters")
