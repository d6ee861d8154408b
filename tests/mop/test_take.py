"""A designer's take (``behaviors.mop.take``): read against the origin its gesture had when it
began, for every spatial input; recorded with a raw camera's tracking jitter, the stills before
and after its gesture are trimmed alike at both ends."""

from pathlib import Path

import numpy as np
import pytest

from behaviors.mop.take import moving_part
from behaviors.mop.takes import TRIM_MARGIN_S
from tabletop.frames import Frame, Puck, Touch
from tabletop.plugins.mop_table import G, RATE, Table, build, designer_config


def _take(engine, name: str, before: float, after: float, jitter: float, seed: int):
    """Record puck 1 still for ``before`` s, drawing ``name``, still for ``after`` s, tracked with
    ``jitter`` metres of noise: (the take's rows, the rows where the gesture starts and ends)."""
    table, rng = Table(engine), np.random.default_rng(seed)
    x0, y0 = table.pucks[1] = (0.5, 0.4)

    def still(seconds: float, x: float, y: float) -> None:
        for _ in range(int(round(seconds * RATE))):
            table.pucks[1] = (x + rng.normal(0, jitter), y + rng.normal(0, jitter))
            table.tick()
    still(1.0, x0, y0)
    engine.begin_take("lizard", Frame(table.seq, table.t, pucks=(Puck(1, x0, y0, 0.0),)))
    still(before, x0, y0)
    g = G.gesture(name)
    ticks = 0
    for tau in np.arange(0.0, g[-1, 0], 1.0 / RATE):
        table.pucks[1] = (x0 + np.interp(tau, g[:, 0], g[:, 1]) + rng.normal(0, jitter),
                          y0 + np.interp(tau, g[:, 0], g[:, 2]) + rng.normal(0, jitter))
        table.tick()
        ticks += 1
    still(after, x0 + g[-1, 1], y0 + g[-1, 2])
    rows = engine.take.samples()
    end = len(rows) - int(round(after * engine.rate_hz))
    return rows, end - int(round(ticks * engine.rate_hz / RATE)), end


@pytest.mark.parametrize("name, before, after, seed", [
    ("zigzag", 0.2, 0.8, 1), ("figure_eight", 0.1, 1.5, 2), ("figure_eight", 0.4, 0.4, 2),
    ("circle", 1.5, 1.0, 1), ("square", 1.0, 0.2, 2), ("wave", 0.4, 0.4, 1)])
def test_a_take_tracked_with_a_raw_cameras_jitter_is_trimmed_alike_at_both_ends(
        tmp_path: Path, name, before, after, seed):
    """0.8 mm of jitter: one jittered row read as a move, and the first (last) row as the
    stillness, left up to 47 still rows at either end (all of a 1.5 s still; medians 5 at the
    start, 18 at the end). Measured with moves of four rows in a row from the end rows'
    median: at most 2 rows off where the gesture starts and ends, as without jitter."""
    engine = build(designer_config(tmp_path), tmp_path)
    performer = engine.performers["hand"]
    rows, start, end = _take(engine, name, before, after, 0.0008, seed * 7 + int(before * 10))
    margin = round(TRIM_MARGIN_S * engine.rate_hz)
    first, last = moving_part(rows, performer.units, performer.jitter, margin)
    assert start - margin - 4 <= first <= start + 3, (first, start)
    assert end - 3 <= last <= end + margin + 4, (last, end)


def test_a_touch_take_reads_from_where_the_finger_first_touched_down(tmp_path: Path):
    """A take of a finger begun before it touches is read from its first touch (the touch's
    origin before it is unknown, NaN); lifted part way and put down elsewhere, the take goes on
    from the first touch's origin, as a puck's does through a rest."""
    data = designer_config(tmp_path)
    data["engines"][0]["performers"][0]["inputs"] = [{"kind": "touch"}]
    engine = build(data, tmp_path)
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
