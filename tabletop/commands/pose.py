"""``tabletop pose``: touch-pose control (paper 003) of one humanoid from recorded touches, offline.

TOUCHES.csv ``t,id,x,y`` (seconds, finger id, table metres): rows sharing ``t`` are one input
frame; a finger missing from a later frame has lifted, and after the last frame every finger
has. One JSON line per output step at ``--rate`` from the first input time to the last plus 2 s;
each step sees only the newest input frame at or before it (causal, as live). ``--describe`` writes
the standing pose and the actions' projected trajectories instead (see DESIGN.md).
"""

from __future__ import annotations

import argparse
import json
import math
from typing import TYPE_CHECKING

from tabletop.commands import (number_in_range, number_pair, output_file, sparse_hint,
                               thousandths_hint, warn_sparse_times)
from tabletop.errors import InputError

if TYPE_CHECKING:
    import numpy as np

    from behaviors.touch_pose.engine import TouchPose

HELP = ("drive a touch-posed humanoid (posing, actions, tracking) from recorded touches, or "
        "describe its parts and actions for a view")

TOUCH_COLUMNS = ("t", "id", "x", "y")
RUN_ON_S = 2.0
MAX_RATE_HZ = 1000.0     # output steps per second (the paper's control runs at about 30)
MAX_STEPS = 1_000_000    # output steps (9 h of touches at 30 Hz; a line is about 1 kB)
TABLE_M = (0.05, 20.0)   # metres: a table side, as config.yaml's table section and behave
HEIGHT_M = (0.01, 20.0)  # metres: the character's drawn height


class PoseArgumentError(InputError):
    """A bad ``tabletop pose`` argument or input."""


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--input", metavar="TOUCHES.csv", help="touches: t,id,x,y (s, id, table m)")
    p.add_argument("--out", metavar="FILE", help="POSES.jsonl (or the --describe JSON; "
                                                 "default stdout for --describe)")
    p.add_argument("--describe", action="store_true",
                   help="write the standing pose's parts and the actions' trajectories instead")
    p.add_argument("--view", default="0,15", metavar="AZ,EL",
                   help="camera azimuth (0 front, 90 the character's right) and elevation, "
                        "degrees (default 0,15)")
    p.add_argument("--rate", default="30", metavar="HZ",
                   help="output steps per second (default 30)")
    p.add_argument("--table", default="1.2,0.8", metavar="W,H",
                   help="table metres (default 1.2,0.8)")
    p.add_argument("--height", default="0.3", metavar="H",
                   help="drawn height of the character on the table, metres (default 0.3)")


def parse_pair(text: str, option: str, what: str) -> tuple[float, float]:
    """``A,B`` as two finite numbers, else one clear error naming the option."""
    a, b = number_pair(text, option, what, PoseArgumentError)
    if not (math.isfinite(a) and math.isfinite(b)):
        raise PoseArgumentError(f"{option} {text!r} must be {what} (finite numbers)")
    return a, b


def parse_view(text: str) -> tuple[float, float]:
    """``AZ,EL`` degrees; elevation within -89..89."""
    from behaviors.touch_pose.humanoid import VIEW_ELEVATION_DEG
    az, el = parse_pair(text, "--view", "AZ,EL in degrees, e.g. 90,15")
    lo, hi = VIEW_ELEVATION_DEG
    if not lo <= el <= hi:
        raise PoseArgumentError(f"--view {text!r}: elevation must be within {lo:g}..{hi:g} degrees")
    return az, el


#: The largest finger id: the CSV's numbers are read as floats, which hold every whole number
#: up to 2**53-1 exactly; a larger id is refused, as two such fingers could read as one.
MAX_ID = 2**53 - 1


def read_touches(path: str) -> list[tuple[float, dict[int, tuple[float, float]]]]:
    """Input frames [(t, {id: (x, y)})] from TOUCHES.csv; one clear error for bad rows."""
    import numpy as np

    from tabletop.files import check_positions, read_csv_lines
    header, data, lines = read_csv_lines(path, TOUCH_COLUMNS, what="touches CSV", min_rows=1)
    # a finger beyond frames.MAX_POSITION_M (1e200 m made every later joint NaN) is refused
    check_positions(data, header, ("x", "y"), path, lines)
    col = {c: header.index(c) for c in TOUCH_COLUMNS}
    t, ids = data[:, col["t"]], data[:, col["id"]]
    back = np.flatnonzero(np.diff(t) < 0)
    if back.size:   # (file lines, as every other CSV error says; "data row" counted otherwise)
        i = int(back[0]) + 1
        raise PoseArgumentError(f"{path}: line {lines[i]}: time {t[i]:g} s goes back from "
                                f"{t[i - 1]:g} s (line {lines[i - 1]}; times must not decrease)")
    bad = np.flatnonzero((ids != np.round(ids)) | (ids < 0) | (ids > MAX_ID))
    if bad.size:
        raise PoseArgumentError(f"{path}: line {lines[bad[0]]}: id {ids[bad[0]]:g} must be "
                                f"a whole number from 0 to {MAX_ID}")
    frames: list[tuple[float, dict[int, tuple[float, float]]]] = []
    for row, line in zip(data, lines):
        tt, fid = float(row[col["t"]]), int(row[col["id"]])
        if not frames or frames[-1][0] != tt:
            frames.append((tt, {}))
        if fid in frames[-1][1]:   # one finger in two places at once (not the last row, silently)
            raise PoseArgumentError(f"{path}: line {line}: finger {fid} is given twice at "
                                    f"t = {tt:g} s (one row per finger and time)")
        frames[-1][1][fid] = (float(row[col["x"]]), float(row[col["y"]]))
    return frames


def warn_units(frames: list[tuple[float, dict[int, tuple[float, float]]]],
               table: tuple[float, float], path: str) -> None:
    """One stderr line when the touches lie off the table (millimetres or pixels given for
    metres: no finger lands on the character, which only stands, without a word) and one when
    the input frames are over a second apart (median: milliseconds given for seconds, which
    made a 20 s recording 600,000 steps of physics)."""
    import sys
    w, h = table
    points = [p for _t, fingers in frames for p in fingers.values()]
    off = [p for p in points if not (0.0 <= p[0] <= w and 0.0 <= p[1] <= h)]
    said = "tabletop pose: warning:"
    if off:
        x, y = off[0]
        print(f"{said} {path}: {len(off)} of {len(points)} touches lie off the {w:g} x {h:g} m "
              f"table (the first at {x:g}, {y:g}); x, y are table metres (millimetres or pixels "
              "given?)", file=sys.stderr)
    warn_sparse_times([t for t, _f in frames], "pose", path, "the input frames")


def run(frames: list[tuple[float, dict[int, tuple[float, float]]]], engine: TouchPose,
        rate: float) -> list[dict]:
    """Output records at ``rate`` from the first input time to the last + 2 s (causal)."""
    t0, t_end = frames[0][0], frames[-1][0] + RUN_ON_S
    n = int(math.floor((t_end - t0) * rate + 1e-9)) + 1
    out, k, current = [], 0, {}
    for i in range(n):
        t = t0 + i / rate
        while k < len(frames) and frames[k][0] <= t + 1e-9:
            current = frames[k][1]
            k += 1
        if t > frames[-1][0] + 1e-9:
            current = {}  # the recording has ended: every finger is lifted
        out.append(engine.step(t, current))
    return out


def main(args: argparse.Namespace) -> int:
    az, el = parse_view(args.view)
    rate = number_in_range(args.rate, "--rate", "Hz", 1.0, MAX_RATE_HZ, PoseArgumentError)
    w, h = parse_pair(args.table, "--table", "W,H in metres, e.g. 1.2,0.8")
    lo, hi = TABLE_M
    if not (lo <= w <= hi and lo <= h <= hi):
        raise PoseArgumentError(f"--table {args.table!r}: width and height must be metres from "
                                f"{lo:g} to {hi:g}" + thousandths_hint("metres", lo, hi, w, h))
    height = number_in_range(args.height, "--height", "metres", *HEIGHT_M, PoseArgumentError)
    if not args.describe and (not args.input or not args.out):
        raise PoseArgumentError("give --input TOUCHES.csv and --out POSES.jsonl (or --describe)")
    if args.describe and args.input:   # it was ignored: the user expected poses of it
        raise PoseArgumentError(f"--describe describes the standing character and its actions; "
                                f"it reads no --input ({args.input}): give one or the other")
    if args.out:
        output_file(args.out, "--out", PoseArgumentError, inputs=(args.input,),
                    example="describe.json" if args.describe else "poses.jsonl")
    frames = None if args.describe else read_touches(args.input)
    if frames is not None:
        span = frames[-1][0] - frames[0][0] + RUN_ON_S
        if span * rate > MAX_STEPS:
            why = sparse_hint([t for t, _f in frames], "; its frames")
            raise PoseArgumentError(f"{args.input}: the touches span {span - RUN_ON_S:g} s, "
                                    f"{span * rate:.3g} steps at {rate:g} Hz; at most "
                                    f"{MAX_STEPS:,} steps are made{why}")
        warn_units(frames, (w, h), args.input)    # (after a refusal: its one line alone)
    from behaviors.touch_pose.engine import TouchPose
    from tabletop.files import atomic_write_text
    engine = TouchPose((w, h), height, az, el, physics=not args.describe)
    try:
        if args.describe:
            text = json.dumps(engine.describe()) + "\n"
            if args.out:
                atomic_write_text(args.out, text)
            else:
                print(text, end="")
            return 0
        records = run(frames, engine, rate)
    finally:
        engine.close()
    atomic_write_text(args.out, "".join(json.dumps(r) + "\n" for r in records))
    return 0
