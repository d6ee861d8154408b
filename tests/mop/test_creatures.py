"""The creature (planar skeleton + joint-angle clips) and the face (blendshapes + weight clips)."""

import numpy as np

from behaviors.mop.creatures import FaceModel, creature_clips, creature_skeleton, face_clips


def _names(sk):
    return {n: i + 1 for i, n in enumerate(sk.names)}   # bone name -> its end point


def test_creature_rest_pose_is_a_symmetric_body():
    sk = creature_skeleton()
    pts = sk.forward()
    ix = _names(sk)
    assert pts[ix["head"], 0] > 0.25 and pts[ix["tail_4"], 0] < -0.35
    span = pts[:, 0].max() - pts[:, 0].min()
    assert abs(span - 1.0) < 0.05                               # one body length, nose to tail
    for left, right in (("front_left_lower", "front_right_lower"),
                        ("hind_left_lower", "hind_right_lower")):
        assert np.allclose(pts[ix[left]], pts[ix[right]] * [1, -1])
        assert pts[ix[left], 1] > 0.05                          # left is +y


def test_creature_clips_keep_bone_lengths_and_loops_close():
    sk = creature_skeleton()
    for name, clip in creature_clips().items():
        for p in np.linspace(0, 1, 25):
            pts = sk.forward(clip.sample(p))
            lengths = [np.linalg.norm(pts[b] - pts[a]) for a, b in sk.bones]
            assert np.allclose(lengths, sk.lengths, atol=1e-12), name
        if clip.loop:
            assert np.allclose(sk.forward(clip.sample(0.0)),
                               sk.forward(clip.sample(1.0)), atol=1e-9)


def test_creature_motions_do_what_they_say():
    sk = creature_skeleton()
    clips = creature_clips()
    ix = _names(sk)
    rest = sk.forward()

    def reach(pts):
        return np.linalg.norm(pts[ix["head"]] - pts[ix["tail_4"]])

    # curl: nose and tail tip come together half way, and part again at the end
    mid = sk.forward(clips["curl"].sample(0.5))
    assert reach(mid) < 0.6 * reach(rest)
    assert abs(reach(sk.forward(clips["curl"].sample(1.0))) - reach(rest)) < 1e-9
    # walk: diagonal feet move together, left and right front feet in opposite phase
    fl, fr, hr = [], [], []
    for p in np.linspace(0, 1, 24, endpoint=False):
        pts = sk.forward(clips["walk"].sample(p))
        fl.append(pts[ix["front_left_lower"], 0])
        fr.append(pts[ix["front_right_lower"], 0])
        hr.append(pts[ix["hind_right_lower"], 0])
    assert np.corrcoef(fl, fr)[0, 1] < -0.8
    assert np.corrcoef(fl, hr)[0, 1] > 0.5
    # wag: the tail tip sweeps to both sides
    tips = [sk.forward(clips["wag"].sample(p))[ix["tail_4"], 1] for p in np.linspace(0, 1, 41)]
    assert max(tips) > 0.1 and min(tips) < -0.1
    # strike: the front feet reach forward of the nose's rest line at its peak
    peak = sk.forward(clips["strike"].sample(0.3))
    assert peak[ix["front_left_lower"], 0] > rest[ix["front_left_lower"], 0] + 0.05


def test_face_blendshapes():
    face = FaceModel()
    n = len(face.BLENDSHAPES)
    s = face.part_slices
    neutral = face.points(np.zeros(n))
    assert np.allclose(neutral, face.neutral)
    # the neutral face is symmetric but for its nose: every point's mirror image is a point
    sym = np.delete(neutral, np.arange(len(neutral))[s["nose"]], axis=0)
    d = np.linalg.norm((sym * [-1, 1])[:, None] - sym[None], axis=2).min(axis=1)
    assert d.max() < 1e-9

    def w(**kw):
        v = np.zeros(n)
        for k, val in kw.items():
            v[face.BLENDSHAPES.index(k)] = val
        return face.points(v)

    def height(pts, part):
        return np.ptp(pts[s[part], 1])

    mouth = s["mouth"]
    smile = w(smile=1.0)
    corner = np.argmax(np.abs(neutral[mouth, 0]))
    centre = np.argmin(np.abs(neutral[mouth, 0]) + (neutral[mouth, 1] > -0.25))
    lift = (smile[mouth][corner, 1] - smile[mouth][centre, 1]) - \
           (neutral[mouth][corner, 1] - neutral[mouth][centre, 1])
    assert lift > 0.04
    frown = w(frown=1.0)
    assert (frown[mouth][corner, 1] - frown[mouth][centre, 1]) < \
           (neutral[mouth][corner, 1] - neutral[mouth][centre, 1]) - 0.04
    assert height(w(jaw_open=1.0), "mouth") > height(neutral, "mouth") + 0.08
    blink = w(blink_left=1.0)
    assert height(blink, "eye_left") < 0.1 * height(neutral, "eye_left")
    assert np.allclose(blink[s["eye_right"]], neutral[s["eye_right"]])
    assert w(brows_up=1.0)[s["brow_left"], 1].min() > neutral[s["brow_left"], 1].max()
    # weights blend linearly
    half = w(smile=0.5, jaw_open=0.5)
    assert np.allclose(half, neutral + 0.5 * (smile - neutral) + 0.5 * (w(jaw_open=1.0) - neutral))


def test_face_clips_are_weights_between_zero_and_one():
    face = FaceModel()
    clips = face_clips()
    assert set(clips) == {"laugh", "surprise", "angry", "wink", "talk"}
    for clip in clips.values():
        assert clip.names == face.BLENDSHAPES
        v = clip.sample_many(np.linspace(0, 1, 50))
        assert v.min() >= 0.0 and v.max() <= 1.0
        assert face.points(v[10]).shape == (len(face.neutral), 2)
    peak = clips["surprise"].sample(0.6)
    assert clips["surprise"].channel(peak, "brows_up")[0] > 0.9
    assert np.allclose(clips["wink"].sample(0.0), 0.0)


def test_a_humanoids_face_stands_on_its_neck_and_turns_with_its_head():
    """The hybrid humanoid's motions (MOP section 3): each plays its motion-capture joints and
    its expression at one progress; the face's chin is on the neck, its eyes toward the head,
    through a cartwheel's upside-down poses too."""
    from behaviors.motion.deepmimic import load_motion, motion_path
    from behaviors.mop.creatures import (HUMANOID_HYBRID_MOTIONS, humanoid_hybrid_clip,
                                         merge_clips)
    from tabletop.plugins.mop_rigs import HUMANOID_HEAD, HUMANOID_NECK, make_rig
    rig = make_rig({"kind": "hybrid", "body": "humanoid", "skeleton": None, "view_yaw": 0.5,
                    "elevation": 0.25, "travel": False})
    face = FaceModel()
    k = len(rig.body.rest())
    eyes = np.r_[face.part_slices["eye_left"], face.part_slices["eye_right"]] + k
    chin = k + int(np.argmin(face.neutral[face.part_slices["outline"], 1]))
    for name in HUMANOID_HYBRID_MOTIONS:
        clip = humanoid_hybrid_clip(name)
        rig.check(clip)
        assert clip.duration == load_motion(motion_path(HUMANOID_HYBRID_MOTIONS[name][0])).duration
    cartwheel = merge_clips("c", load_motion(motion_path("cartwheel")), face_clips()["laugh"])
    ups = []
    for q in np.linspace(0, 1, 41):
        p = rig.pose(cartwheel, float(q))
        up = p[HUMANOID_HEAD] - p[HUMANOID_NECK]
        up /= np.linalg.norm(up)
        ups.append(up[1])
        # measured (standing heights): the chin at most 0.021 from the neck (the laugh's jaw
        # opens it), the eyes 0.18 along neck -> head in every pose
        assert np.linalg.norm(p[chin] - p[HUMANOID_NECK]) < 0.04
        assert (p[eyes] - p[HUMANOID_NECK]).mean(axis=0) @ up > 0.15
    assert min(ups) < -0.5                     # the cartwheel turns the head over (-0.90)
