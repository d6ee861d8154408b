"""The MOP engine's action templates are read once, when the config loads (once however many
actions name a file), and the build follows the rows read then; a template changed on disk
since is read again by the build (a config's value stays the file's path)."""

import pickle
import shutil
from collections import Counter
from pathlib import Path

import numpy as np

from tabletop.config import validate_config
from tabletop import files
from tabletop.plugins import mop
from tabletop.plugins.mop_files import load_template
from tabletop.plugins.mop_table import EXAMPLES, RATE
from tabletop.registry import BuildContext
from tests.reads import counting_reads

GESTURES = EXAMPLES / "mop" / "gestures"


def _data() -> dict:
    def acts(*names: str) -> list[dict]:
        return [{"name": n, "template": f"{n}.csv", "motion": "walk"} for n in names]
    return {"sources": [{"kind": "scripted"}], "engines": [{
        "kind": "mop",
        "performers": [{"name": "hand", "inputs": [{"kind": "puck", "id": 1}]}],
        "characters": [
            {"name": "lizard", "kind": "creature", "performer": "hand",
             "actions": acts("circle", "line")},
            {"name": "gecko", "kind": "creature", "performer": "hand",
             "actions": acts("circle")}]}]}


def _counting_reads(monkeypatch) -> Counter:
    return counting_reads(monkeypatch, files, "read_csv_lines")


def _load(tmp_path: Path):
    cfg = validate_config(_data(), str(tmp_path / "test.yaml"), tmp_path)
    return cfg, BuildContext(table=(1.2, 0.8), rate_hz=RATE, config=cfg, base=tmp_path)


def _followed(stage, name: str) -> dict[str, np.ndarray]:
    return {a: s for a, (_, s) in stage.templates[name].items()}


def test_each_template_is_read_once_from_config_load_to_build(tmp_path, monkeypatch):
    for name in ("circle.csv", "line.csv"):
        shutil.copy(GESTURES / name, tmp_path / name)
    reads = _counting_reads(monkeypatch)
    cfg, ctx = _load(tmp_path)
    stage = mop.build(cfg["engines"][0], ctx)
    assert reads == {"circle.csv": 1, "line.csv": 1}
    rate = cfg["engines"][0]["rate_hz"]
    circle = load_template(GESTURES / "circle.csv", ("dx", "dy"), rate)
    assert np.array_equal(_followed(stage, "gecko")["circle"], circle)
    assert np.array_equal(_followed(stage, "lizard")["line"],
                          load_template(GESTURES / "line.csv", ("dx", "dy"), rate))
    # the config's value is still the file's path (a config loaded again equals it) ...
    action = cfg["engines"][0]["characters"][1]["actions"][0]
    assert action["template"] == tmp_path / "circle.csv"
    assert _load(tmp_path)[0] == cfg
    # ... and what it carries goes with a pickled config
    again = pickle.loads(pickle.dumps(action))["template"]
    assert np.array_equal(load_template(again, ("dx", "dy"), rate), circle)


def test_a_template_changed_since_the_load_is_read_again_by_the_build(tmp_path, monkeypatch):
    for name in ("circle.csv", "line.csv"):
        shutil.copy(GESTURES / name, tmp_path / name)
    cfg, ctx = _load(tmp_path)
    shutil.copy(GESTURES / "zigzag.csv", tmp_path / "circle.csv")     # edited meanwhile
    reads = _counting_reads(monkeypatch)
    stage = mop.build(cfg["engines"][0], ctx)
    zigzag = load_template(GESTURES / "zigzag.csv", ("dx", "dy"), cfg["engines"][0]["rate_hz"])
    assert np.array_equal(_followed(stage, "lizard")["circle"], zigzag)
    assert np.array_equal(_followed(stage, "gecko")["circle"], zigzag)
    assert reads["circle.csv"] == 2         # (read again once for each action naming it)


def test_two_actions_of_one_character_on_one_template_are_refused_at_load(tmp_path):
    """A character given a second action on the same samples (for another motion) started
    without a word, and that action never played: the follower takes them as one (a bird's
    "wave2" on wave.csv: 0 of 2,227 ticks). The same gesture for two characters is fine."""
    import pytest

    from tabletop.config import ConfigError
    for name in ("circle.csv", "line.csv"):
        shutil.copy(GESTURES / name, tmp_path / name)
    shutil.copy(GESTURES / "circle.csv", tmp_path / "round.csv")
    data = _data()
    validate_config(data, str(tmp_path / "test.yaml"), tmp_path)      # circle for both: fine
    lizard = data["engines"][0]["characters"][0]["actions"]
    for template, said in (("circle.csv", "the same template as action 'circle'"),
                           ("round.csv", "round.csv holds the same samples as the template of "
                                         "action 'circle'")):
        lizard.append({"name": "curl", "template": template, "motion": "curl"})
        with pytest.raises(ConfigError) as exc:
            validate_config(data, str(tmp_path / "test.yaml"), tmp_path)
        assert "engines[0].characters[0].actions[2].template: " in str(exc.value)
        assert said in str(exc.value) and "'curl' would never play" in str(exc.value)
        lizard.pop()
