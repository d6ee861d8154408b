"""Sample motions per action: the jump's second motion is the clip mirrored, and the action's
trajectory and postures average over both."""

import numpy as np

from behaviors.touch_pose.humanoid import PARTS
from behaviors.touch_pose.latent import Blend
from behaviors.touch_pose.samples import ACTIONS, MIRRORED, clip_named, clip_poses


def test_a_mirrored_clip_is_the_same_motion_with_the_other_side_leading(models):
    body = models.body
    u = np.linspace(0.0, 1.0, 25)
    a = np.array([body.parts(p) for p in clip_poses(body, clip_named("jump"), u)])
    b = np.array([body.parts(p) for p in clip_poses(body, clip_named("jump" + MIRRORED), u)])
    flip = np.array([1.0, 1.0, -1.0])
    swap = [PARTS.index(p.replace("left", "@").replace("right", "left").replace("@", "right"))
            for p in PARTS]
    assert np.abs(b - a[:, swap] * flip).max() < 1e-9
    assert np.abs(a[:, PARTS.index("pelvis"), 2]).max() > 0.03  # the recorded jump drifts sideways
    poses = clip_poses(body, clip_named("jump" + MIRRORED), u)
    assert sum(len(body.violations(p.rots)) for p in poses) == 0


def test_the_jump_averages_its_two_sample_motions(models):
    jump = next(a for a in models.actions if a.name == "jump")
    assert [s.motions for s in ACTIONS if s.name == "jump"] == [("jump", "jump" + MIRRORED)]
    model = jump.model
    assert np.bincount(model.motion).tolist() == [107, 107]
    # the average stroke: forward and up as recorded, the sideways drift of each motion cancels
    assert abs(jump.stroke[-1, 2]) < 1e-9 and jump.stroke[-1, 0] > 0.5
    # postures at a generalised time: one motion alone, or both by their share of the weights
    pelvis = PARTS.index("pelvis")
    only = [Blend(np.flatnonzero(model.motion == m)[:1], np.ones(1), None, 0.0) for m in (0, 1)]
    za, zb = (models.body.parts(model.at_time(b, 0.6).pose)[pelvis, 2] for b in only)
    z_mean = models.body.parts(model.at_time(None, 0.6).pose)[pelvis, 2]
    assert za > 0.03 and abs(za + zb) < 1e-6 and abs(z_mean) < 1e-6
    # one motion per action elsewhere: its posture at u is that clip's
    punch = next(a for a in models.actions if a.name == "punch")
    assert punch.model.motion.max() == 0
