"""A ``serial`` source on a real pseudo-terminal, for the serial tests."""

import os
from contextlib import contextmanager

from tabletop.loop import LiveInputs
from tabletop.plugins.tracking import Tracker
from tracking.pucks import TrackerSettings
from tracking.serial_input import SerialInput

from tests.network.helpers import wait_for


def open_pty():
    master, slave = os.openpty()
    return master, slave, os.ttyname(slave)


@contextmanager
def a_pty():
    """A fresh pseudo-terminal, both ends closed after: yields (master, slave, its name)."""
    master, slave, name = open_pty()
    try:
        yield master, slave, name
    finally:
        os.close(master)
        os.close(slave)


@contextmanager
def tracked_pty(timeout_s: float, settings: TrackerSettings | None = None):
    """A serial source on a fresh pseudo-terminal, open and healthy, with the tracker's inputs
    (``settings``, unsmoothed by default): yields (the terminal's master end, the source, the
    inputs)."""
    with a_pty() as (master, _, name):
        src = SerialInput("mcu", name, timeout_s=timeout_s)
        inputs = LiveInputs([src], Tracker(settings or TrackerSettings(smooth=False)))
        src.open()
        try:
            assert wait_for(lambda: src.health().ok, 5.0)
            yield master, src, inputs
        finally:
            src.close()
