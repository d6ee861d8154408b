"""Review sheets are drawn in one thread for the whole process: matplotlib keeps each font open
once per thread that draws, so a thread per sheet (and per studio build) leaves two more font
files open, and their fonts in memory, at each applied config edit of a kiosk. Closing a studio
build waits for its own sheet only; the thread ends with the run."""

import os
import threading
import time

import numpy as np

from tabletop.studio.take import Try
from tabletop.studio.session import SessionLog


class PoseTake:
    """A target's recorded take as the session log reads it: a touch-pose action's part path."""

    what = "pose action"

    def __init__(self) -> None:
        t = np.linspace(0.0, 1.0, 30)
        self.demo = np.c_[t, 0.1 * t, 0.2 + 0.1 * t, np.zeros_like(t)]


def drawers() -> list[threading.Thread]:
    """The drawing threads alive."""
    return [t for t in threading.enumerate() if t.name == "review" and t.is_alive()]


def fonts_open() -> int:
    """Files of matplotlib's fonts this process holds open."""
    n = 0
    for fd in os.listdir("/proc/self/fd"):
        try:
            n += "mpl-data/fonts" in os.readlink(f"/proc/self/fd/{fd}")
        except OSError:
            pass
    return n


def test_review_sheets_keep_each_font_open_once(tmp_path):
    stop = threading.Event()
    held = []   # threads that live on, as an installation's do: every new thread is a new one
    counts = []
    try:
        for k in range(4):
            held.append(threading.Thread(target=stop.wait, daemon=True))
            held[-1].start()
            log = SessionLog(tmp_path / f"studio{k}", review=True)   # a studio build
            log.wait()
            log.log_try(Try("poser", "pose action", time.time(), outcome="kept"), PoseTake())
            log.wait()
            assert (log.folder / f"{log.path.stem}-try001.png").stat().st_size > 1000
            log.close()                       # the studio stage closes with its loop
            counts.append((fonts_open(), len(drawers())))
    finally:
        stop.set()
    assert counts[0][0] > 0 and counts == [(counts[0][0], 1)] * 4, counts


def test_a_slow_sheet_at_the_drawers_end_never_leaves_two_drawers():
    """The drawer's end given up on (a sheet slower than the wait) and a sheet asked for
    meanwhile: the old drawer ends after its slow sheet, the new one draws the rest, and never
    two draw at once."""
    from tabletop.studio.session import draw_later, end_drawing

    release = threading.Event()
    slow = draw_later(lambda: release.wait(30))
    old = drawers()
    assert len(old) == 1
    assert not end_drawing(timeout=0.05)             # still drawing the slow sheet
    second = draw_later(lambda: None)                  # a new drawer
    release.set()
    assert slow.wait(30) and second.wait(30)
    third = draw_later(lambda: None)
    assert third.wait(30)
    old[0].join(30)
    assert len(drawers()) == 1, drawers()
    assert end_drawing() and drawers() == []


def test_a_sheet_that_fails_does_not_stop_the_drawing_thread(caplog):
    """A drawing job raising is logged; the jobs after it still run (the thread ended with the
    first failure and every later sheet waited for ever)."""
    from tabletop.studio.session import draw_later

    def fails() -> None:
        raise ValueError("no such sheet")

    ran: list[int] = []
    first = draw_later(fails)
    second = draw_later(lambda: ran.append(1))
    assert first.wait(30) and second.wait(30) and ran == [1]
    assert "a review sheet was not drawn" in caplog.text
