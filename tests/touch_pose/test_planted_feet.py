"""Posing control keeps the planted feet where they stand (paper 003, section 4: IK fixes the
foot positions on the ground) while a finger drags another part, also where the blended
posture crouches and its legs lie far from the planted feet."""

import numpy as np
import pytest

from behaviors.touch_pose.humanoid import PARTS

FEET = [PARTS.index("left_foot"), PARTS.index("right_foot")]


def drag(e, part: str, by: tuple[float, float], seconds: float = 2.0, rate: float = 30.0):
    """Drag ``part`` by ``by`` (table m); the feet's largest move on the table (m) and their
    lowest height over the frames (metres of the character's scale; the ground is 0)."""
    e.step(0.0, {})
    start = e.table_points()[e._np:][FEET].copy()
    xy = e.table_points()[e._np:][PARTS.index(part)].copy()
    n = int(seconds * rate)
    lowest = np.inf
    for k in range(1, n + 1):
        e.step(k / rate, {1: tuple(xy + np.array(by) * k / n)})
        lowest = min(lowest, float(e.body.parts(e.target)[FEET][:, 1].min()))
    moved = float(np.linalg.norm(e.table_points()[e._np:][FEET] - start, axis=1).max())
    return moved, lowest


# (view, part, drag (table m), largest foot move allowed (table m)); measured with the legs'
# own IK / with CCD alone (feet's lowest height, character m; largest move, table m):
# 0.036 / -0.083, 0.005 / 0.057; 0.048 / -0.086, 0.001 / 0.034; 0.043 / -0.058, 0.030 / 0.040;
# 0.045 / -0.058, 0.013 / 0.013 (the feet stand at 0.048)
CASES = [((60.0, 30.0), "head", (0.0, -0.1), 0.01),
         ((60.0, 30.0), "right_hand", (0.0, -0.1), 0.01),
         ((250.0, 25.0), "left_hand", (0.0, -0.1), 0.035),
         ((320.0, 15.0), "left_hand", (0.0, -0.08), 0.02)]


@pytest.mark.parametrize("view, part, by, most", CASES)
def test_a_crouch_keeps_the_planted_feet_above_the_ground(make, view, part, by, most):
    e = make(view=view, physics=False)
    moved, lowest = drag(e, part, by)
    assert lowest > 0.02
    assert moved < most
