"""What visitors do at the table: touch a part after an action, rest a finger, two at once."""

import numpy as np

from .conftest import stroke_drag


def test_a_part_touched_after_an_action_stays_under_the_finger(make, models):
    # the punch steps 1.9 m (character metres), beyond how far the character may roam: it is
    # brought back as the action ends, not later under the finger of the next visitor (the
    # pelvis slid 0.13 m on the table, the held foot 0.06 m away from the still finger)
    e = make(view=(90.0, 15.0), physics=False)
    recs, _, _ = stroke_drag(e, models, "punch", pace=1.0, after=3.0)
    assert "punch" in {r["action"] for r in recs} and recs[-1]["mode"] == "posing"
    t = recs[-1]["t"]
    before = e.frame(t)["parts"]
    for part in ("right_foot", "left_hand"):
        where = np.array(e.frame(t)["parts"][part])
        moved = []
        for k in range(1, 31):   # a finger resting on the part for a second
            r = e.step(t + k / 30, {7: tuple(where)})
            assert r["touches"] == {"7": part}
            moved.append(np.linalg.norm(np.array(r["parts"][part]) - where))
        t += 1.0
        for k in range(1, 16):
            e.step(t + k / 30, {})
        t += 0.5
        assert max(moved) < 0.01, (part, max(moved))
    pelvis = np.linalg.norm(np.array(e.frame(t)["parts"]["pelvis"]) - before["pelvis"])
    assert pelvis < 0.01
