"""A character's frames (behaviors.mop.puppetry.Puppet): the pose shown and the hint's."""

import numpy as np

from behaviors.motion.clips import Channel, Clip
from behaviors.motion.skeleton import Skeleton2D, place
from behaviors.mop.puppetry import Action, PlanarRig, Puppet, Vote


def _clip(turn: float) -> Clip:
    return Clip("bend", [Channel("a"), Channel("b")], np.array([0.0, 1.0]),
                np.array([[0.0, 0.0], [turn, -turn]]))


def _puppet() -> tuple[Puppet, PlanarRig]:
    rig = PlanarRig(Skeleton2D(("a", "b"), (0, 1), (1.0, 0.5), (0.0, 0.0)))
    return Puppet("c", rig, [Action("bend", _clip(1.0))], x=0.3, y=0.2, heading=0.5, size=0.1,
                  blend_s=0.0), rig


def _at(p: Puppet, rig: PlanarRig, u: float) -> np.ndarray:
    """The bend's pose at ``u``, placed where ``p`` stands, computed afresh."""
    return place(rig.pose(p.actions["bend"].clip, u), p.x, p.y, p.heading, p.size)


def test_each_frame_shows_the_pose_at_its_progress_where_the_character_stands():
    # the pose and its place are kept between frames (Puppet._pose, _place): each frame still
    # equals them computed afresh, on a sample's second frame (the same vote), once the action
    # is replaced under its name, and once the character is moved
    p, rig = _puppet()
    drive = [Vote("bend", 0.9, 0.4, True)]
    first, second = p.update(0.0, drive).points, p.update(1 / 60, drive).points
    np.testing.assert_array_equal(first, _at(p, rig, 0.4))
    np.testing.assert_array_equal(second, _at(p, rig, 0.4))
    p.add_action(Action("bend", _clip(2.0)))
    replaced = p.update(2 / 60, drive).points
    np.testing.assert_array_equal(replaced, _at(p, rig, 0.4))
    assert not np.array_equal(replaced, second)
    p.x = 0.5
    np.testing.assert_array_equal(p.update(3 / 60, drive).points, _at(p, rig, 0.4))
    drive = [Vote("bend", 0.9, 0.5, True)]
    np.testing.assert_array_equal(p.update(4 / 60, drive).points, _at(p, rig, 0.5))


def test_the_hint_shows_the_likeliest_pose_at_its_progress_where_the_character_stands():
    p, rig = _puppet()
    hint = [Vote("bend", 0.6, 0.3, False, hint=True)]
    for k in range(2):
        np.testing.assert_array_equal(p.update(k / 60, hint).hint_points, _at(p, rig, 0.3))
    p.add_action(Action("bend", _clip(-1.0)))
    np.testing.assert_array_equal(p.update(2 / 60, hint).hint_points, _at(p, rig, 0.3))
    p.heading = 1.0
    np.testing.assert_array_equal(p.update(3 / 60, hint).hint_points, _at(p, rig, 0.3))
