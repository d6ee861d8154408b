"""A take the follower cannot tell from an action the character knows is named so on the status
line when it is tried (a circle recorded again beside the face's circle), and one it can is not
(a line beside it)."""

from tabletop.studio.machine import Studio
from tabletop.studio.mop_target import MopTarget
from tests.studio.mop_table import face_take

TOO_LIKE = ("take1 is too like circle: MOP cannot tell them apart (K keeps it anyway); "
            "try it: K keep, X discard, R redo")


def test_a_circle_recorded_again_is_named_too_like_circle(tmp_path):
    engine, table = face_take(tmp_path, "circle")
    assert table.studio.state == "trying"
    assert TOO_LIKE in table.status, table.status
    # it is what the designer sees when trying it: the take does not drive
    run = table.perform("circle")
    assert not any(ch["face"].valid and ch["face"].action == "take1" for _, ch in run)
    table.tick(["designer.keep"])                 # K keeps it anyway
    assert "kept as take1" in table.status, table.status


def test_a_line_recorded_beside_circle_is_not(tmp_path):
    engine, table = face_take(tmp_path, "line")
    assert table.studio.state == "trying"
    assert "take1 -> laugh; try it" in table.status and "too like" not in table.status, table.status


def test_with_the_followers_built_in_a_worker_the_take_is_named_once_trained(tmp_path):
    # the installation builds the followers, and replays the take, off the hot path
    engine, table = face_take(tmp_path, "line")
    table.tick(["designer.discard"])
    table.targets = [MopTarget(engine, c, tmp_path / "lib", background=True)
                     for c in engine.order]
    table.studio = Studio(table.targets, countdown_s=0.0)
    table.tick(["designer.record"])
    table.perform("circle")
    table.tick(["designer.record"])
    states = [table.studio.state]
    for _ in range(120):
        table.tick()
        states.append(table.studio.state)
        if table.studio.state == "trying":
            break
    assert states[0] == "training" and states[-1] == "trying", states
    assert "take2 is too like circle: MOP cannot tell them apart" in table.status, table.status
    assert all(t.close() for t in table.targets)


def test_with_the_followers_built_within_the_tick_the_replay_is_off_it(tmp_path):
    """Without a training worker the stop's tick builds the followers (the take is followed from
    it) but leaves the take's replay (30-65 ms) to the target's own worker: the take is tried,
    named too like circle, from the next tick."""
    engine, table = face_take(tmp_path, "line")
    table.tick(["designer.discard"])
    table.tick(["designer.record"])
    table.perform("circle")
    table.tick(["designer.record"])
    assert "take2" in engine.puppets["face"].actions       # followed from the stop's tick
    assert table.studio.state == "training", table.status
    table.tick()
    assert table.studio.state == "trying"
    assert "take2 is too like circle: MOP cannot tell them apart" in table.status, table.status
    assert all(t.close() for t in table.targets)
