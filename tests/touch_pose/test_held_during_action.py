"""A part held by a second finger while an action plays (paper 003, section 7: the interface
"can be used not only to move body parts but also to fix them", during posing or action control)."""

import numpy as np
import pytest

from behaviors.touch_pose.humanoid import PARTS

#: Largest median distance (table metres, 0.3 m tall) of the held part's target from its finger
#: over the action's frames. Measured (view 90,15, physics off): walk 0.018, punch 0.051, kick
#: 0.006; with the held part's IK goal kept within 0.2 m of where the action puts it, 0.126,
#: 0.133 and 0.095 (the part went with the travelling body).
HELD_MEDIAN_M = 0.07
#: The same over the posing frames after the action, the finger still down: walk 0.063, punch
#: 0.028, kick 0.006; with posing's 0.2 m limit for it there, 0.102, 0.099 and 0.006 (the body
#: stood where the action took it and the part stayed away from its finger).
AFTER_MEDIAN_M = 0.08

#: Largest step (table m per 30 fps frame) of the held part's target over the action's last 10
#: frames and the 8 posing frames after it. Measured (physics off), views 90,15 / 60,30 / 90,40:
#: after the action at most 0.003 walk, 0.008 punch, 0.004 kick (its last frames 0.007, 0.008,
#: 0.003); with posing taking over at once from the base, 0.047, 0.132 and 0.038 (the held part
#: jumped, then moved back the next frame: walk 0.047, 0.037).
HANDOVER_STEP_M = 0.02

#: (action, the part held while it runs)
HELD = [("walk", "right_hand"), ("punch", "left_hand"), ("kick", "left_hand")]


def _hold_while_acting(e, models, action, part, seconds=3.0):
    """Hold ``part`` with finger 2, drag ``action``'s stroke with finger 1 from 0.2 s on, from
    where its primary part is drawn then (posing from the held part alone may have moved it:
    from 60,30 the held left hand takes the right hand 0.055 m, 0.3 m tall, from where it stood,
    and a finger at its standing place took the pelvis); the held part's target distances
    (table m) from finger 2 over the action's frames and over the posing frames after it."""
    held = np.array(e.describe()["parts"][part])
    model = next(a for a in models.actions if a.name == action)
    times, traj = model.stroke_t + 0.3, None
    far, after, modes, steps = [], [], set(), []
    prev = None
    for k in range(int(seconds * 30)):
        t = k / 30
        touches = {2: tuple(held)}
        if 0.2 <= t <= times[-1]:
            traj = e.stroke_on_table(model) if traj is None else traj
            s = max(t, times[0])
            touches[1] = (float(np.interp(s, times, traj[:, 0])),
                          float(np.interp(s, times, traj[:, 1])))
        r = e.step(t, touches)
        modes.add(r["action"])
        p = e.camera.table(e.body.parts(e.target))[PARTS.index(part)]
        if prev is not None and (r["action"] == action or far) and len(after) < 8:
            steps.append(float(np.linalg.norm(p - prev)))
        prev = p
        if r["action"] == action:
            assert r["touches"]["2"] == part
            p = e.camera.table(e.body.parts(e.target))[PARTS.index(part)]
            far.append(float(np.linalg.norm(p - held)))
        elif far:
            p = e.camera.table(e.body.parts(e.target))[PARTS.index(part)]
            after.append(float(np.linalg.norm(p - held)))
    return far, after, modes, steps


@pytest.mark.parametrize("action, part", HELD)
def test_a_part_held_while_an_action_travels_stays_under_its_finger(make, models, action, part):
    e = make(view=(90.0, 15.0), physics=False)
    far, after, modes, _ = _hold_while_acting(e, models, action, part, seconds=3.5)
    assert action in modes and len(far) > 10 and len(after) > 10
    assert float(np.median(far)) < HELD_MEDIAN_M, far
    assert float(np.median(after)) < AFTER_MEDIAN_M, after


@pytest.mark.parametrize("action, part", HELD)
@pytest.mark.parametrize("view", [(90.0, 15.0), (60.0, 30.0), (90.0, 40.0)])
def test_a_held_part_moves_on_continuously_when_the_action_ends(make, models, action, part, view):
    e = make(view=view, physics=False)
    far, after, modes, steps = _hold_while_acting(e, models, action, part, seconds=2.5)
    assert action in modes and action not in e.excluded(), (modes, e.excluded())
    assert len(after) >= 8
    assert max(steps[-18:]) < HANDOVER_STEP_M, steps[-18:]
