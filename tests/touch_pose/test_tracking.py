"""Tracking control (section 6): equations 2-4, the physical effect (6-7), feet re-fixed by IK."""

import numpy as np

from behaviors.touch_pose.humanoid import PARTS
from behaviors.touch_pose.tracking import (PhysicalEffect, Tracker, apply_effect, free_segments,
                                           rot_diff)


def test_acceleration_tracking_reaches_a_jumped_target_smoothly(models):
    body = models.body
    start = models.posing.blend(np.array([0]), np.array([1.0])).pose
    goal = models.posing.blend(np.array([len(models.posing) - 1]), np.array([1.0])).pose
    jump = np.degrees(np.linalg.norm(rot_diff(goal.rots, start.rots), axis=1)).max()
    assert jump > 60
    tr = Tracker(start)
    prev, steps = start.rots, []
    for _ in range(30):  # 1 s at 30 fps
        pose = tr.step(goal, 1 / 30)
        steps.append(np.degrees(np.linalg.norm(rot_diff(pose.rots, prev), axis=1)).max())
        prev = pose.rots
    assert max(steps) < 0.25 * jump            # never more than a quarter of the jump a frame
    assert np.degrees(np.linalg.norm(rot_diff(pose.rots, goal.rots), axis=1)).max() < 2.0
    assert np.linalg.norm(pose.root - goal.root) < 0.005
    assert body.violations(pose.rots) == []


def test_physical_effect_only_on_free_segments():
    assert free_segments({"right_hand"}, {"left_foot", "right_foot"}) == {"torso", "left_arm"}
    assert free_segments({"pelvis"}, set()) == {"right_arm", "left_arm", "right_leg", "left_leg"}


def test_secondary_motion_sways_free_parts_and_keeps_planted_feet(make, models):
    e = make(view=(90.0, 15.0), physics=True)
    hand = np.array(e.describe()["parts"]["right_hand"])
    dev_arm, dev_leg, foot_err = [], [], []
    li = [models.body.names.index(j) for j in ("left_shoulder", "left_elbow")]
    for k in range(60):  # the right hand dragged quickly up and down
        t = k / 30
        e.step(t, {1: tuple(hand + [0.0, 0.03 * np.sin(2 * np.pi * t)])})
        d = np.degrees(np.linalg.norm(rot_diff(e.output.rots, e.tracker.pose.rots), axis=1))
        dev_arm.append(d[li].max())
        grounded = e._grounded(e.target)
        out, tracked = models.body.parts(e.output), models.body.parts(e.tracker.pose)
        for f in grounded:
            foot_err.append(np.linalg.norm(out[PARTS.index(f)] - tracked[PARTS.index(f)]))
        dev_leg.append(d[[models.body.names.index("right_hip")]].max() if not grounded else 0.0)
    assert max(dev_arm) > 1.0          # the untouched arm is shaken by the body's motion
    assert max(dev_arm) < 30.0         # ... and stays a secondary motion
    assert foot_err and max(foot_err) < 0.02  # planted feet re-fixed by IK (metres)
    effect = PhysicalEffect(len(models.body.names))
    effect.dq[:] = 0.1
    pose = e.tracker.pose
    shaken = apply_effect(models.body, pose, effect, {"left_arm"})
    changed = np.linalg.norm(rot_diff(shaken.rots, pose.rots), axis=1) > 1e-6
    assert set(np.array(models.body.names)[changed]) == {"left_shoulder", "left_elbow"}
