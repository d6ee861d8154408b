"""The ``mop`` engine plugin: config, performers bound to characters, playback at the performer's
progress, holding and resting, several inputs concatenated, and the designer flow on real files
(a config it refuses: test_plugin_config.py)."""

import math
from pathlib import Path

import numpy as np
import pytest
import yaml

from tabletop.frames import InputError, Touch
from tabletop.plugins import mop
from tabletop.plugins.mop_table import EXAMPLES, G, RATE, Table, build, designer_config
from tabletop.registry import BuildContext
from tabletop.schema import ConfigError


def _example_data() -> dict:
    return yaml.safe_load((EXAMPLES / "mop.yaml").read_text())


def test_example_config_builds_every_kind_of_character(example_cfg):
    ctx = BuildContext(table=(1.2, 0.8), rate_hz=RATE, config=example_cfg, base=EXAMPLES)
    engine = mop.build(example_cfg["engines"][0], ctx)
    chars = Table(engine).rest(0.5)[-1]
    assert {c.kind for c in chars.values()} == {"skeleton", "creature", "face", "sprite", "hybrid"}
    for c in chars.values():
        assert np.all(np.isfinite(c.points)) and len(c.bones) >= 7
        assert c.points[:, 0].min() > 0 and c.points[:, 0].max() < 1.2
        assert c.points[:, 1].min() > 0 and c.points[:, 1].max() < 0.8
        # a resting puck performs nothing, or at most rests at the start of a gesture
        assert not c.valid or c.progress <= 0.2
    dancer = chars["dancer"]
    # the humanoid stands `size` tall along its heading (+y)
    assert abs(np.ptp(dancer.points[:, 1]) - 0.3) < 0.02


def test_warped_noisy_performance_plays_the_motion_at_its_progress(example_cfg):
    ctx = BuildContext(table=(1.2, 0.8), rate_hz=RATE, config=example_cfg, base=EXAMPLES)
    engine = mop.build(example_cfg["engines"][0], ctx)
    table = Table(engine)
    table.rest(1.0)
    # speed changes within the performance from 0.6x to 1.7x of the recording
    run = table.perform("zigzag", speed=lambda u: 0.6 + 1.1 * u, noise=0.002, seed=1)
    late = [(u, c["dancer"]) for u, c in run if u >= 0.4]
    right = [c.valid and c.action == "zigzag" for _, c in late]
    assert np.mean(right) >= 0.9
    err = [c.progress - u for u, c in late if c.valid and c.action == "zigzag"]
    assert math.sqrt(np.mean(np.square(err))) <= 0.06
    # what is drawn is the kick clip at that progress (after the cross-fade), placed on the table
    u, c = late[-1]
    puppet = engine.puppets["dancer"]
    clip = puppet.actions["zigzag"].clip
    assert clip.name == "kick"
    from behaviors.motion.skeleton import place
    expected = place(puppet.rig.pose(clip, c.progress), puppet.x, puppet.y, puppet.heading,
                     puppet.size)
    assert np.abs(expected - c.points).max() < 1e-9
    # the other performer's characters were not driven
    assert not any(ch["salamander"].valid for _, ch in run)


def test_pause_holds_and_going_back_reverses(example_cfg):
    ctx = BuildContext(table=(1.2, 0.8), rate_hz=RATE, config=example_cfg, base=EXAMPLES)
    engine = mop.build(example_cfg["engines"][0], ctx)
    table = Table(engine)
    table.rest(1.0)
    run = table.perform("figure_eight", upto=0.6)
    p_end = run[-1][1]["dancer"].progress
    assert run[-1][1]["dancer"].action == "figure_eight" and abs(p_end - 0.6) < 0.08
    held = [c["dancer"] for c in table.rest(0.4)]
    assert all(c.action == "figure_eight" for c in held)
    assert max(abs(c.progress - p_end) for c in held if c.valid) < 0.04
    # going back along the path: progress goes down
    g = G.gesture("figure_eight")
    x0 = table.pucks[1][0] - np.interp(0.6 * g[-1, 0], g[:, 0], g[:, 1])
    y0 = table.pucks[1][1] - np.interp(0.6 * g[-1, 0], g[:, 0], g[:, 2])
    back = []
    for tau in np.linspace(0.6, 0.35, 25) * g[-1, 0]:
        table.pucks[1] = (x0 + np.interp(tau, g[:, 0], g[:, 1]),
                          y0 + np.interp(tau, g[:, 0], g[:, 2]))
        back.append(table.tick()["dancer"])
    progress = [c.progress for c in back if c.valid and c.action == "figure_eight"]
    assert len(progress) > 15 and progress[-1] < p_end - 0.15


def test_unrelated_input_holds_then_returns_to_rest(example_cfg):
    ctx = BuildContext(table=(1.2, 0.8), rate_hz=RATE, config=example_cfg, base=EXAMPLES)
    engine = mop.build(example_cfg["engines"][0], ctx)
    table = Table(engine)
    table.rest(1.0)
    table.perform("circle", upto=0.7)
    playing = table.tick()["dancer"]
    assert playing.valid and playing.action == "circle"
    # the puck vanishes: the character holds its pose for hold_s, dimmed
    del table.pucks[1]
    held = [table.tick()["dancer"] for _ in range(int(0.4 * RATE))]
    assert not any(c.valid for c in held[2:])       # from the next follower sample (30 Hz) on
    assert np.abs(held[-1].points - playing.points).max() < 0.02
    # a fast scribble that is no gesture: still invalid; after hold and rest time it is at rest
    rng = np.random.default_rng(5)
    table.pucks[1] = (0.6, 0.5)
    rest_pts, valid = None, []
    for _ in range(int(3.0 * RATE)):
        x, y = table.pucks[1]
        table.pucks[1] = (min(1.0, max(0.2, x + rng.normal(0, 0.03))),
                          min(0.7, max(0.1, y + rng.normal(0, 0.03))))
        c = table.tick()["dancer"]
        valid.append(c.valid)
        rest_pts = c.points
    assert not any(valid[int(0.5 * RATE):])
    puppet = engine.puppets["dancer"]
    from behaviors.motion.skeleton import place
    rest = place(puppet.rig.rest(), puppet.x, puppet.y, puppet.heading, puppet.size)
    assert np.abs(rest_pts - rest).max() < 0.005


def test_time_warp_maps_action_progress_onto_motion(tmp_path):
    data = _example_data()
    eng = data["engines"][0]
    eng["library"] = None
    for c in eng["characters"]:
        for a in c["actions"]:
            a["template"] = str(EXAMPLES / a["template"])
        if c["kind"] == "sprite":
            c["sheet"] = str(EXAMPLES / c["sheet"])
    for p in data["sources"][0].get("performers", []):
        p["gestures"] = [str(EXAMPLES / g) for g in p["gestures"]]
    lizard = next(c for c in eng["characters"] if c["name"] == "salamander")
    lizard["actions"][0]["warp"] = [[0, 0], [0.5, 0.8], [1, 1]]
    engine = build(data, tmp_path)
    puppet = engine.puppets["salamander"]
    action = puppet.actions["circle"]
    assert abs(action.warp(0.5) - 0.8) < 1e-12
    table = Table(engine)
    table.rest(1.0)
    run = table.perform("circle", puck=2, upto=0.6)
    c = run[-1][1]["salamander"]
    assert c.valid and c.action == "circle"
    from behaviors.motion.skeleton import place
    expected = place(puppet.rig.pose(action.clip, action.warp(c.progress)), puppet.x, puppet.y,
                     puppet.heading, puppet.size)
    assert np.abs(expected - c.points).max() < 1e-9


def test_sprite_sheet_frames_follow_progress(example_cfg, tmp_path):
    ctx = BuildContext(table=(1.2, 0.8), rate_hz=RATE, config=example_cfg, base=EXAMPLES)
    engine = mop.build(example_cfg["engines"][0], ctx)
    table = Table(engine)
    table.rest(1.0)
    run = table.perform("wave")
    bird = engine.puppets["bird"]
    from behaviors.motion.skeleton import place
    shown = set()
    for u, ch in run:
        c = ch["bird"]
        if c.valid and c.action == "wave" and u > 0.3:
            k = min(int(6 * c.progress), 5)
            expected = place(bird.rig.frames[k], bird.x, bird.y, bird.heading, bird.size)
            if np.abs(expected - c.points).max() < 1e-9:
                shown.add(k)
    assert len(shown) >= 4              # the wing beat went through its frames in turn
    bad = tmp_path / "sheet.json"
    bad.write_text('{"format": "tabletop.sprites", "bones": [[0, 9]], '
                   '"frames": [[[0, 0], [1, 1]]]}')
    data = {"sources": [{"kind": "scripted"}], "engines": [{"kind": "mop",
            "performers": [{"name": "p", "inputs": [{"kind": "puck"}]}],
            "characters": [{"name": "s", "kind": "sprite", "performer": "p", "sheet": str(bad)}]}]}
    with pytest.raises(InputError,
                       match="sheet.json: a bone refers to a point that does not exist"):
        build(data, tmp_path)
    del data["engines"][0]["characters"][0]["sheet"]
    with pytest.raises(ConfigError, match=r"characters\[0\]\.sheet: a sprite character needs"):
        build(data, tmp_path)


def _multi_config(tmp_path: Path) -> dict:
    """One performer: puck 1 path + a mocap stream + a touch, concatenated."""
    g = G.gesture("wave")
    arm = np.sin(np.linspace(0, np.pi, len(g)))             # e.g. an elbow angle, radians
    finger_dx = np.linspace(0, 0.1, len(g))
    rows = np.column_stack([g[:, 0], g[:, 1], g[:, 2], arm, finger_dx, 0 * finger_dx])
    header = "t,puck1_dx,puck1_dy,arm_0,touch_dx,touch_dy"
    np.savetxt(tmp_path / "wave_arm.csv", rows, delimiter=",", header=header, comments="")
    rows2 = rows.copy()
    rows2[:, 3] = -rows2[:, 3]
    np.savetxt(tmp_path / "wave_arm_down.csv", rows2, delimiter=",", header=header, comments="")
    return {"sources": [{"kind": "scripted"}], "engines": [{
        "kind": "mop", "rate_hz": 30,
        "performers": [{"name": "dancer", "inputs": [{"kind": "puck", "id": 1},
                                                     {"kind": "stream", "name": "arm",
                                                      "columns": [0]},
                                                     {"kind": "touch"}]}],
        "characters": [{"name": "face", "kind": "face", "performer": "dancer", "actions": [
            {"name": "up", "template": "wave_arm.csv", "motion": "laugh"},
            {"name": "down", "template": "wave_arm_down.csv", "motion": "angry"}]}]}]}


def test_several_inputs_concatenated(tmp_path):
    engine = build(_multi_config(tmp_path), tmp_path)
    assert engine.performers["dancer"].names == ("puck1_dx", "puck1_dy", "arm_0",
                                                 "touch_dx", "touch_dy")
    g = G.gesture("wave")
    for sign, expect in ((1.0, "up"), (-1.0, "down")):
        table = Table(engine)
        table.t = 100.0 if sign < 0 else 0.0
        table.rest(1.0)
        x0, y0 = table.pucks[1]
        seen = []
        for k in range(len(g) * 2):
            tau = k / RATE
            u = min(1.0, tau / g[-1, 0])
            table.pucks[1] = (x0 + np.interp(tau, g[:, 0], g[:, 1]),
                              y0 + np.interp(tau, g[:, 0], g[:, 2]))
            table.streams = {"arm": np.array([sign * math.sin(math.pi * u)])}
            table.touches = (Touch(4, 0.5 + 0.1 * u, 0.2),)
            c = table.tick()["face"]
            if 0.5 <= u < 1.0:
                seen.append(c.valid and c.action == expect)
        assert np.mean(seen) > 0.9, expect
        # the stream disappears: nothing can be followed, the character is not valid
        table.streams = {}
        assert not table.tick()["face"].valid


def test_two_performers_drive_one_character(tmp_path):
    gestures = EXAMPLES / "mop" / "gestures"
    data = {"sources": [{"kind": "scripted"}], "engines": [{
        "kind": "mop",
        "performers": [{"name": "ann", "inputs": [{"kind": "puck", "id": 1}]},
                       {"name": "bob", "inputs": [{"kind": "puck", "id": 2}]}],
        "characters": [{"name": "face", "kind": "face", "performer": "ann", "actions": [
            {"name": "circle", "template": str(gestures / "circle.csv"), "motion": "talk"},
            {"name": "line", "template": str(gestures / "line.csv"), "motion": "wink",
             "performer": "bob"}]}]}]}
    engine = build(data, tmp_path)
    table = Table(engine)
    table.rest(1.0)
    for puck, name in ((2, "line"), (1, "circle")):
        run = table.perform(name, puck=puck)
        late = [c["face"] for u, c in run if u > 0.4]
        assert np.mean([c.valid and c.action == name for c in late]) > 0.9, name
        table.rest(1.0)


def test_characters_of_one_performer_compete_and_share_what_they_have_in_common(tmp_path):
    # "move" is a circle for the face and a line for the lizard; both have the square
    gestures = EXAMPLES / "mop" / "gestures"
    data = {"sources": [{"kind": "scripted"}], "engines": [{
        "kind": "mop",
        "performers": [{"name": "hand", "inputs": [{"kind": "puck", "id": 1}]}],
        "characters": [
            {"name": "face", "kind": "face", "performer": "hand", "actions": [
                {"name": "move", "template": str(gestures / "circle.csv"), "motion": "talk"},
                {"name": "square", "template": str(gestures / "square.csv"), "motion": "wink"}]},
            {"name": "lizard", "kind": "creature", "performer": "hand", "actions": [
                {"name": "move", "template": str(gestures / "line.csv"), "motion": "strike"},
                {"name": "square", "template": str(gestures / "square.csv"), "motion": "curl"}]}]}]}
    engine = build(data, tmp_path)
    table = Table(engine)
    table.rest(1.0)
    for gesture, playing, idle in (("circle", "face", "lizard"), ("line", "lizard", "face"),
                                   ("square", "face", None)):
        run = table.perform(gesture)
        late = [c for u, c in run if u > 0.6]
        assert np.mean([c[playing].valid and c[playing].action ==
                        ("square" if gesture == "square" else "move") for c in late]) > 0.9, gesture
        if idle is None:
            assert np.mean([c["lizard"].valid and c["lizard"].action == "square"
                            for c in late]) > 0.9
        else:
            assert not any(c[idle].valid for u, c in run if u > 0.3), gesture
        table.rest(1.5)
    # a puck at rest drives nobody
    assert not any(c[n].valid for c in table.rest(1.0)[int(0.3 * RATE):]
                   for n in ("face", "lizard"))


def test_a_hybrid_character_moves_body_and_face_with_one_action(example_cfg):
    # MOP section 3: the gecko's square plays "strike_angry": skeletal and blendshape channels
    ctx = BuildContext(table=(1.2, 0.8), rate_hz=RATE, config=example_cfg, base=EXAMPLES)
    table = Table(mop.build(example_cfg["engines"][0], ctx))
    rest = table.rest(1.0)[-1]["gecko"]
    run = table.perform("square", puck=2, upto=0.55)
    gecko = run[-1][1]["gecko"]
    assert gecko.kind == "hybrid" and gecko.valid and gecko.action == "square"
    body = 16        # the creature's points come first, the face's after them
    moved = np.linalg.norm(gecko.points - rest.points, axis=1)
    face = gecko.points[body:] - gecko.points[body + 0]
    face_rest = rest.points[body:] - rest.points[body + 0]
    assert moved[:body].max() > 0.01                      # the body strikes (metres)
    assert np.abs(face - face_rest).max() > 0.005         # and the face frowns, not only moves


def test_early_feedback_shows_the_likeliest_actions_faintly(example_cfg):
    ctx = BuildContext(table=(1.2, 0.8), rate_hz=RATE, config=example_cfg, base=EXAMPLES)
    table = Table(mop.build(example_cfg["engines"][0], ctx))
    assert not any(c.hints for c in table.rest(1.0)[-1].values())     # nothing while resting
    run = table.perform("circle", upto=0.6)
    hinted = [(u, ch["dancer"]) for u, ch in run if ch["dancer"].hints and not ch["dancer"].valid]
    assert hinted and hinted[0][0] <= 0.15      # suggested from the first samples of the gesture
    u, dancer = hinted[0]
    assert dancer.hint_points is not None and dancer.hint_points.shape == dancer.points.shape
    assert run[-1][1]["dancer"].valid and run[-1][1]["dancer"].action == "circle"


def test_an_action_of_a_few_millimetres_leaves_the_others_recognised(tmp_path):
    """A designer's nudge (a 1 mm action beside a circle) is floored at the puck's smallest
    spread worth telling apart: unfloored it shrank the follower's still radius to its own spread
    and the circle never drove again (valid 0% of its second half)."""
    (tmp_path / "nudge.csv").write_text("t,dx,dy\n0,0,0\n0.5,0.001,0\n1,0,0\n")
    data = designer_config(tmp_path)
    data["engines"][0]["library"] = None
    data["engines"][0]["characters"][1]["actions"] = [
        {"name": "nudge", "template": str(tmp_path / "nudge.csv"), "motion": "curl"}]
    engine = build(data, tmp_path)
    assert engine.performers["hand"].min_scale.tolist() == [0.01, 0.01]
    table = Table(engine)
    table.rest(1.5)
    run = table.perform("circle")
    late = [c["face"].valid and c["face"].action == "circle" for u, c in run if u > 0.5]
    assert np.mean(late) > 0.9
    assert not any(c["lizard"].valid for u, c in run)


def test_a_stream_with_too_few_columns_is_said_on_its_characters(tmp_path, caplog):
    """A performer reading columns 0 and 1 of a stream that has one: nothing can be followed,
    and the characters' label says why (it said "no action", like an unknown gesture), logged
    once."""
    g = G.gesture("wave")
    rows = np.column_stack([g[:, 0], g[:, 1], g[:, 2]])
    np.savetxt(tmp_path / "arm.csv", rows, delimiter=",", header="t,arm_0,arm_1", comments="")
    data = {"sources": [{"kind": "scripted"}], "engines": [{
        "kind": "mop",
        "performers": [{"name": "body", "inputs": [{"kind": "stream", "name": "arm",
                                                    "columns": [0, 1]}]}],
        "characters": [{"name": "face", "kind": "face", "performer": "body", "actions": [
            {"name": "wave", "template": "arm.csv", "motion": "laugh"}]}]}]}
    table = Table(build(data, tmp_path))
    table.streams = {"arm": np.zeros(1)}
    with caplog.at_level("ERROR", logger="tabletop"):
        labels = [table.tick()["face"].label for _ in range(30)]
    assert labels[-1] == "stream 'arm' has 1 column(s), reads column(s) 0, 1"
    assert sum("stream 'arm' has 1 column(s)" in r.getMessage() for r in caplog.records) == 1
    table.streams = {"arm": np.zeros(2)}
    assert "stream" not in table.tick()["face"].label


def test_a_sprite_sheet_point_beyond_any_figure_is_refused(tmp_path):
    # a point of 1e300 would fail the view at every frame (no pygame Rect holds it): refused
    bad = tmp_path / "sheet.json"
    bad.write_text('{"format": "tabletop.sprites", "bones": [[0, 1]], '
                   '"frames": [[[0, 0], [1e300, 1]]]}')
    data = {"sources": [{"kind": "scripted"}], "engines": [{"kind": "mop",
            "performers": [{"name": "p", "inputs": [{"kind": "puck"}]}],
            "characters": [{"name": "s", "kind": "sprite", "performer": "p", "sheet": str(bad)}]}]}
    with pytest.raises(InputError, match=r"sheet.json: a frame holds a point 1e\+300 figure "
                                         r"units from the origin; at most 1000"):
        build(data, tmp_path)


@pytest.mark.parametrize("change, words", [
    ('"frames": [[[0, 0], [1, "x"]]]', r"frames\[0\]\[1\]\[1\]: expected a number, got \"x\""),
    ('"frames": [[[0, 0], [1]]]', r"frames\[0\]\[1\]: expected \[x, y\], got \[1\]"),
    ('"frames": [[[0, 0], [1, 1]], [[0, 0]]]', r"'frames' hold 1 or 2 points; every frame"),
    ('"frmes": [[[0, 0], [1, 1]]]', r"'frmes': unknown key \(known: format, bones, frames\)"),
    ('"frames": [[[0, 0], [1, 1]]], "bones": [[0, 0.5]]',
     r"bones\[0\]\[1\]: expected a point index, got 0.5"),
])
def test_a_sprite_sheet_names_the_place_of_a_bad_value(tmp_path, change, words):
    # (each said "'frames' must be a list of frames of [x, y] points and 'bones' a list of
    # [a, b] point index pairs", or "'frames' must be frames of the same number..." for a typo)
    bad = tmp_path / "sheet.json"
    bad.write_text('{"format": "tabletop.sprites", ' + change + '}')
    data = {"sources": [{"kind": "scripted"}], "engines": [{"kind": "mop",
            "performers": [{"name": "p", "inputs": [{"kind": "puck"}]}],
            "characters": [{"name": "s", "kind": "sprite", "performer": "p", "sheet": str(bad)}]}]}
    with pytest.raises(InputError, match="sheet.json: " + words):
        build(data, tmp_path)
