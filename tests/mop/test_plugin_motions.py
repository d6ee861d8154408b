"""A character's built-in motions as the engine's loader gives them
(:class:`tabletop.plugins.mop_files.MotionLoader`): each its own clip, as made alone."""

import numpy as np
import pytest

from behaviors.mop.creatures import creature_clips, face_clips, hybrid_clips
from tabletop.plugins.mop_files import MotionLoader
from tabletop.plugins.mop_table import EXAMPLES


@pytest.mark.parametrize("kind, made", [("creature", creature_clips), ("face", face_clips),
                                        ("hybrid", hybrid_clips)])
def test_each_built_in_motion_is_its_own_clip_as_made_alone(kind, made):
    # the loader makes its kind's clips once for all its motions: asked in any order, each
    # motion is its own clip, equal to the one made alone, and the same clip when asked again
    alone = made()
    load = MotionLoader(kind, EXAMPLES)
    for name in reversed(list(alone)):
        clip = load(name)
        assert clip.name == name
        assert [c.name for c in clip.channels] == [c.name for c in alone[name].channels]
        np.testing.assert_array_equal(clip.times, alone[name].times)
        np.testing.assert_array_equal(clip.values, alone[name].values)
        assert load(name) is clip
