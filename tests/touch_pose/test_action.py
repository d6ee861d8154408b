"""Action control (section 5) and tracking control at the switches (section 6)."""

import numpy as np
import pytest

from behaviors.touch_pose.action import ActionClock, dp_distance, threshold
from behaviors.touch_pose.tracking import rot_diff
from bench.touch_pose_drags import stroke_drag, there_and_back

from .conftest import actions_begun

#: Largest rotation (degrees) any joint may make in one 30 fps frame when the control switches.
SWITCH_DEG = 20.0


def _modes(records):
    return [(r["mode"], r["action"]) for r in records]


def test_quick_punch_drag_from_the_side_starts_the_punch(make, models):
    e = make(view=(90.0, 15.0), physics=False)
    recs, _, _ = stroke_drag(e, models, "punch", pace=1.0, after=0.5)
    acts = [r for r in recs if r["mode"] == "action"]
    assert acts and {r["action"] for r in acts} == {"punch"}
    # it started while the finger was still dragging (not after)
    stroke_s = next(a for a in models.actions if a.name == "punch").stroke_t[-1]
    assert acts[0]["t"] <= stroke_s + 1e-6


def test_resting_on_the_hand_then_punching_starts_the_punch(make, models):
    e = make(view=(90.0, 15.0), physics=False)
    recs, _, _ = stroke_drag(e, models, "punch", pace=1.0, before=1.0, after=0.5)
    assert all(r["mode"] == "posing" for r in recs if r["t"] < 1.0)
    assert {r["action"] for r in recs if r["mode"] == "action"} == {"punch"}


def test_the_same_drag_done_slowly_only_poses(make, models):
    e = make(view=(90.0, 15.0), physics=False)
    recs, _, _ = stroke_drag(e, models, "punch", pace=4.0, after=0.3)
    assert all(r["mode"] == "posing" for r in recs)
    assert recs[-1]["touches"] == {}


@pytest.mark.parametrize("view", [(90.0, 25.0), (90.0, 40.0)])
def test_a_punch_opening_like_the_shorter_wave_starts_the_punch(make, models, view):
    """From these views the punch's drag fits the wave's whole (foreshortened) stroke 0.1 m
    off, under its threshold, before half the punch has been drawn: the wave started. The
    wave's own drag still starts the wave."""
    for name in ("punch", "wave"):
        e = make(view=view, physics=False)
        desc = next(a for a in e.describe()["actions"] if a["name"] == name)
        assert not desc["excluded"]
        times = next(a for a in models.actions if a.name == name).stroke_t
        assert actions_begun(e, np.array(desc["trajectory"]), times) == {name}


def test_from_the_front_the_punch_is_excluded(make, models):
    front = make(view=(0.0, 15.0), physics=False)
    desc = {a["name"]: a for a in front.describe()["actions"]}
    assert desc["punch"]["excluded"] is True
    recs, _, _ = stroke_drag(front, models, "punch", pace=1.0, after=0.3)
    assert all(r["action"] != "punch" for r in recs)
    side = make(view=(270.0, 15.0), physics=False)
    assert {a["name"]: a for a in side.describe()["actions"]}["punch"]["excluded"] is False


def test_lifting_the_finger_mid_kick_finishes_the_kick(make, models):
    e = make(view=(90.0, 15.0), physics=False)
    recs, _, _ = stroke_drag(e, models, "kick", pace=1.0, frac=0.75, after=2.0)
    kick = next(a for a in models.actions if a.name == "kick")
    times = [r["action_time"] for r in recs if r["action"] == "kick"]
    assert times, "the kick did not start"
    assert max(times) >= 0.98 * kick.duration       # ran on to its end by itself
    assert np.all(np.diff(times) > 0)                # forward only, never paused
    assert recs[-1]["mode"] == "posing"              # and back to posing


def _held_times(recs, t_from, t_to):
    return [r["action_time"] for r in recs if t_from <= r["t"] <= t_to and r["action"]]


def test_holding_still_holds_only_where_the_action_allows_it(make, models):
    # the wave may pause with the hand up: held still, the time stands
    wave = make(view=(90.0, 15.0), physics=False)
    recs, _, _ = stroke_drag(wave, models, "wave", pace=1.0, hold=1.5, after=3.0)
    w = next(a for a in models.actions if a.name == "wave")
    end = w.stroke_t[-1]
    held = _held_times(recs, end + 0.5, end + 1.4)
    assert len(held) > 20 and max(held) - min(held) < 0.05
    # ... and once lifted it waves on to the end
    assert max(r["action_time"] or 0 for r in recs) >= 0.98 * w.duration
    # the kick cannot stop with the foot in the air: held still, the time keeps going
    kick = make(view=(90.0, 15.0), physics=False)
    recs, _, _ = stroke_drag(kick, models, "kick", pace=1.0, hold=1.5, after=0.5)
    k = next(a for a in models.actions if a.name == "kick")
    end = k.stroke_t[-1]
    moving = _held_times(recs, end, end + 0.3)
    assert len(moving) >= 8 and np.all(np.diff(moving) > 0)
    # it stops only where stillness is allowed again
    still = [r["action_time"] / k.duration for r in recs
             if r["action"] == "kick" and r["t"] > end + 0.9 and r["t"] <= end + 1.5]
    assert still and min(still) >= k.spec.segments[-1].start - 1e-6
    assert max(still) - min(still) < 0.02


@pytest.mark.parametrize("name", ["punch", "kick", "wave"])
def test_switching_control_moves_no_joint_more_than_a_set_angle_per_frame(make, models, name):
    e = make(view=(90.0, 15.0), physics=True)
    recs, targets, out = stroke_drag(e, models, name, pace=1.0, after=3.0)
    modes = [r["mode"] for r in recs]
    switches = [i for i in range(1, len(modes)) if modes[i] != modes[i - 1]]
    assert len(switches) == 2  # posing -> action -> posing
    raw_jump = max(np.degrees(np.linalg.norm(rot_diff(targets[i], targets[i - 1]), axis=1)).max()
                   for i in switches)
    assert raw_jump > 45.0  # the switch itself is a jump of the target posture
    for i in switches:
        for k in range(max(1, i - 1), min(len(out), i + 6)):
            step = np.degrees(np.linalg.norm(rot_diff(out[k], out[k - 1]), axis=1)).max()
            assert step < SWITCH_DEG, (i, k, step)


def test_dp_distance_time_term_and_coverage():
    act = np.stack([np.linspace(0, 1, 24), np.zeros(24)], axis=1)
    act_t = np.linspace(0, 0.5, 24)
    same, j = dp_distance(act, act_t, act, act_t)
    assert same < 1e-9 and j == 23
    slow, _ = dp_distance(act, act_t * 4, act, act_t)
    assert slow > 0.3  # only the time term differs
    short, j = dp_distance(act[:8], act_t[:8], act, act_t)
    assert np.isinf(short) or j > 11  # never judged on less than half of the action
    assert threshold(1.0) > threshold(0.25)


@pytest.mark.parametrize("view", [(270.0, 30.0), (60.0, 10.0)])
def test_once_the_time_reaches_the_synthesised_time_the_synthesised_posture_is_output(
        make, models, view):
    # section 5: close to the synthesised time, the posture synthesised for the touches is the
    # output (not the sample motion's posture at that time): the kicking foot follows the finger
    # (median 0.062 and 0.072 m from it on the table, 0.3 m tall, when only the time followed)
    from behaviors.touch_pose.humanoid import PARTS
    e = make(view=view, physics=False)
    kick = next(a for a in models.actions if a.name == "kick")
    traj = np.array(next(a for a in e.describe()["actions"] if a["name"] == "kick")["trajectory"])
    far, prev, turns = [], None, []
    for k in range(int((kick.stroke_t[-1] + 0.5) * 30) + 1):
        t = k / 30
        s = min(t, kick.stroke_t[-1])
        finger = np.array([np.interp(s, kick.stroke_t, traj[:, 0]),
                           np.interp(s, kick.stroke_t, traj[:, 1])])
        r = e.step(t, {1: tuple(finger)})
        if r["mode"] != "action":
            continue
        if t <= kick.stroke_t[-1]:
            foot = e.camera.table(e.body.parts(e.target))[PARTS.index("right_foot")]
            far.append(float(np.linalg.norm(foot - finger)))
        if prev is not None:   # tracking still smooths it
            turns.append(np.degrees(np.linalg.norm(rot_diff(e.output.rots, prev), axis=1)).max())
        prev = e.output.rots.copy()
    assert len(far) >= 4
    assert np.median(far) < 0.04
    assert max(turns) < SWITCH_DEG


@pytest.mark.parametrize("pace", [0.5, 0.75])
def test_a_quick_drag_across_the_bow_does_not_start_it(make, models, pace):
    # the head dragged quickly at right angles to the bow's short stroke (0.35 m) started the
    # bow: the speed-loosened threshold (0.23 m) exceeded what tells the two apart
    bow = next(a for a in models.actions if a.name == "bow")
    for turn in (90.0, -90.0):
        e = make(view=(90.0, 15.0), physics=False)
        drawn = next(a for a in e.describe()["actions"] if a["name"] == "bow")
        traj = np.array(drawn["trajectory"])
        c, s = np.cos(np.radians(turn)), np.sin(np.radians(turn))
        across = traj[0] + (traj - traj[0]) @ np.array([[c, s], [-s, c]])
        assert "bow" not in actions_begun(e, across, bow.stroke_t * pace), turn
    e = make(view=(90.0, 15.0), physics=False)
    assert "bow" in actions_begun(e, traj, bow.stroke_t * pace)    # the stroke itself still does


def test_a_drag_back_through_a_segment_without_stillness_rewinds_it(make, models):
    # the walk's step (from 0.1 on) may not stand still, but the finger may take it back
    e = make(view=(90.0, 15.0), physics=False)
    walk = next(a for a in models.actions if a.name == "walk")
    recs, _, _, turn = there_and_back(e, models, "walk", frac=0.9, back=0.3)
    u = [(r["t"], r["action_time"] / walk.duration) for r in recs if r["action"] == "walk"]
    assert u and u[0][0] < turn, "the walk did not start during the drag forward"
    peak = max(v for t, v in u if t <= turn + 0.1)
    back = [v for t, v in u if t > turn + 0.1]
    assert back and all(walk.segment(v).still is False for v in back[:3])
    assert min(back) < peak - 0.15          # the drag back rewound the step
    assert np.all(np.diff([v for t, v in u if t > turn + 0.2]) < 0)   # and it never stood


def _turns(u: list[float], band: float = 0.02) -> int:
    """How often the series ``u`` turns (changes direction by more than ``band``)."""
    turns, direction, extreme = 0, 0, u[0]
    for v in u[1:]:
        if direction >= 0 and v < extreme - band or direction <= 0 and v > extreme + band:
            turns += direction != 0
            direction = 1 if v > extreme else -1
            extreme = v
        elif direction * (v - extreme) > 0:
            extreme = v
    return turns


@pytest.mark.parametrize("name,frac,back", [("walk", 0.9, 0.5), ("kick", 0.65, 0.5)])
def test_a_drag_back_held_still_mid_action_goes_on_back_and_never_replays(make, models, name,
                                                                          frac, back):
    # held still where stillness is not allowed, the time goes on the way the finger last
    # took it (back) instead of sweeping back past the finger and forward again: one turn only
    e = make(view=(90.0, 15.0), physics=False)
    act = next(a for a in models.actions if a.name == name)
    recs = there_and_back(e, models, name, frac=frac, back=back, hold=1.0, after=1.0).recs
    u = [r["action_time"] / act.duration for r in recs if r["action"] == name]
    assert u and max(u) < 0.99, "the held action was replayed to its end"
    peak = int(np.argmax(u))
    assert _turns(u) <= 1 and all(np.diff(u[peak:]) <= 1e-9), [round(v, 2) for v in u]


@pytest.mark.parametrize("jitter", [0.001, 0.002])
@pytest.mark.parametrize("seed", [0, 1])
def test_a_jittering_finger_held_on_a_kick_in_the_air_never_turns_it(make, models, jitter, seed):
    # touches jitter by a millimetre or two: held still in the air, the kick runs on to where
    # it may stand and stays there, never pulled back into the air by the jitter
    e = make(view=(90.0, 15.0), physics=False)
    kick = next(a for a in models.actions if a.name == "kick")
    recs = there_and_back(e, models, "kick", frac=0.65, back=0.65, hold=1.5, jitter=jitter,
                          seed=seed).recs
    u = [r["action_time"] / kick.duration for r in recs if r["action"] == "kick"]
    assert u and all(np.diff(u) >= 0), [round(v, 2) for v in u]
    assert u[-1] >= kick.spec.segments[-1].start


@pytest.mark.parametrize("name,view,seed", [("punch", (90.0, 15.0), 2), ("bow", (60.0, 10.0), 2)])
def test_a_jittering_finger_resting_where_the_action_may_stand_holds_it(make, models, name, view,
                                                                        seed):
    # held with a millimetre of jitter where the action may stand, the synthesised time flips
    # between neighbouring samples (the punch's 0.810 <-> 0.831) frame after frame; the action
    # time and the posture hold (bench/touch_pose_rest.py, these cases: the time's back-and-forth
    # 0.78 s of the punch's, 0.98 s of the bow's when it follows every flip, under 0.005 s held;
    # the target's most-moving part goes back and forth 0.03-0.15 m with the synthesised
    # posture output at the held time, 0 with the posture held)
    e = make(view=view, physics=False)
    act = next(a for a in models.actions if a.name == name)
    d = there_and_back(e, models, name, frac=1.0, back=1.0, hold=1.5, jitter=0.001, seed=seed)
    stop = act.stroke_t[-1] + 0.5
    k = [i for i, r in enumerate(d.recs) if r["action"] == name and r["t"] >= stop
         and act.segment(r["action_time"] / act.duration).still]
    assert len(k) >= 20
    u = np.array([d.recs[i]["action_time"] for i in k])
    assert np.abs(np.diff(u)).sum() - abs(u[-1] - u[0]) < 0.03, np.round(u, 3).tolist()
    parts = np.array([d.targets[i] for i in k])
    path = np.linalg.norm(np.diff(parts, axis=0), axis=2).sum(axis=0)
    assert (path - np.linalg.norm(parts[-1] - parts[0], axis=1)).max() < 0.002


@pytest.mark.parametrize("view", [(60.0, 10.0), (90.0, 15.0)])
def test_a_resting_finger_that_drags_again_is_followed_at_once(make, models, view):
    # rested a second at the bow's end (the hold engaged), the finger drags the head back to 0.3
    # of the stroke: the hold lets go as it moves (the head's gap from it over the drag back,
    # table m: 0.013-0.014 mean, 0.022 largest; a hold that never lets go: 0.021-0.024, 0.05)
    e = make(view=view, physics=False)
    bow = next(a for a in models.actions if a.name == "bow")
    d = there_and_back(e, models, "bow", frac=1.0, back=0.3, pause=1.0, jitter=0.001)
    gaps = [float(np.linalg.norm(np.array(r["parts"]["head"]) - xy))
            for r, xy in zip(d.recs, d.fingers)
            if r["action"] == "bow" and xy is not None and r["t"] > d.turn]
    assert len(gaps) >= 10 and bow.spec.part == "head"
    assert np.mean(gaps) < 0.016 and max(gaps) < 0.03, (np.mean(gaps), max(gaps))


@pytest.mark.parametrize("view", [(60.0, 10.0), (90.0, 15.0)])
def test_a_finger_dragging_back_slowly_is_not_held(make, models, view):
    # dragged back along the bow five times slower than its stroke, the synthesised time moves
    # less than the resting band, but the finger itself moves: the head follows it (gap mean
    # 0.006 m, largest 0.008; held by the time's band alone: 0.018, 0.036)
    e = make(view=view, physics=False)
    d = there_and_back(e, models, "bow", frac=1.0, back=0.3, slower=5.0, hold=0.5)
    gaps = [float(np.linalg.norm(np.array(r["parts"]["head"]) - xy))
            for r, xy in zip(d.recs, d.fingers)
            if r["action"] == "bow" and xy is not None and r["t"] > d.turn]
    assert len(gaps) >= 60
    assert np.mean(gaps) < 0.01 and max(gaps) < 0.02, (np.mean(gaps), max(gaps))


def test_the_action_clock_takes_a_frame_of_no_time(models):
    # a repeated frame time (dt = 0) while a finger rests leaves the time where it is
    clock = ActionClock(next(a for a in models.actions if a.name == "punch"), 0.9)
    for _ in range(3):
        assert clock.step(1 / 30, 0.9, True) == pytest.approx(0.9, abs=0.06)
    u = clock.u
    assert clock.step(0.0, 0.91, True) == pytest.approx(u)
