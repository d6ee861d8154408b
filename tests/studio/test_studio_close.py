"""Closing the studio's stage ends every target's worker, even when dropping the take under
way fails (a disk gone), and its waits share one deadline (behaviors.worker.close_workers)."""

import threading
import time

import pytest

from behaviors.worker import Worker, close_workers
from tabletop.studio.build import Markers, StudioStage
from tests.studio.test_studio_keys import Bench, designer


def test_the_targets_workers_end_when_the_studio_fails_to_close(tmp_path):
    (e,) = designer(tmp_path, background_training=True)
    bench = Bench([e], tmp_path)
    target = bench.studio.targets["pet"]
    threads = [target.trainer._thread, target.loader._thread]
    assert all(t.is_alive() for t in threads)

    def fails() -> None:
        raise OSError(28, "No space left on device")

    bench.studio.close = fails
    with pytest.raises(OSError, match="No space left"):   # logged by the loop; the rest closed
        StudioStage(Markers({}, bench.studio), bench.studio).close()
    assert not any(t.is_alive() for t in threads)


def test_workers_closed_past_their_deadline_say_so_and_end_after_their_jobs():
    release = threading.Event()
    busy, idle = Worker("busy"), Worker("idle")
    busy.start(release.wait, 30.0)
    assert not close_workers(busy, None, idle, deadline=time.monotonic())
    release.set()
    busy.wait(30.0)
    assert close_workers(busy, idle)     # ended after their jobs; closing again ends at once
