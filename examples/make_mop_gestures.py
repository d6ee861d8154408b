"""Write the example puck gestures of examples/mop.yaml (examples/mop/gestures/NAME.csv) and
its bird sprite sheet (examples/mop/bird.json).

Each gesture is a puck path relative to where it starts (columns t, dx, dy: seconds, metres),
sampled at 30 Hz, easing in and out, with 0.5 mm of seeded jitter. Deterministic: running it
again writes the same files.

    python examples/make_mop_gestures.py [--out examples/mop]

The bird is a vector sprite sheet seen from above: six frames of one wing beat (the wings'
span shrinks as they rise and fall), in units of its length, y from tail to beak.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Callable

import numpy as np

RATE_HZ = 30.0


def _ease(u: np.ndarray) -> np.ndarray:
    """0..1 -> 0..1 with zero speed at both ends."""
    return u - np.sin(2 * np.pi * u) / (2 * np.pi)


def circle(s: np.ndarray) -> np.ndarray:
    a = 2 * np.pi * s
    r = 0.08
    return np.stack([r * np.sin(a), r * (1 - np.cos(a))], axis=1)


def zigzag(s: np.ndarray) -> np.ndarray:
    tri = 2 * np.abs(((3 * s + 0.25) % 1.0) - 0.5) - 0.5     # three zigs between -0.5 and 0.5
    return np.stack([0.2 * s, 0.1 * tri], axis=1)


def figure_eight(s: np.ndarray) -> np.ndarray:
    a = 2 * np.pi * s
    return np.stack([0.1 * np.sin(a), 0.1 * np.sin(a) * np.cos(a)], axis=1)


def line(s: np.ndarray) -> np.ndarray:
    out = 0.15 * np.sin(np.pi * s)          # straight out along x and back
    return np.stack([out, 0.0 * s], axis=1)


def square(s: np.ndarray) -> np.ndarray:
    corners = np.array([[0, 0], [0.1, 0], [0.1, 0.1], [0, 0.1], [0, 0]], dtype=float)
    k = np.minimum((s * 4).astype(int), 3)
    f = s * 4 - k
    return corners[k] + f[:, None] * (corners[k + 1] - corners[k])


def wave(s: np.ndarray) -> np.ndarray:
    return np.stack([0.2 * s, 0.04 * np.sin(4 * np.pi * s)], axis=1)


GESTURES: dict[str, tuple[Callable[[np.ndarray], np.ndarray], float]] = {
    "circle": (circle, 2.0), "zigzag": (zigzag, 1.8), "figure_eight": (figure_eight, 2.4),
    "line": (line, 1.5), "square": (square, 2.4), "wave": (wave, 2.0),
}


def gesture(name: str, seed: int = 0) -> np.ndarray:
    """Rows (t, dx, dy) of one example gesture."""
    fn, seconds = GESTURES[name]
    n = int(round(seconds * RATE_HZ)) + 1
    t = np.arange(n) / RATE_HZ
    xy = fn(_ease(t / t[-1]))
    xy = xy - xy[0]
    rng = np.random.default_rng(seed + sum(map(ord, name)))
    xy[1:] += rng.normal(0.0, 0.0005, size=(n - 1, 2))
    return np.column_stack([t, xy])


def bird_sheet(frames: int = 6) -> dict:
    """The bird's sprite sheet: {"format", "bones", "frames"} (points: tail, body, head, beak,
    then shoulder, elbow, tip for the left and the right wing)."""
    out = []
    for k in range(frames):
        a = 0.9 * np.cos(2 * np.pi * k / frames)        # wing elevation, radians
        elbow = np.array([0.28 * np.cos(a), 0.05 + 0.04 * np.sin(a)])
        tip = elbow + np.array([0.26 * np.cos(1.4 * a), -0.08 + 0.06 * np.sin(a)])
        pts = [[0, -0.45], [0, 0], [0, 0.3], [0, 0.42], [0, 0.05],
               [-elbow[0], elbow[1]], [-tip[0], tip[1]], [elbow[0], elbow[1]], [tip[0], tip[1]]]
        out.append([[round(float(x), 6), round(float(y), 6)] for x, y in pts])
    bones = [[0, 1], [1, 2], [2, 3], [4, 5], [5, 6], [4, 7], [7, 8]]
    return {"format": "tabletop.sprites", "bones": bones, "frames": out}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(Path(__file__).resolve().parent / "mop"))
    args = ap.parse_args()
    out = Path(args.out) / "gestures"
    out.mkdir(parents=True, exist_ok=True)
    for name in GESTURES:
        rows = gesture(name)
        text = "t,dx,dy\n" + "".join(f"{r[0]:.6f},{r[1]:.6f},{r[2]:.6f}\n" for r in rows)
        (out / f"{name}.csv").write_text(text, encoding="utf-8")
        print(f"{out / name}.csv: {len(rows)} samples, {rows[-1, 0]:.2f} s")
    sheet = Path(args.out) / "bird.json"
    sheet.write_text(json.dumps(bird_sheet()) + "\n", encoding="utf-8")
    print(f"{sheet}: {len(bird_sheet()['frames'])} frames")


if __name__ == "__main__":
    main()
