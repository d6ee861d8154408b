"""Touch ids across TUIO senders and sources: fingers numbered alike by two senders or two
sources stay two fingers, each keeping its id; a blob outlining its sender's cursor or object
is no touch."""

import time

from tabletop.loop import LiveInputs
from tabletop.plugins.tracking import Tracker
from tracking.osc_input import OscInput
from tracking.pucks import TrackerSettings

from tests.network.helpers import RefSender
from tests.network.test_tuio_source import TABLE, sent, source  # noqa: F401 (fixture)


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
