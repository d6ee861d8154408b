"""A character's inks (tabletop.drawing.characters.inks: faded directly, remembered by the
opacity's 1/128 step) against palette.fade's own layers, on random colours, opacities (within
0..1, beyond it, and on the steps themselves) and grounds (the table, black, any): every ink
equal to the bit. The long form of tests/tabletop/test_view_inks.py (which checks the first
2,000 cases; faults of the rounding, the step or the clamp fail within 20 of them). Prints one
JSON line; exits 1 when a case differs.

    OPENBLAS_NUM_THREADS=1 .venv/bin/python bench/inks.py [--cases 200000] [--seed 0]
"""

from __future__ import annotations

import argparse
import json
import random
import sys
import time
from pathlib import Path
from typing import Iterator

ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from tabletop.drawing import characters as C  # noqa: E402
from tabletop.drawing.palette import EYE_WHITE, INK, TABLE, fade, lighten, rgb, shade  # noqa: E402

Color = tuple[int, int, int]


def faded(c: Color, alpha: float, g: Color) -> tuple[int, ...]:
    """The inks as palette.fade's remembered layers make them."""
    eyes = (lighten(c, 0.35), c) if g == (0, 0, 0) else (EYE_WHITE, INK)
    return tuple(rgb(fade(shade(c, k), alpha, g)) for k in (0.62, 0.68, 0.7, 0.72, 1.0)) + tuple(
        rgb(fade(x, alpha, g)) for x in (lighten(c, 0.18), lighten(c, 0.35), *eyes))


def cases(n: int, seed: int = 0) -> Iterator[tuple[Color, float, Color]]:
    """``n`` random (colour, opacity, ground): an opacity within 0..1, within -0.1..1.1 or on
    a 1/128 step; the ground the table, black or any colour."""
    rnd = random.Random(seed)
    for _ in range(n):
        c = tuple(rnd.randrange(256) for _ in range(3))
        g = rnd.choice([TABLE, (0, 0, 0), tuple(rnd.randrange(256) for _ in range(3))])
        a = rnd.choice([rnd.random(), rnd.random() * 1.2 - 0.1, rnd.randrange(129) / 128])
        yield c, a, g


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cases", type=int, default=200_000, help="random cases (default 200000)")
    ap.add_argument("--seed", type=int, default=0, help="the cases' seed (default 0)")
    a = ap.parse_args(argv)
    t0 = time.process_time()
    differing = [(c, al, g) for c, al, g in cases(a.cases, a.seed) if C.inks(c, al, g) !=
                 faded(c, al, g)]
    print(json.dumps({"cases": a.cases, "seed": a.seed, "differing": len(differing),
                      "first": differing[:1], "cpu_s": round(time.process_time() - t0, 2)}))
    return 1 if differing else 0


if __name__ == "__main__":
    sys.exit(main())
