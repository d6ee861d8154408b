"""Characters made in this repository: a salamander-like creature and a face with blendshapes.

Creature: a planar :class:`~behaviors.motion.skeleton.Skeleton2D` seen from above (the table's own
view): spine, head, tail and four two-segment legs, lengths in body lengths (nose to tail tip is
1). Its clips are keyframes of joint angles (radians, channel type ``angle``): ``walk`` (spine
wave with alternating legs, a loop), ``wag`` (tail sweeps), ``curl`` (the body rolls into a ring
and back), ``strike`` (rears the head forward and reaches with the front legs).

Face: a front view drawn as line loops (outline, brows, eyes, nose, mouth), in face heights
(chin at y = -0.5, brow line near +0.25, x to the face's right). Each blendshape moves points by
a fixed offset scaled by its weight (0..1): ``smile``, ``frown``, ``jaw_open``, ``brows_up``,
``brows_angry``, ``blink_left``, ``blink_right``, ``puff``. Its clips are keyframes of weights
(channel type ``scalar``): ``laugh``, ``surprise``, ``angry``, ``wink``, ``talk``.

Everything here is built by code from a few numbers; nothing is read from files.
"""

from __future__ import annotations

import math
from typing import Callable

import numpy as np

from behaviors.motion.clips import Channel, Clip, ClipError
from behaviors.motion.skeleton import Skeleton2D

# --- creature -----------------------------------------------------------------------------------

_CREATURE_BONES: tuple[tuple[str, int, float, float], ...] = (
    # name, parent point, length (body lengths), rest angle (rad, relative to parent)
    ("spine_front", 0, 0.19, 0.0),        # point 1: shoulders
    ("neck", 1, 0.10, 0.0),               # 2
    ("head", 2, 0.14, 0.0),               # 3: nose
    ("tail_1", 0, 0.16, math.pi),         # 4
    ("tail_2", 4, 0.15, 0.0),             # 5
    ("tail_3", 5, 0.14, 0.0),             # 6
    ("tail_4", 6, 0.12, 0.0),             # 7: tail tip
    ("front_left_upper", 1, 0.11, 1.2),   # 8
    ("front_left_lower", 8, 0.10, 0.9),   # 9
    ("front_right_upper", 1, 0.11, -1.2),  # 10
    ("front_right_lower", 10, 0.10, -0.9),  # 11
    ("hind_left_upper", 0, 0.11, 1.9),    # 12
    ("hind_left_lower", 12, 0.10, -0.9),  # 13
    ("hind_right_upper", 0, 0.11, -1.9),  # 14
    ("hind_right_lower", 14, 0.10, 0.9),  # 15
)


def creature_skeleton() -> Skeleton2D:
    """The creature's planar skeleton (body lengths, x forward, y to its left)."""
    names, parents, lengths, rest = zip(*_CREATURE_BONES)
    return Skeleton2D(names, parents, lengths, rest)


def _creature_clip(name: str, pose: Callable[[float], dict[str, float]], keys: int,
                   seconds: float, loop: bool) -> Clip:
    names = [b[0] for b in _CREATURE_BONES]
    u = np.linspace(0.0, 1.0, keys)
    values = np.array([[pose(float(t)).get(n, 0.0) for n in names] for t in u])
    return Clip(name, [Channel(n, "angle") for n in names], u * seconds, values, loop)


def _walk(t: float) -> dict[str, float]:
    w = 2 * math.pi * t
    spine = 0.25 * math.sin(w)
    swing = 0.45 * math.sin(w)
    return {"spine_front": spine, "neck": -0.5 * spine, "head": -0.3 * spine,
            "tail_1": -spine, "tail_2": -0.6 * math.sin(w - 0.8),
            "tail_3": -0.6 * math.sin(w - 1.6),
            "tail_4": -0.5 * math.sin(w - 2.4),
            "front_left_upper": swing, "front_right_upper": swing,
            "hind_left_upper": -swing, "hind_right_upper": -swing,
            "front_left_lower": 0.3 * max(0.0, math.sin(w)),
            "hind_right_lower": -0.3 * max(0.0, -math.sin(w))}


def _wag(t: float) -> dict[str, float]:
    s = math.sin(4 * math.pi * t) * math.sin(math.pi * t)
    return {"tail_1": 0.5 * s,
            "tail_2": 0.5 * math.sin(4 * math.pi * t - 0.7) * math.sin(math.pi * t),
            "tail_3": 0.5 * math.sin(4 * math.pi * t - 1.4) * math.sin(math.pi * t),
            "tail_4": 0.4 * math.sin(4 * math.pi * t - 2.1) * math.sin(math.pi * t),
            "head": -0.2 * s}


def _curl(t: float) -> dict[str, float]:
    c = math.sin(math.pi * t) ** 2
    bend = 0.75 * c
    return {"spine_front": 0.3 * c, "neck": bend, "head": bend, "tail_1": -0.3 * c,
            "tail_2": -bend, "tail_3": -bend, "tail_4": -bend,
            "front_left_upper": -0.8 * c, "front_right_upper": 0.8 * c,
            "hind_left_upper": 0.8 * c, "hind_right_upper": -0.8 * c}


def _strike(t: float) -> dict[str, float]:
    reach = math.sin(math.pi * min(1.0, t / 0.6)) if t < 0.6 else 0.0
    coil = math.sin(math.pi * t / 0.3) if t < 0.3 else 0.0
    return {"neck": 0.6 * coil, "head": -0.9 * coil,
            "front_left_upper": -0.9 * reach, "front_right_upper": 0.9 * reach,
            "front_left_lower": -0.8 * reach, "front_right_lower": 0.8 * reach,
            "tail_1": 0.3 * reach, "tail_2": -0.3 * reach}


CREATURE_MOTIONS: dict[str, tuple[Callable[[float], dict[str, float]], float, bool]] = {
    "walk": (_walk, 1.2, True), "wag": (_wag, 1.5, False),
    "curl": (_curl, 2.0, False), "strike": (_strike, 1.0, False),
}


def creature_clips(keys: int = 13) -> dict[str, Clip]:
    """The creature's motions as joint-angle keyframe clips (``keys`` keys each)."""
    return {name: _creature_clip(name, fn, keys, seconds, loop)
            for name, (fn, seconds, loop) in CREATURE_MOTIONS.items()}


# --- face ---------------------------------------------------------------------------------------

def _ellipse(cx: float, cy: float, rx: float, ry: float, n: int, start: float = 0.0) -> np.ndarray:
    a = start + np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    return np.stack([cx + rx * np.cos(a), cy + ry * np.sin(a)], axis=1)


class FaceModel:
    """A neutral face (points, bones as closed loops and strokes) and its blendshape offsets.

    ``points(weights)`` = neutral + sum_f weights[f] * deltas[f] (face heights, y up).
    """

    BLENDSHAPES = ("smile", "frown", "jaw_open", "brows_up", "brows_angry", "blink_left",
                   "blink_right", "puff")

    def __init__(self) -> None:
        parts: dict[str, np.ndarray] = {
            "outline": _ellipse(0.0, 0.0, 0.36, 0.5, 24),
            "brow_left": np.array([[0.07, 0.2], [0.13, 0.23], [0.2, 0.23], [0.26, 0.2]]),
            "brow_right": np.array([[-0.07, 0.2], [-0.13, 0.23], [-0.2, 0.23], [-0.26, 0.2]]),
            "eye_left": _ellipse(0.165, 0.1, 0.075, 0.04, 8),
            "eye_right": _ellipse(-0.165, 0.1, 0.075, 0.04, 8),
            "nose": np.array([[0.0, 0.06], [0.04, -0.1], [-0.03, -0.12]]),
            "mouth": _ellipse(0.0, -0.25, 0.14, 0.03, 12, start=math.pi),
        }
        self.part_slices: dict[str, slice] = {}
        pts, bones, start = [], [], 0
        for name, p in parts.items():
            n = len(p)
            self.part_slices[name] = slice(start, start + n)
            pts.append(p)
            closed = name in ("outline", "eye_left", "eye_right", "mouth")
            bones += [(start + i, start + (i + 1) % n) for i in range(n if closed else n - 1)]
            start += n
        self.neutral = np.vstack(pts)
        self.bones = tuple(bones)
        self.deltas = np.stack([self._delta(b) for b in self.BLENDSHAPES])
        # (F x 2N: np.tensordot's own product, without its ~10 us of reshaping per pose)
        self._deltas_flat = self.deltas.reshape(len(self.BLENDSHAPES), -1)

    def _delta(self, shape: str) -> np.ndarray:
        d = np.zeros_like(self.neutral)
        p = self.neutral
        mouth = self.part_slices["mouth"]
        m = p[mouth]
        mx = m[:, 0] / 0.14                          # -1 (right corner) .. 1 (left corner)
        lower = m[:, 1] < -0.25 - 1e-9
        if shape in ("smile", "frown"):
            s = 1.0 if shape == "smile" else -1.0
            d[mouth, 1] = s * 0.07 * mx ** 2 - s * 0.02
            d[mouth, 0] = s * 0.03 * mx
        elif shape == "jaw_open":
            d[mouth, 1] = np.where(lower, -0.12 * (1 - 0.5 * mx ** 2), 0.01)
            chin = p[self.part_slices["outline"], 1] < -0.3
            out = self.part_slices["outline"]
            d[out, 1] = np.where(chin, -0.08 * (-p[out, 1] - 0.3) / 0.2, 0.0)
        elif shape in ("brows_up", "brows_angry"):
            for side, sign in (("brow_left", 1.0), ("brow_right", -1.0)):
                b = self.part_slices[side]
                if shape == "brows_up":
                    d[b, 1] = 0.07
                else:
                    inner = 1.0 - (sign * p[b, 0] - 0.07) / 0.19   # 1 at the inner end
                    d[b, 1] = -0.06 * inner
            if shape == "brows_up":
                for eye in ("eye_left", "eye_right"):
                    e = self.part_slices[eye]
                    d[e, 1] = np.sign(p[e, 1] - 0.1) * 0.02
        elif shape in ("blink_left", "blink_right"):
            e = self.part_slices["eye_left" if shape == "blink_left" else "eye_right"]
            d[e, 1] = 0.95 * (0.1 - p[e, 1])
        elif shape == "puff":
            out = self.part_slices["outline"]
            cheek = np.exp(-((p[out, 1] + 0.1) / 0.2) ** 2)
            d[out, 0] = 0.08 * np.sign(p[out, 0]) * cheek
            d[mouth, 0] = -0.4 * m[:, 0]
        return d

    def points(self, weights: np.ndarray) -> np.ndarray:
        """Face points (N x 2, face heights) at blendshape ``weights`` (F,)."""
        w = np.asarray(weights, dtype=float).reshape(1, -1)
        return self.neutral + np.dot(w, self._deltas_flat).reshape(self.neutral.shape)


_FACE_MOTIONS: dict[str, tuple[float, list[tuple[float, dict[str, float]]]]] = {
    "laugh": (1.5, [(0.0, {}), (0.25, {"smile": 1.0, "jaw_open": 0.4, "blink_left": 0.5,
                                         "blink_right": 0.5}),
                    (0.5, {"smile": 1.0, "jaw_open": 0.9, "brows_up": 0.4}),
                    (0.75, {"smile": 1.0, "jaw_open": 0.3, "blink_left": 0.7, "blink_right": 0.7}),
                    (1.0, {"smile": 0.3})]),
    "surprise": (1.2, [(0.0, {}), (0.3, {"brows_up": 1.0, "jaw_open": 0.7}),
                       (0.7, {"brows_up": 1.0, "jaw_open": 1.0, "puff": 0.2}),
                       (1.0, {"brows_up": 0.3})]),
    "angry": (1.2, [(0.0, {}), (0.4, {"brows_angry": 1.0, "frown": 0.8}),
                    (0.8, {"brows_angry": 1.0, "frown": 1.0, "puff": 0.6}), (1.0, {"frown": 0.4})]),
    "wink": (0.8, [(0.0, {}), (0.4, {"blink_left": 1.0, "smile": 0.6}),
                   (0.6, {"blink_left": 1.0, "smile": 0.8}), (1.0, {"smile": 0.3})]),
    "talk": (2.0, [(0.0, {}), (0.15, {"jaw_open": 0.6}), (0.3, {"jaw_open": 0.1}),
                   (0.45, {"jaw_open": 0.8, "brows_up": 0.3}), (0.6, {"jaw_open": 0.2}),
                   (0.75, {"jaw_open": 0.5}), (1.0, {})]),
}


def face_clips() -> dict[str, Clip]:
    """The face's motions as blendshape-weight keyframe clips."""
    channels = [Channel(n, "scalar") for n in FaceModel.BLENDSHAPES]
    out = {}
    for name, (seconds, keys) in _FACE_MOTIONS.items():
        times = np.array([k[0] for k in keys]) * seconds
        values = np.array([[w.get(n, 0.0) for n in FaceModel.BLENDSHAPES] for _, w in keys])
        out[name] = Clip(name, channels, times, values, loop=False)
    return out


# --- hybrid: a creature with a face -------------------------------------------------------------

#: Built-in motions of the hybrid creature (MOP section 3: skeletal and blendshape channels
#: driven together by one action): body motion + facial expression, played at one progress.
HYBRID_MOTIONS: dict[str, tuple[str, str]] = {
    "walk_talk": ("walk", "talk"), "strike_angry": ("strike", "angry"),
    "curl_surprise": ("curl", "surprise"), "wag_laugh": ("wag", "laugh"),
}


def merge_clips(name: str, body: Clip, face: Clip) -> Clip:
    """One clip driving both ``body`` and ``face`` channels: ``face`` resampled at ``body``'s keys
    (both normalised to progress 0..1, MOP's duration alignment)."""
    clash = set(body.names) & set(face.names)
    if clash:
        raise ClipError(f"clips {body.name!r} and {face.name!r} share channels {sorted(clash)}")
    face_keys = face.resampled(len(body.times)).values
    return Clip(name, body.channels + face.channels, body.times,
                np.hstack([body.values, face_keys]), body.loop)


def hybrid_clips() -> dict[str, Clip]:
    """The hybrid creature's motions (:data:`HYBRID_MOTIONS`)."""
    bodies, faces = creature_clips(), face_clips()
    return {n: merge_clips(n, bodies[b], faces[f]) for n, (b, f) in HYBRID_MOTIONS.items()}


# --- hybrid: a humanoid with a face -------------------------------------------------------------

#: Built-in motions of the hybrid humanoid: a DeepMimic motion-capture clip (``pybullet_data``)
#: and a facial expression of :class:`FaceModel`, played at one progress.
HUMANOID_HYBRID_MOTIONS: dict[str, tuple[str, str]] = {
    "walk_talk": ("walk", "talk"), "punch_angry": ("punch", "angry"),
    "jump_surprise": ("jump", "surprise"), "dance_laugh": ("dance_a", "laugh"),
}


def humanoid_hybrid_clip(name: str) -> Clip:
    """The hybrid humanoid's motion ``name`` (:data:`HUMANOID_HYBRID_MOTIONS`): its DeepMimic
    clip's joint channels and the expression's blendshape weights in one clip."""
    from behaviors.motion.deepmimic import load_motion, motion_path
    body, face = HUMANOID_HYBRID_MOTIONS[name]
    return merge_clips(name, load_motion(motion_path(body)), face_clips()[face])
