"""The URDF humanoid, the DeepMimic clips driving it, the projection onto the table, 2-D
skeletons."""

import json
import math

import numpy as np
import pytest

from behaviors.motion.clips import ClipError
from behaviors.motion.deepmimic import (FRAME_WIDTH, ROOT_SCALE, humanoid_pose, humanoid_urdf,
                                     load_motion, motion_path, parse_motion)
from behaviors.motion.skeleton import (Projection, ProjectedFigure, Skeleton2D, SkeletonError,
                                    load_urdf, place)

CLIPS = ["walk", "run", "jump", "kick", "punch", "spinkick", "backflip", "cartwheel", "crawl",
         "dance_a", "dance_b", "getup_facedown", "getup_faceup", "roll", "spin"]


@pytest.fixture(scope="module")
def humanoid():
    return load_urdf(humanoid_urdf())


def _pose3d(sk, clip, p):
    root, rot, joints = humanoid_pose(clip, clip.sample(p))
    return sk.forward(root * ROOT_SCALE, rot, joints)


def test_urdf_tree_and_tips(humanoid):
    names = humanoid.point_names
    for n in ("root", "chest", "neck", "right_knee", "left_elbow", "right_wrist", "neck_tip",
              "right_ankle_tip", "left_ankle_tip"):
        assert n in names
    rest = humanoid.forward()
    y = {n: rest[i, 1] for i, n in enumerate(names)}
    # standing at rest, y up: head above neck above chest above root above knees above ankles
    assert y["neck_tip"] > y["neck"] > y["chest"] > y["root"] > y["right_knee"] > y["right_ankle"]
    # the toe points forward (+x) from the ankle
    i, j = names.index("right_ankle"), names.index("right_ankle_tip")
    assert rest[j, 0] - rest[i, 0] > 0.3


def test_every_humanoid_clip_loads_with_the_interpolator_layout():
    for name in CLIPS:
        clip = load_motion(name)
        assert clip.width == FRAME_WIDTH - 1
        raw = json.loads(motion_path(name).read_text())["Frames"]
        # knees bend one way and elbows the other (URDF limits): true only if the angles sit
        # where humanoid_pose_interpolator.py reads them (frame[20], [34] knees; [29], [43] elbows)
        knees = np.array([[f[20], f[34]] for f in raw])
        elbows = np.array([[f[29], f[43]] for f in raw])
        # (a few frames of some clips hyperextend a knee by up to 0.22 rad)
        assert np.mean(knees <= 0.05) > 0.95 and knees.max() < 0.3, name
        assert elbows.min() >= -0.05, name
        # and the quaternions read there are unit length (some clips hold a few frames of
        # slightly off-unit quaternions, which the loader normalises), unlike a layout shifted
        # by one number
        starts = np.array([4, 8, 12, 16, 21, 25, 30, 35, 39])
        for shift, ok in ((0, True), (1, False), (-1, False)):
            quats = np.array([[f[k + shift:k + shift + 4] for k in starts] for f in raw])
            off = np.abs(np.linalg.norm(quats, axis=2) - 1.0)
            assert (np.median(off) < 1e-3) == ok, (name, shift)
        chest = clip.values[:, clip.slices["chest"]]
        assert np.abs(np.linalg.norm(chest, axis=1) - 1).max() < 1e-12


def test_walk_keeps_bone_lengths_feet_on_floor_and_alternates_feet(humanoid):
    clip = load_motion("walk")
    rest = humanoid.forward()
    names = humanoid.point_names
    r, l = names.index("right_ankle_tip"), names.index("left_ankle_tip")
    root = names.index("root")
    fwd_r, fwd_l, lowest = [], [], []
    for p in np.linspace(0, 1, 40):
        pts = _pose3d(humanoid, clip, p)
        for a, b in humanoid.bones:
            assert abs(np.linalg.norm(pts[a] - pts[b]) - np.linalg.norm(rest[a] - rest[b])) < 1e-9
        assert pts[names.index("neck_tip"), 1] > pts[root, 1] + 1.5      # upright throughout
        lowest.append(min(pts[r, 1], pts[l, 1]))
        fwd_r.append(pts[r, 0] - pts[root, 0])
        fwd_l.append(pts[l, 0] - pts[root, 0])
    # one foot is always on (or within 0.35 units of) the floor, y = 0
    assert max(abs(v) for v in lowest) < 0.35
    # the feet swing in opposite phase
    assert np.corrcoef(fwd_r, fwd_l)[0, 1] < -0.5


def test_backflip_turns_upside_down(humanoid):
    clip = load_motion("backflip")
    names = humanoid.point_names
    head, root = names.index("neck_tip"), names.index("root")
    heights = [(_pose3d(humanoid, clip, p)[head, 1] - _pose3d(humanoid, clip, p)[root, 1])
               for p in np.linspace(0, 1, 60)]
    assert heights[0] > 2.0 and heights[-1] > 2.0 and min(heights) < -1.0


def test_projected_figure_is_one_height_tall_on_the_floor(humanoid):
    fig = ProjectedFigure(humanoid, Projection(view_yaw=0.5, elevation=0.25), ROOT_SCALE)
    rest = fig.rest_points()
    assert abs(rest[:, 1].max() - rest[:, 1].min() - 1.0) < 1e-12 and abs(rest[:, 1].min()) < 1e-12
    clip = load_motion("walk")
    root_i = humanoid.point_names.index("root")
    xs = []
    for p in np.linspace(0, 1, 20):
        root, rot, joints = humanoid_pose(clip, clip.sample(p))
        pts = fig.points(root, rot, joints)
        xs.append(pts[root_i, 0])
        assert 0.85 < pts[:, 1].max() - pts[:, 1].min() < 1.1
    assert max(abs(x) for x in xs) < 1e-9       # walked in place
    first = clip.sample(0.0)
    origin = humanoid_pose(clip, first)[0]
    root, rot, joints = humanoid_pose(clip, clip.sample(1.0))
    travelled = fig.points(root, rot, joints, travel=True, origin=origin)[root_i, 0]
    assert travelled > 0.3                       # the walk clip moves forward about 0.8 heights


def test_place_turns_figure_up_onto_heading():
    pts = np.array([[0.0, 0.0], [0.0, 1.0], [0.5, 0.0]])
    out = place(pts, 0.4, 0.3, heading=math.pi / 2, scale=0.1)
    assert np.allclose(out[0], [0.4, 0.3])
    assert np.allclose(out[1], [0.4, 0.4])       # up goes along +y, the heading
    assert np.allclose(out[2], [0.45, 0.3])      # screen right is the heading's right (+x here)


def test_planar_skeleton_forward_kinematics():
    sk = Skeleton2D(["a", "b", "c"], [0, 1, 1], [1.0, 0.5, 0.5], [0.0, 0.0, math.pi / 2])
    pts = sk.forward()
    assert np.allclose(pts, [[0, 0], [1, 0], [1.5, 0], [1, 0.5]])
    pts = sk.forward([math.pi / 2, 0.0, 0.0])
    assert np.allclose(pts, [[0, 0], [0, 1], [0, 1.5], [-0.5, 1]])
    with pytest.raises(SkeletonError, match="earlier bone"):
        Skeleton2D(["a", "b"], [0, 2], [1, 1], [0, 0])


def test_missing_and_bad_files_are_named(tmp_path):
    with pytest.raises(SkeletonError, match="nothere.urdf: skeleton file not found"):
        load_urdf(tmp_path / "nothere.urdf")
    bad = tmp_path / "bad.urdf"
    bad.write_text("<robot><link name='a'/><joint name='j' type='planar'><parent link='a'/>"
                   "<child link='a'/></joint></robot>")
    with pytest.raises(SkeletonError, match="bad.urdf: joint 'j' has type 'planar'"):
        load_urdf(bad)
    with pytest.raises(ClipError, match="nothere.txt: DeepMimic clip not found"):
        load_motion(tmp_path / "nothere.txt")
    with pytest.raises(ClipError, match="humanoid3d_nosuch.txt") as err:
        load_motion("nosuch")
    assert "the clips: backflip, cartwheel, " in str(err.value) and str(err.value).endswith(
        ", walk")
    assert "did you mean" not in str(err.value)
    # a misspelt clip names the likely one
    for typo in ("wlak", "spinkik"):
        with pytest.raises(ClipError, match=f"{typo}.*; did you mean '(walk|spinkick)'\\? the "
                           "clips: backflip"):
            load_motion(typo)
    short = tmp_path / "short.txt"
    short.write_text(json.dumps({"Loop": "none", "Frames": [[0.1] * 44, [0.1] * 43]}))
    with pytest.raises(ClipError, match="short.txt: frame 1 has 43 numbers"):
        load_motion(short)
    with pytest.raises(ClipError, match="not a DeepMimic motion"):
        parse_motion({"frames": []}, "x.txt")


def test_humanoid_rig_keyframe_cache_matches_full_kinematics(humanoid):
    from behaviors.mop.puppetry import HumanoidRig
    rig = HumanoidRig(ProjectedFigure(humanoid, Projection(), ROOT_SCALE))
    for name in ("walk", "backflip", "spinkick"):
        clip = load_motion(name)
        err = max(np.abs(rig.pose(clip, p) - rig.exact_pose(clip, p)).max()
                  for p in np.linspace(0, 1, 397))
        assert err < 0.01, name    # figure heights: under 1% of the body's height
        assert np.abs(rig.pose(clip, 1.0) - rig.exact_pose(clip, 1.0)).max() < 1e-12
