"""What visitors do at the table: touch a part after an action, rest a finger, two at once."""

import numpy as np
import pytest

from bench.touch_pose_drags import stroke_drag


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


def test_a_finger_resting_on_empty_table_beside_a_moving_one_turns_nothing(make):
    # two visitors, each with one finger on empty table: one rests, the other drags 0.2 m
    e = make(view=(90.0, 15.0), physics=False)
    for k in range(31):
        e.step(k / 30, {1: (0.1, 0.7), 2: (1.1, 0.1 + 0.2 * k / 30)})
    assert e.fingers[1].part is None and e.fingers[2].part is None
    assert (e.camera.azimuth, e.camera.elevation) == (90.0, 15.0)
    # ... and two fingers dragged apart (a pinch) turn nothing either
    f = make(view=(90.0, 15.0), physics=False)
    for k in range(31):
        f.step(k / 30, {1: (0.3 - 0.1 * k / 30, 0.7), 2: (0.5 + 0.1 * k / 30, 0.7)})
    assert (f.camera.azimuth, f.camera.elevation) == (90.0, 15.0)
    # two fingers dragged together still turn it, by their motion
    g = make(view=(90.0, 15.0), physics=False)
    for k in range(31):
        g.step(k / 30, {1: (0.1, 0.1 + 0.05 * k / 30), 2: (0.2, 0.1 + 0.05 * k / 30)})
    assert g.camera.elevation == pytest.approx(15.0 - 0.05 * 300.0)


def test_a_finger_on_overlapping_parts_takes_the_one_in_front(make):
    # from the character's right side the feet are drawn 0.015 m apart: a finger between them,
    # a little nearer the hidden left foot, takes the right foot, which it sees in front
    e = make(view=(90.0, 15.0), physics=False)
    p = {k: np.array(v) for k, v in e.describe()["parts"].items()}
    assert np.linalg.norm(p["left_foot"] - p["right_foot"]) < 0.02
    between = 0.45 * p["right_foot"] + 0.55 * p["left_foot"]
    assert e.step(0.0, {1: tuple(between)})["touches"] == {"1": "right_foot"}
    # from the left side, the left foot is in front
    f = make(view=(270.0, 15.0), physics=False)
    q = {k: np.array(v) for k, v in f.describe()["parts"].items()}
    between = 0.55 * q["right_foot"] + 0.45 * q["left_foot"]
    assert f.step(0.0, {1: tuple(between)})["touches"] == {"1": "left_foot"}
    # a finger right on a part apart from the others still takes it
    g = make(view=(90.0, 15.0), physics=False)
    assert g.step(0.0, {2: tuple(p["left_hand"])})["touches"] == {"2": "left_hand"}


def test_punches_in_a_row_keep_the_character_on_the_table(make, models):
    # 0.4 m tall on a 1.2 x 0.8 m table (examples/touch_pose.yaml): each punch steps 1.9 m
    # (character metres) from where the last left it; three took the hand to x = 1.26 m
    e = make(view=(90.0, 15.0), physics=True, height=0.4)
    xs, t0, punches = [], 0.0, 0
    for _ in range(3):
        step = e.step
        e.step = lambda t, touches, record=True, _s=step, _t0=t0: _s(t + _t0, touches, record)
        recs, _, _ = stroke_drag(e, models, "punch", pace=1.0, after=3.0)
        e.step = step
        t0 = recs[-1]["t"] + 1 / 30
        punches += "punch" in {r["action"] for r in recs}
        xs += [x for r in recs for x, _ in r["parts"].values()]
    assert punches == 3
    assert max(xs) > 1.15            # it did reach the edge ...
    assert 0.0 <= min(xs) and max(xs) <= 1.2   # ... and stayed on
