"""Hybrid characters whose body is a humanoid (MOP section 3: one action drives skeletal joints
and blendshape weights together): the config that names the body, and the example's mime."""

import numpy as np

from behaviors.motion.skeleton import place
from tabletop.plugins import mop
from tabletop.plugins.mop_table import EXAMPLES, RATE, Table, build, designer_config
from tabletop.registry import BuildContext

from tests.mop.helpers import refused

LINE = str(EXAMPLES / "mop/gestures/line.csv")


def _mime(**keys) -> dict:
    return dict({"name": "mime", "kind": "hybrid", "body": "humanoid", "performer": "hand",
                 "actions": [{"name": "line", "template": LINE, "motion": "punch_angry"}]},
                **keys)


def test_the_body_of_a_hybrid_is_refused_naming_its_key(tmp_path):
    def expect(mutate, *words):
        refused(tmp_path, mutate, *words)

    expect(lambda e: e["characters"][0].update(body="humanoid"),
           "engines[0].characters[0].body", "only a hybrid character takes body")
    expect(lambda e: e["characters"].append(_mime(body="robot")),
           "engines[0].characters[2].body", "robot")
    # the face stands on the neck of pybullet_data's humanoid: no other URDF
    from behaviors.motion.deepmimic import humanoid_urdf
    expect(lambda e: e["characters"].append(_mime(skeleton=str(humanoid_urdf()))),
           "engines[0].characters[2].skeleton", "it takes no skeleton")
    expect(lambda e: e["characters"].append(_mime(actions=[
        {"name": "line", "template": LINE, "motion": "wag_laugh"}])),
           "engines[0].characters[2].actions[0].motion",
           "unknown motion 'wag_laugh' for a humanoid hybrid", "punch_angry")
    # a creature's body is still seen from above: no view of a humanoid
    expect(lambda e: e["characters"].append(_mime(body="creature", view_yaw=1.0, actions=[])),
           "engines[0].characters[2].view_yaw", "only with body: humanoid")
    data = designer_config(tmp_path)               # a humanoid's view is read
    data["engines"][0]["characters"].append(_mime(view_yaw=1.0))
    turned = build(data, tmp_path).puppets["mime"].rig.rest()
    data["engines"][0]["characters"][2]["view_yaw"] = 0.5
    assert np.abs(turned - build(data, tmp_path).puppets["mime"].rig.rest()).max() > 0.01


def test_the_mime_jumps_with_a_surprised_face_from_one_action(example_cfg):
    """The example's humanoid with a face: a zigzag drawn with puck 1 plays jump_surprise, its
    motion-capture joints and its blendshape weights at the one progress followed."""
    from behaviors.mop.creatures import humanoid_hybrid_clip
    ctx = BuildContext(table=(1.2, 0.8), rate_hz=RATE, config=example_cfg, base=EXAMPLES)
    engine = mop.build(example_cfg["engines"][0], ctx)
    table = Table(engine)
    rest = table.rest(1.0)[-1]["mime"]
    run = table.perform("zigzag", puck=1, upto=0.6)
    mime = run[-1][1]["mime"]
    assert mime.kind == "hybrid" and mime.valid and mime.action == "zigzag"
    rig = engine.puppets["mime"].rig
    body = len(rig.body.rest())       # the humanoid's points come first, the face's after them
    expected = place(rig.pose(humanoid_hybrid_clip("jump_surprise"), mime.progress),
                     mime.x, mime.y, mime.heading, mime.size)
    assert np.abs(mime.points - expected).max() < 1e-9   # body and face: one progress
    moved = np.linalg.norm(mime.points[:body] - rest.points[:body], axis=1)

    def shape(p: np.ndarray) -> np.ndarray:    # the face's point-to-point distances (metres):
        return np.linalg.norm(p[:, None] - p[None], axis=2)   # the same however it is turned

    stare = np.abs(shape(mime.points[body:]) - shape(rest.points[body:])).max()
    # measured at 0.59 of the zigzag: a point of the body 79 mm from its rest, the face's shape
    # 14 mm off its rest (a 77 mm face); both 0 while nothing drives it
    assert moved.max() > 0.04                  # the body jumps (metres)
    assert stare > 0.007                       # and the face stares, not only moves with it
