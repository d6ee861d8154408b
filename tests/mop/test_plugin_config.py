"""The ``mop`` engine plugin's config refused in one line naming its key or file: a skeleton that is
no URDF, every key an engine reads, and two engines keeping one character in one library."""

import copy

import pytest

from tabletop.config import validate_config
from tabletop.plugins import mop
from tabletop.plugins.mop_table import EXAMPLES, RATE, build, designer_config
from tabletop.registry import BuildContext
from tabletop.schema import ConfigError

from tests.mop.helpers import refused


@pytest.mark.parametrize("clip_file", [False, True])
def test_a_skeleton_file_that_is_no_urdf_is_refused_naming_its_key(tmp_path, clip_file):
    """With a clip file to check against the rig it stopped the config check, and without one
    the build, both naming the file alone (SkeletonError, not the character's key)."""
    from tabletop.plugins.mop import resolve_motion
    (tmp_path / "bad.urdf").write_text("<notrobot/>")
    walk = str(resolve_motion("skeleton", "walk", tmp_path)[1]) if clip_file else "walk"
    data = designer_config(tmp_path)
    data["engines"][0]["characters"].append({
        "name": "dancer", "kind": "skeleton", "performer": "hand", "skeleton": "bad.urdf",
        "actions": [{"name": "a", "template": str(EXAMPLES / "mop/gestures/line.csv"),
                     "motion": walk}]})
    with pytest.raises(ConfigError, match=r"engines\[0\]\.characters\[2\]\.skeleton: .*bad\.urdf"):
        build(data, tmp_path)


def test_config_errors_name_the_key_or_file(tmp_path):
    def expect(mutate, *words, error=ConfigError):
        refused(tmp_path, mutate, *words, error=error)

    expect(lambda e: e["characters"][0].update(performer="nobody"),
           "engines[0].characters[0].performer", "no performer 'nobody'")
    expect(lambda e: e["characters"][0]["actions"][0].update(motion="moonwalk"),
           "engines[0].characters[0].actions[0].motion", "unknown motion 'moonwalk'")
    expect(lambda e: e["characters"][0]["actions"][0].update(motion="clips/nothere.json"),
           "actions[0].motion", "nothere.json")
    expect(lambda e: e["characters"][0]["actions"][0].update(template="nothere.csv"),
           "actions[0].template", "nothere.csv")
    expect(lambda e: e["characters"][0]["actions"][0].update(warp=[[0, 0.5], [1, 1]]),
           "actions[0].warp", "start at [0, 0]")
    expect(lambda e: e["characters"].append({"name": "hero", "kind": "skeleton",
                                             "performer": "hand",
                                             "skeleton": "missing.urdf"}),
           "characters[2].skeleton", "missing.urdf")
    expect(lambda e: e["characters"].append({"name": "hero", "kind": "skeleton",
                                             "performer": "hand",
                                             "actions": [{"name": "a", "template": str(
                                                 EXAMPLES / "mop/gestures/line.csv"),
                                                 "motion": "moonwalk"}]}),
           "characters[2].actions[0].motion", "humanoid3d_moonwalk.txt")
    expect(lambda e: e["performers"][0]["inputs"].append({"kind": "stream"}),
           "performers[0].inputs[1].name", "needs the stream's name")
    # an option the input's kind does not read (it was taken and changed nothing)
    expect(lambda e: e["performers"][0]["inputs"].append({"kind": "touch", "features": ["speed"]}),
           "performers[0].inputs[1].features", "only a puck input takes features",
           "a touch input does not read it")
    expect(lambda e: e["performers"][0]["inputs"].append({"kind": "touch", "rest_time": 2}),
           "performers[0].inputs[1].rest_time", "only a puck input takes rest_time")
    expect(lambda e: e["performers"][0]["inputs"].append(
        {"kind": "stream", "name": "arm", "columns": [0], "id": 3}),
           "performers[0].inputs[1].id", "only a puck input takes id")
    expect(lambda e: e["performers"][0]["inputs"][0].update(columns=[0, 1]),
           "performers[0].inputs[0].columns", "only a stream input takes columns")
    expect(lambda e: e["characters"][0].update(travel=True),
           "characters[0].travel", "only a skeleton character takes travel",
           "a face character does not read it")
    expect(lambda e: e["characters"][1].update(sheet=str(EXAMPLES / "mop/bird.json")),
           "characters[1].sheet", "only a sprite character takes sheet")
    blocked = tmp_path / "a_file"      # a library that cannot be made: refused at load, not at K
    blocked.write_text("")
    expect(lambda e: e.update(library=str(blocked / "lib")), "engines[0].library",
           "cannot hold kept actions", "a_file is not a folder")
    bad = tmp_path / "bad.csv"
    bad.write_text("t,dx,speed\n0,0,0\n0.1,0.1,0.1\n")
    expect(lambda e: e["characters"][0]["actions"][0].update(template=str(bad)),
           "engines[0].characters[0].actions[0].template", "bad.csv",
           "do not match the performer's features dx,dy")
    long = tmp_path / "long.csv"     # resampled at the engine's rate: it ran out of memory
    long.write_text("t,dx,dy\n0,0,0\n0.1,0.1,0.1\n1e9,0.2,0.2\n")
    expect(lambda e: e["characters"][0]["actions"][0].update(template=str(long)),
           "engines[0].characters[0].actions[0].template",
           "long.csv: the template spans 1e+09 s (column 't'); at most 3600 s can be followed")
    # names: an empty action's stopped the followers' build naming no key; a character's names
    # its library folder ('..' kept its actions beside the library)
    expect(lambda e: e["characters"][0]["actions"][0].update(name=" "),
           "engines[0].characters[0].actions[0].name", "an action needs a name")
    for name in ("", "..", "a/b"):
        expect(lambda e: e["characters"][1].update(name=name), "engines[0].characters[1].name",
               f"{name!r} cannot name a character")
    # a clip file the character cannot play: the key is named, not only the character
    import json

    from behaviors.mop.creatures import creature_clips
    from behaviors.motion.clips import clip_to_mapping
    walk = tmp_path / "walk.json"
    walk.write_text(json.dumps(clip_to_mapping(creature_clips()["walk"])))
    expect(lambda e: e["characters"][0]["actions"][0].update(motion=str(walk)),
           "engines[0].characters[0].actions[0].motion", "no channel named after a blendshape")
    expect(lambda e: e["characters"].append({"name": "hero", "kind": "skeleton",
                                             "performer": "hand", "motions": [str(walk)]}),
           "engines[0].characters[2].motions[0]", "clip 'walk' does not drive skeleton")
    far = tmp_path / "far.csv"       # its followers' probabilities became NaN
    far.write_text("t,dx,dy\n0,0,0\n0.1,1e300,0.1\n")
    expect(lambda e: e["characters"][0]["actions"][0].update(template=str(far)),
           "engines[0].characters[0].actions[0].template",
           "far.csv: line 3: column 'dx': 1e+300 is beyond 1e+100")


def test_two_engines_keeping_a_character_of_one_name_in_one_library_are_refused(tmp_path):
    """Both kept that character's takes as lib/face/take1.csv (the later keep wrote over the
    earlier) and each loaded the other's actions as its own."""
    first = designer_config(tmp_path)["engines"][0]
    second = dict(copy.deepcopy(first), name="mop2")
    data = {"sources": [{"kind": "scripted"}], "engines": [first, second]}
    cfg = validate_config(data, str(tmp_path / "test.yaml"), tmp_path)
    ctx = BuildContext(table=(1.2, 0.8), rate_hz=RATE, config=cfg, base=tmp_path)
    mop.build(cfg["engines"][0], ctx)
    with pytest.raises(mop.MopError) as err:
        mop.build(cfg["engines"][1], ctx)
    assert str(err.value).startswith(f"{tmp_path / 'test.yaml'}: engines[1].library: engines[0]")
    assert "character 'face'" in str(err.value)
    second["library"] = "lib2"                       # its own library: both build
    cfg = validate_config(data, str(tmp_path / "test.yaml"), tmp_path)
    ctx = BuildContext(table=(1.2, 0.8), rate_hz=RATE, config=cfg, base=tmp_path)
    assert [mop.build(e, ctx).name for e in cfg["engines"]] == ["mop", "mop2"]
