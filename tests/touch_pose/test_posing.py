"""Posing control (section 4): picking, the learned model, blending, CCD IK within limits."""

import numpy as np

from behaviors.touch_pose.humanoid import PARTS, Camera, yaw_of
from behaviors.touch_pose.ik import MAX_CORRECTION
from behaviors.touch_pose.latent import classical_mds, inverse_square, pose_distances
from behaviors.touch_pose.samples import clip_named, clip_poses, place


def _screen_error(engine, part, table_xy):
    """Distance (metres of the character's own scale) between a part and a touch on screen."""
    p = np.array(engine.frame(0.0)["parts"][part])
    return float(np.linalg.norm(p - np.asarray(table_xy))) / engine.scale


def test_dragging_a_hand_to_a_reachable_point_reaches_it_within_limits(make, models):
    e = make(view=(30.0, 20.0))
    start = np.array(e.describe()["parts"]["right_hand"])
    # a reachable point: where the hand is in a recorded posture (the wave, arm half raised)
    wave = clip_poses(models.body, clip_named("wave"), np.array([0.15]))[0]
    goal = e.camera.table(models.body.parts(place(wave, e.base, e.yaw))[PARTS.index("right_hand")])
    assert np.linalg.norm(goal - start) / e.scale > 0.15  # a real drag, not a nudge
    for k in range(75):  # 1 s drag, then 1.5 s held
        t = k / 30
        e.step(t, {7: tuple(start + (goal - start) * min(t, 1.0))})
    assert e.fingers[7].part == "right_hand"
    assert _screen_error(e, "right_hand", goal) < 0.02
    assert models.body.violations(e.output.rots) == []
    assert models.body.violations(e.target.rots) == []


def test_several_fingers_pose_several_parts(make, models):
    e = make(view=(90.0, 15.0), physics=False)
    parts = e.describe()["parts"]
    moves = {"left_hand": (0.0, 0.03), "right_hand": (0.02, 0.02), "head": (0.005, -0.01)}
    for k in range(60):
        t = k / 30
        e.step(t, {i: tuple(np.array(parts[p]) + np.array(d) * min(t, 1.0))
                   for i, (p, d) in enumerate(moves.items())})
    for i, (p, d) in enumerate(moves.items()):
        assert e.fingers[i].part == p
        assert _screen_error(e, p, np.array(parts[p]) + d) < 0.02, p
    assert models.body.violations(e.output.rots) == []


def test_a_touch_on_empty_table_picks_nothing_and_moves_nothing(make):
    e = make(physics=False)
    before = e.frame(0.0)["joints"]
    for k in range(20):
        f = e.step(k / 30, {3: (0.1, 0.1 + 0.005 * k)})
    assert f["touches"] == {"3": None}
    after = f["joints"]
    assert max(np.abs(np.array(after[j]) - np.array(before[j])).max() for j in before) < 1e-3


def test_ik_never_corrects_more_than_the_limit(make, models):
    e = make(physics=False)
    hand = e.describe()["parts"]["right_hand"]
    far = (hand[0] + 0.3, hand[1] + 0.3)  # metres on the table: out of any reach
    e.step(0.0, {1: tuple(hand)})
    e.step(1 / 30, {1: far})
    names, targets = e._constraints()
    from behaviors.touch_pose.latent import yaw_view
    view, offset = yaw_view(e.camera.matrix, e.base, e.yaw)
    blend = models.posing.synthesize(np.array([PARTS.index("right_hand")]), targets, view, offset)
    blended = models.body.parts(place(blend.pose, e.base, e.yaw))[PARTS.index("right_hand")]
    solved = models.body.parts(e.target)[PARTS.index("right_hand")]
    assert np.linalg.norm(solved - blended) <= MAX_CORRECTION + 1e-6
    assert np.linalg.norm(solved - blended) > 0.1  # it did use the correction


def test_the_blend_takes_other_weights(models):
    # weights of the constraint distances (the blend bench's hook): all on the nearest sample
    # gives that sample's posture; the default is 1 / (d + EPS)^2
    model, view = models.posing, Camera(90.0, 15.0, 1.0).matrix
    hand = np.array([PARTS.index("right_hand")])
    target = models.body.parts(models.stand)[hand] @ view.T + np.array([[0.1, 0.2]])
    nearest = model.synthesize(hand, target, view, np.zeros(2),
                               lambda d: (d == d.min()).astype(float))
    k = nearest.index[int(np.argmax(nearest.weight))]
    assert np.allclose(nearest.pose.rots, model.rots[k]) and np.allclose(nearest.pose.root,
                                                                           model.roots[k])
    plain = model.synthesize(hand, target, view, np.zeros(2))
    d = model.constraint_distance(plain.index, hand, target, view, np.zeros(2))
    assert np.allclose(plain.weight, inverse_square(d) / inverse_square(d).sum())


def test_latent_space_preserves_pose_distances(models):
    m = models.posing
    d_latent = np.linalg.norm(m.latent[:, None] - m.latent[None], axis=2)
    iu = np.triu_indices(len(m), 1)
    r = np.corrcoef(m.distance[iu], d_latent[iu])[0, 1]
    assert r > 0.8
    assert len(m.rep) == len(m.cells) and len(m.rep) >= 10
    # classical MDS recovers points exactly when distances are Euclidean
    pts = np.random.default_rng(0).normal(size=(30, 2))
    d = np.linalg.norm(pts[:, None] - pts[None], axis=2)
    y = classical_mds(d, 2)
    assert np.allclose(np.linalg.norm(y[:, None] - y[None], axis=2), d, atol=1e-8)
    assert pose_distances(np.zeros((3, 4, 3))).sum() == 0.0


def test_camera_half_lines_and_projection_agree():
    cam = Camera(90.0, 15.0, 0.2, (0.6, 0.4))
    p = np.array([0.3, 1.2, -0.4])
    s = cam.screen(p)
    q = cam.ray_point(s, np.zeros(3))  # another point of the same half-line
    assert np.allclose(cam.screen(q), s)
    assert np.allclose(cam.to_screen(cam.table(p)), s)
    # azimuth 90 looks from the character's right: its forward (+x) is screen right
    assert cam.right @ np.array([1.0, 0, 0]) > 0.99


def test_joint_limits_clamp_one_by_one_and_together(models):
    from behaviors.motion.clips import quat_normalize
    body = models.body
    rng = np.random.default_rng(1)
    for _ in range(50):
        r = quat_normalize(rng.normal(size=(13, 4)))
        for i in np.flatnonzero(body.hinge):
            a = rng.uniform(-4, 4)
            r[i] = np.r_[np.cos(a / 2), np.sin(a / 2) * body.axis[i]]
        one, many = r.copy(), r.copy()
        for i in range(1, 13):
            body.clamp(one, i)
        body.clamp_many(many, list(range(13)))
        assert np.allclose(np.abs(np.einsum("ij,ij->i", one, many)), 1.0, atol=1e-9)
        assert body.violations(many) == []


def test_posing_samples_stand_in_place(models):
    """Every posing sample's pelvis at its motion's start, heading 0 (see samples' module doc)."""
    post = models.posing
    assert np.hypot(post.roots[:, 0], post.roots[:, 2]).max() <= 1e-9
    assert max(abs(yaw_of(q)) for q in post.rots[:, 0]) <= 1e-9


def test_posing_never_walks_the_character_away(make):
    e = make(view=(90.0, 15.0), physics=False)
    parts = e.describe()["parts"]
    home = {1: np.array(parts["right_hand"]), 2: np.array(parts["left_hand"]),
            3: np.array(parts["left_foot"])}
    far = 0.0
    for k in range(240):   # 8 s of three fingers in wide circles
        a = 2 * np.pi * k / 75
        e.step(k / 30, {i: tuple(h + 0.06 * np.array([np.cos(a + i) - np.cos(i),
                                                      np.sin(a + 2 * i) - np.sin(2 * i)]))
                        for i, h in home.items()})
        far = max(far, float(np.hypot(*(e.output.root[[0, 2]] - e.base))))
    assert far <= 0.01
