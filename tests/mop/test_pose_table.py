"""The humanoid rig's pose table, worked out in bulk, against its per-sample kinematics."""

import numpy as np
import pytest

from behaviors.motion.clips import Clip
from behaviors.motion.deepmimic import ROOT_SCALE, humanoid_urdf, load_motion
from behaviors.motion.skeleton import Projection, ProjectedFigure, load_urdf
from behaviors.mop.puppetry import HumanoidRig


@pytest.fixture(scope="module")
def figure() -> ProjectedFigure:
    return ProjectedFigure(load_urdf(humanoid_urdf()), Projection(), ROOT_SCALE)


def _clip(name: str) -> Clip:
    """A DeepMimic clip; ``moved``: the walk started away from the origin (every shipped clip
    starts its root at x = z = 0, where a travelling root's origin cancels)."""
    if name != "moved":
        return load_motion(name)
    walk = load_motion("walk")
    values = walk.values.copy()
    values[:, [walk.slices["root_x"].start, walk.slices["root_z"].start]] += [0.7, -0.3]
    return Clip("moved", walk.channels, walk.times, values, walk.loop)


@pytest.mark.parametrize("travel", [False, True])
@pytest.mark.parametrize("name", ["cartwheel", "walk", "moved"])
def test_bulk_table_equals_exact_pose_at_sampled_progresses(figure, name, travel):
    rig = HumanoidRig(figure, travel)
    clip = _clip(name)
    table = rig._table(clip)
    rows = np.unique(np.r_[0, len(table) - 1, np.linspace(0, len(table) - 1, 25).astype(int)])
    for i in rows:   # the table's own rows, at their progress
        u = i / (len(table) - 1)
        assert np.abs(table[i] - rig.exact_pose(clip, u)).max() < 1e-12, (name, u)
    off = np.array([0.0, 0.013, 0.29, 0.5, 0.777, 1.0, np.nan])   # between keys, and NaN -> 0
    bulk = rig.exact_poses(clip, off)
    for u, pts in zip(off, bulk):
        # measured: at most 4.4e-16 apart (the slerp's quaternion dot product summed in
        # another order along the sample axis)
        assert np.abs(pts - rig.exact_pose(clip, u)).max() < 1e-12, (name, u)


def test_rigs_share_a_table_only_for_the_same_figure_and_clip(figure):
    walk = load_motion("walk")
    table = HumanoidRig(figure)._table(walk)
    assert HumanoidRig(figure)._table(load_motion("walk")) is table   # a rebuild: no new table
    travel = HumanoidRig(figure, travel=True)
    assert travel._table(walk) is not table
    values = walk.values.copy()
    values[:, walk.slices["root_y"].start] += 0.1    # the same walk, 0.1 model units higher
    raised = Clip("walk", walk.channels, walk.times, values, walk.loop)
    assert np.abs(travel._table(raised) - travel._table(walk)).max() > 0.05   # measured 0.063
    turned = HumanoidRig(ProjectedFigure(figure.skeleton, Projection(view_yaw=1.0), ROOT_SCALE))
    other = turned._table(walk)
    assert other is not table
    assert np.abs(other[7] - turned.exact_pose(walk, 7 / (len(other) - 1))).max() < 1e-12
