"""Sprite characters: a vector sprite sheet as a rig (MOP 3.1.3's motions shown as frames), and
its JSON file form read with every wrong element named by its place."""

from __future__ import annotations

import json
from typing import Mapping, Sequence

import numpy as np

from behaviors.motion.clips import Clip, ClipError


class SpriteRig:
    """A vector sprite sheet: frames of points sharing one set of bones (figure units, y along
    the heading). A clip's ``frame`` channel (type ``frame``) picks the frame shown."""

    kind = "sprite"

    def __init__(self, frames: np.ndarray, bones: Sequence[tuple[int, int]]) -> None:
        self.frames = np.asarray(frames, dtype=float)
        self.bones = tuple((int(a), int(b)) for a, b in bones)

    def check(self, clip: Clip) -> None:
        if "frame" not in clip.names:
            raise ClipError(f"clip {clip.name!r} has no 'frame' channel to pick sprite frames")

    def pose(self, clip: Clip, progress: float) -> np.ndarray:
        i = int(round(clip.channel(clip.sample(progress), "frame")[0]))
        return self.frames[min(max(i, 0), len(self.frames) - 1)].copy()

    def rest(self) -> np.ndarray:
        return self.frames[0].copy()

    def cycle(self) -> Clip:
        """A clip that shows every frame in order, each for an equal share of the progress."""
        from behaviors.motion.clips import Channel
        n = len(self.frames)
        times = np.arange(n + 1, dtype=float)
        values = np.minimum(np.arange(n + 1), n - 1)[:, None].astype(float)
        return Clip("frames", [Channel("frame", "frame")], times, values)


SHEET_KEYS = ("format", "bones", "frames")


def _check_nested(value: object, where: str, key: str, names: tuple[str, ...],
                  pair: str) -> None:
    """ClipError naming, by its place (``frames[3][2][1]``), the first element of ``value``
    that is not what it should be: lists of ``names[0]``, each a list of ``names[1]``, ...,
    the innermost a ``pair`` (``"xy"``: two numbers, ``"ab"``: two point indices)."""
    def got(v: object) -> str:
        return json.dumps(v)[:40]

    def walk(v: object, level: int, at: str) -> None:
        if level == len(names) + 1:   # a number, or a point index
            ints = pair == "ab"
            if isinstance(v, bool) or not isinstance(v, int if ints else (int, float)):
                raise ClipError(f"{where}: {at}: expected {'a point index' if ints else 'a number'}"
                                f", got {got(v)}")
            return
        if level == len(names):
            if not isinstance(v, list) or len(v) != 2:
                raise ClipError(f"{where}: {at}: expected [{', '.join(pair)}], got {got(v)}")
        elif not isinstance(v, list):
            raise ClipError(f"{where}: {at}: expected a list of {names[level]}s, got {got(v)}")
        for i, item in enumerate(v):
            walk(item, level + 1, f"{at}[{i}]")
    walk(value, 0, key)


MAX_SPRITE_UNITS = 1000.0   # a sprite point's farthest coordinate, figure units (the shipped
#                             bird's reach 0.5)


def sprite_sheet_from_mapping(data: object, where: str) -> SpriteRig:
    """A sprite rig from its JSON form ``{"format": "tabletop.sprites", "bones": [[a, b], ...],
    "frames": [[[x, y], ...], ...]}`` (every frame has the same number of points)."""
    if not isinstance(data, Mapping) \
            or data.get("format", "tabletop.sprites") != "tabletop.sprites":
        raise ClipError(f"{where}: expected a JSON object with format 'tabletop.sprites'")
    for key in data:
        if key not in SHEET_KEYS:
            raise ClipError(f"{where}: {key!r}: unknown key (known: {', '.join(SHEET_KEYS)})")
    if "frames" not in data:
        raise ClipError(f"{where}: 'frames' missing: a list of frames of [x, y] points")
    _check_nested(data["frames"], where, "frames", ("frame", "point"), "xy")
    _check_nested(data.get("bones", []), where, "bones", ("bone",), "ab")
    sizes = sorted({len(f) for f in data["frames"]})
    if len(sizes) > 1:
        raise ClipError(f"{where}: 'frames' hold {' or '.join(map(str, sizes))} points; every "
                        "frame must have the same number")
    frames = np.array(data["frames"], dtype=float)
    bones = np.array(data.get("bones", []), dtype=int).reshape(-1, 2)
    if frames.ndim != 3 or frames.shape[0] < 1 or frames.shape[2] != 2 or frames.shape[1] < 2:
        raise ClipError(f"{where}: 'frames' must be frames of the same number (>= 2) of [x, y] "
                        "points")
    if not np.all(np.isfinite(frames)):
        raise ClipError(f"{where}: a frame holds a value that is not a finite number")
    far = float(np.abs(frames).max())
    if far > MAX_SPRITE_UNITS:   # 1e300 loaded, then failed the view's every frame (no Rect)
        raise ClipError(f"{where}: a frame holds a point {far:g} figure units from the origin; "
                        f"at most {MAX_SPRITE_UNITS:g}")
    if bones.size and (bones.min() < 0 or bones.max() >= frames.shape[1]):
        raise ClipError(f"{where}: a bone refers to a point that does not exist "
                        f"(frames have {frames.shape[1]} points)")
    return SpriteRig(frames, [tuple(b) for b in bones])
