"""Touch ids across TUIO senders and sources: fingers numbered alike by two senders or two
sources stay two fingers, each keeping its id; a blob outlining its sender's cursor or object
is no touch."""

import random
import time

from tabletop.live_inputs import LiveInputs
from tabletop.plugins.tracking import Tracker
from tracking.osc_input import OscInput
from tracking.pucks import TrackerSettings
from tracking.touch_ids import TouchIds

from tests.network.helpers import TABLE, RefSender, sent


def touch_xy(src) -> dict[int, tuple[float, float]]:
    return {c.id: (round(c.x, 3), round(c.y, 3)) for c in src.latest().touches}


def test_touches_of_senders_counting_alike_stay_apart_and_keep_their_ids(source):
    """Two trackers each number their fingers from 0: two fingers, each keeping its id while it
    stays (they were two touches of one id, one finger to every engine and to the tuio sink)."""
    a = RefSender(source.bound_port, source="tableA@10.0.0.1")
    b = RefSender(source.bound_port, source="tableB@10.0.0.2")
    a.cursors([(0, 0.25, 0.5)])
    assert sent(source, 1)
    b.cursors([(0, 0.75, 0.5)])
    assert sent(source, 2)
    assert touch_xy(source) == {0: (0.3, 0.4), 1: (0.9, 0.4)}
    a.cursors([])                                    # A's finger lifts: B's keeps its id
    b.cursors([(0, 0.5, 0.25)])
    assert sent(source, 4)
    assert touch_xy(source) == {1: (0.6, 0.6)}
    a.cursors([(0, 0.25, 0.5), (1, 0.25, 0.75)])     # A's session 1 is taken by B's finger
    assert sent(source, 5)
    assert touch_xy(source) == {0: (0.3, 0.4), 1: (0.6, 0.6), 2: (0.3, 0.2)}


def test_a_blob_outlining_a_cursor_or_an_object_of_its_sender_is_no_touch(source):
    """A sender's blob with the session id of its cursor or object is that entity's outline
    (one counter numbers a TUIO sender's profiles): one finger, and a puck is no finger."""
    ref = RefSender(source.bound_port, source="tracker@10.0.0.5")
    ref.objects([(4, 5, 0.5, 0.5, 0.0)])
    ref.cursors([(3, 0.25, 0.25)])
    blob = [(s, x, 0.25, 0.0, 0.05, 0.05, 0.01, 0.0, 0.0, 0.0, 0.0, 0.0)
            for s, x in ((3, 0.25), (4, 0.5), (6, 0.75))]
    ref.send(ref.profile_bundle("2Dblb", [3, 4, 6], blob, 1))
    assert sent(source, 3)
    assert touch_xy(source) == {3: (0.3, 0.6), 6: (0.9, 0.6)}   # the cursor, the lone blob


def test_touches_of_two_sources_with_one_id_are_two_fingers_in_the_frame():
    """Two osc sources (two ports, a tracker each), both sending finger 7."""
    one, two = (OscInput(n, port=0, table=TABLE) for n in ("one", "two"))
    inputs = LiveInputs([one, two], Tracker(TrackerSettings(smooth=False)))
    inputs.open()
    try:
        assert one.wait_listening() and two.wait_listening()
        RefSender(one.bound_port).cursors([(7, 0.25, 0.5)])
        RefSender(two.bound_port).cursors([(7, 0.75, 0.5)])
        assert sent(one, 1) and sent(two, 1)
        for seq in range(3):   # stable from frame to frame
            f = inputs.next(seq, time.monotonic())
            assert {c.id: round(c.x, 3) for c in f.touches} == {7: 0.3, 0: 0.9}
    finally:
        inputs.close()


def test_a_lifted_fingers_id_goes_to_no_other_finger_in_the_next_frame(source):
    """Sender B's finger holds the spare id 1 and lifts as sender A's second finger (session 1)
    lands: A's finger takes another id, so id 1 does not jump across the table (touch-pose
    would drag B's held part to A's finger in one tick)."""
    a = RefSender(source.bound_port, source="tableA@10.0.0.1")
    b = RefSender(source.bound_port, source="tableB@10.0.0.2")
    a.cursors([(0, 0.25, 0.5)])
    b.cursors([(0, 0.75, 0.5)])
    assert sent(source, 2)
    assert touch_xy(source) == {0: (0.3, 0.4), 1: (0.9, 0.4)}
    b.cursors([])
    a.cursors([(0, 0.25, 0.5), (1, 0.5, 0.25)])
    assert sent(source, 4)
    now = touch_xy(source)
    assert 1 not in now and sorted(now.values()) == [(0.3, 0.4), (0.6, 0.6)]
    assert now[0] == (0.3, 0.4)


def test_a_single_origin_keeps_the_ids_it_brings():
    """One origin with unique ids, fingers landing and lifting at random (ids reused at once
    too): every bus id is the id brought, in 2,000 random runs of 60 frames."""
    rng = random.Random(1)
    for _ in range(2000):
        ids, present, nxt = TouchIds(), set(), rng.randint(0, 3)
        for _f in range(60):
            present -= {s for s in present if rng.random() < 0.2}
            while rng.random() < 0.3:
                present.add(nxt if rng.random() < 0.8 else rng.randint(0, 50))
                nxt += 1
            own = sorted(present)
            assert ids.assign([("A", k) for k in own]) == own
