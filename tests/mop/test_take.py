"""A designer's take (``behaviors.mop.take``): read against the origin its gesture had when it
began, for every spatial input."""

from pathlib import Path

import numpy as np

from tabletop.frames import Frame, Touch
from tests.mop.test_plugin import G, RATE, Table, _build, _designer_config


def test_a_touch_take_reads_from_where_the_finger_first_touched_down(tmp_path: Path):
    """A take of a finger begun before it touches is read from its first touch (the touch's
    origin before it is unknown, NaN); lifted part way and put down elsewhere, the take goes on
    from the first touch's origin, as a puck's does through a rest."""
    data = _designer_config(tmp_path)
    data["engines"][0]["performers"][0]["inputs"] = [{"kind": "touch"}]
    engine = _build(data, tmp_path)
    table = Table(engine)
    table.rest(0.5)
    engine.begin_take("lizard", Frame(table.seq, table.t))
    table.rest(0.3)
    line = G.gesture("line")
    half = line[-1, 0] / 2
    for tau in np.arange(0.0, line[-1, 0], 1.0 / RATE):   # lifted for 0.1 s half way
        dx, dy = np.interp(tau, line[:, 0], line[:, 1]), np.interp(tau, line[:, 0], line[:, 2])
        down = not half <= tau < half + 0.1
        table.touches = (Touch(1 + (tau > half), 0.4 + dx, 0.3 + dy),) if down else ()
        table.tick()
    rows = engine.take.samples()
    assert np.abs(rows[0]).max() < 1e-9
    assert np.hypot(*(rows[-1] - line[-1, 1:3])) < 0.005, (rows[-1], line[-1])
    assert np.allclose(np.ptp(rows, axis=0), np.ptp(line[:, 1:3], axis=0), atol=0.005)
    assert np.hypot(*np.diff(rows, axis=0).T).max() < 0.02
