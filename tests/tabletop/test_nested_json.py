"""A JSON file nested too deep for Python's recursion (``[[[[...``, from a broken tool or a
bad copy) is refused as any malformed JSON file is, in one line naming the file: a
RecursionError went up as an internal error (status 1 from ``tabletop run``)."""

import pytest

from behaviors.motion.clips import ClipError
from behaviors.motion.deepmimic import load_motion
from behaviors.touch_pose.designed import DesignedActionError, read_take
from tabletop.config import validate_config
from tabletop.frames import InputError
from tabletop.plugins.mop_table import build
from tabletop.schema import ConfigError
from tests.tabletop.test_mop_config_files import CIRCLE, mop_config

DEEP = "[" * 100_000


@pytest.fixture
def deep(tmp_path):
    path = tmp_path / "deep.json"
    path.write_text(DEEP)
    return path


def test_a_clip_file(tmp_path, deep):
    with pytest.raises(ConfigError) as info:
        validate_config(mop_config(str(CIRCLE), "deep.json"), "m.yaml", tmp_path)
    assert str(info.value) == ("m.yaml: engines[0].characters[0].actions[0].motion: "
                               f"{deep}: cannot read clip: nested too deep: line 1 column 1 "
                               "(char 0)")


def test_a_sprite_sheet(tmp_path, deep):
    data = {"sources": [{"kind": "scripted"}], "engines": [{"kind": "mop",
            "performers": [{"name": "p", "inputs": [{"kind": "puck"}]}],
            "characters": [{"name": "s", "kind": "sprite", "performer": "p",
                            "sheet": str(deep)}]}]}
    with pytest.raises(InputError, match=r"deep\.json: cannot read sprite sheet: nested too "
                                         "deep"):
        build(data, tmp_path)


def test_a_deepmimic_clip(deep):
    with pytest.raises(ClipError, match=r"deep\.json: not valid JSON at line 1: nested too "
                                        "deep$"):
        load_motion(deep)


def test_a_designed_touch_pose_action(deep):
    with pytest.raises(DesignedActionError, match=r"deep\.json: cannot read the action: "
                                                  "nested too deep"):
        read_take(deep, None)
