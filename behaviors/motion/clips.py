"""Character motion clips: keyframes sampled at any progress 0..1, and time alignment.

A :class:`Clip` holds keyframes (times in seconds, any increasing spacing) of named channels:

- ``scalar``: a number interpolated linearly (blendshape weights, positions);
- ``angle``: radians interpolated along the shorter arc (2-D skeleton joint angles);
- ``quat``: a unit quaternion (w, x, y, z), four columns, interpolated by slerp (3-D ball joints);
- ``frame``: a sprite-sheet frame index, held until the next key (no blending between frames).

Progress 0 is the first key and 1 the last; a clip of any length is played at the progress of an
action of any other length. This is MOP's time alignment (section 3.1.3): the action and the
motion are normalised to one duration, so action progress p shows the motion at progress p. A
:class:`TimeWarp` optionally bends that map (piecewise linear and increasing) so a designer can
line up key moments of the action with those of the motion.

Clips convert to and from plain mappings (the JSON clip format, see :func:`clip_from_mapping`);
reading and writing files is left to the caller.
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass
from typing import Any, Mapping, Sequence

import numpy as np

from tabletop.frames import InputError

CHANNEL_TYPES = ("scalar", "angle", "quat", "frame")
CLIP_FORMAT = "tabletop.clip"
MAX_VALUE = 1e6    # a keyframe value's magnitude: a face drawn with weights of 1e6 still draws


class ClipError(InputError):
    """A clip is malformed; the message names the clip (or file) and what is wrong."""


@dataclass(frozen=True)
class Channel:
    """One named channel of a clip; ``type`` is one of :data:`CHANNEL_TYPES`."""

    name: str
    type: str = "scalar"

    @property
    def width(self) -> int:
        """Number of columns the channel takes (4 for a quaternion, else 1)."""
        return 4 if self.type == "quat" else 1


# --- quaternions (w, x, y, z) -------------------------------------------------------------------

def quat_normalize(q: np.ndarray) -> np.ndarray:
    """Unit quaternions (..., 4); a zero quaternion becomes the identity."""
    q = np.asarray(q, dtype=float)
    n = np.sqrt(np.einsum("...i,...i->...", q, q))[..., None]
    ok = n > 1e-12
    if np.all(ok):
        return q / n
    out = np.where(ok, q / np.where(ok, n, 1.0), 0.0)
    out[..., 0] = np.where(ok[..., 0], out[..., 0], 1.0)
    return out


def quat_slerp(q0: np.ndarray, q1: np.ndarray, f: np.ndarray | float) -> np.ndarray:
    """Spherical interpolation of unit quaternions (..., 4) at fraction ``f`` (..., ), shortest
    path."""
    q0 = quat_normalize(q0)
    q1 = quat_normalize(q1)
    f = np.asarray(f, dtype=float)[..., None]
    dot = np.einsum("...i,...i->...", q0, q1)[..., None]
    q1 = np.where(dot < 0.0, -q1, q1)
    dot = np.abs(dot)
    theta = np.arccos(np.minimum(dot, 1.0))
    sin_t = np.sin(theta)
    small = sin_t < 1e-6
    safe = np.where(small, 1.0, sin_t)
    w0 = np.where(small, 1.0 - f, np.sin((1.0 - f) * theta) / safe)
    w1 = np.where(small, f, np.sin(f * theta) / safe)
    return quat_normalize(w0 * q0 + w1 * q1)


def quat_to_matrix(q: np.ndarray) -> np.ndarray:
    """Rotation matrices (..., 3, 3) of quaternions (..., 4) given w first."""
    q = quat_normalize(q)
    w, x, y, z = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    out = np.empty(q.shape[:-1] + (3, 3))
    out[..., 0, 0] = 1 - 2 * (y * y + z * z)
    out[..., 0, 1] = 2 * (x * y - w * z)
    out[..., 0, 2] = 2 * (x * z + w * y)
    out[..., 1, 0] = 2 * (x * y + w * z)
    out[..., 1, 1] = 1 - 2 * (x * x + z * z)
    out[..., 1, 2] = 2 * (y * z - w * x)
    out[..., 2, 0] = 2 * (x * z - w * y)
    out[..., 2, 1] = 2 * (y * z + w * x)
    out[..., 2, 2] = 1 - 2 * (x * x + y * y)
    return out


def quat_from_axis_angle(axis: Sequence[float], angle: float) -> np.ndarray:
    """The unit quaternion (w, x, y, z) turning ``angle`` radians about ``axis``."""
    a = np.asarray(axis, dtype=float)
    a = a / max(float(np.linalg.norm(a)), 1e-12)
    return np.concatenate([[math.cos(angle / 2)], math.sin(angle / 2) * a])


def _hamilton(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return np.array([aw * bw - ax * bx - ay * by - az * bz, aw * bx + ax * bw + ay * bz - az * by,
                     aw * by - ax * bz + ay * bw + az * bx, aw * bz + ax * by - ay * bx + az * bw])


# The Hamilton product as a bilinear map: (a * b)_j = sum_ik a_i T[i, j, k] b_k.
_HAMILTON = np.stack([np.stack([_hamilton(np.eye(4)[i], np.eye(4)[k]) for k in range(4)], axis=1)
                      for i in range(4)]).reshape(4, 16)


def quat_left_matrix(a: np.ndarray) -> np.ndarray:
    """Matrices (..., 4, 4) L with L @ b = a * b for quaternions ``a`` (..., 4)."""
    a = np.asarray(a, dtype=float)
    return (a @ _HAMILTON).reshape(a.shape[:-1] + (4, 4))


def quat_mul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton products a * b of quaternions (..., 4), w first (apply b, then a); shapes
    broadcast. Two matrix products instead of sixteen elementwise ones (4x faster here)."""
    b = np.asarray(b, dtype=float)
    return np.matmul(quat_left_matrix(a), b[..., None])[..., 0]


def quat_conj(q: np.ndarray) -> np.ndarray:
    """Conjugates (inverses of unit quaternions) of quaternions (..., 4)."""
    out = np.array(q, dtype=float)
    out[..., 1:] *= -1.0
    return out


def quat_to_rotvec(q: np.ndarray) -> np.ndarray:
    """Rotation vectors (..., 3; axis times angle in radians, angle <= pi) of quaternions."""
    q = np.asarray(q, dtype=float)
    q = np.where(q[..., :1] < 0.0, -q, q)
    v = q[..., 1:]
    s = np.sqrt(np.einsum("...i,...i->...", v, v))
    angle = 2.0 * np.arctan2(s, q[..., 0])
    scale = np.where(s > 1e-9, angle / np.where(s > 1e-9, s, 1.0), 2.0)
    return v * scale[..., None]


def quat_from_rotvec(r: np.ndarray) -> np.ndarray:
    """Unit quaternions (..., 4) of rotation vectors (..., 3, radians)."""
    r = np.asarray(r, dtype=float)
    angle = np.sqrt(np.einsum("...i,...i->...", r, r))
    half = 0.5 * angle
    k = np.where(angle > 1e-9, np.sin(half) / np.where(angle > 1e-9, angle, 1.0), 0.5)
    return np.concatenate([np.cos(half)[..., None], r * k[..., None]], axis=-1)


# --- clips --------------------------------------------------------------------------------------

class Clip:
    """Keyframes ``values`` (K x D) at ``times`` (K, seconds, increasing) of ``channels``.

    ``sample(progress)`` returns the D-vector at progress 0..1 (clamped), each channel
    interpolated by its type. ``loop`` marks a cyclic motion (its last key joins its first);
    progress still runs 0..1 over one cycle.
    """

    def __init__(self, name: str, channels: Sequence[Channel], times: np.ndarray,
                 values: np.ndarray, loop: bool = False) -> None:
        self.name = name
        self.channels = tuple(channels)
        self.times = np.asarray(times, dtype=float).reshape(-1)
        self.values = np.array(values, dtype=float, ndmin=2)
        self.loop = bool(loop)
        _check_clip(self)
        self.slices: dict[str, slice] = {}
        col = 0
        for ch in self.channels:
            self.slices[ch.name] = slice(col, col + ch.width)
            col += ch.width
        self._cols = {t: np.concatenate([np.arange(self.slices[c.name].start,
                                                   self.slices[c.name].stop)
                                         for c in self.channels if c.type == t] or
                                        [np.zeros(0, dtype=int)]).astype(int)
                      for t in CHANNEL_TYPES}
        quat_cols = self._cols["quat"]
        if quat_cols.size:
            n = len(self.times)
            self.values[:, quat_cols] = quat_normalize(
                self.values[:, quat_cols].reshape(n, -1, 4)).reshape(n, -1)
        span = self.times[-1] - self.times[0]
        self._u = (self.times - self.times[0]) / span
        self._u_list = self._u.tolist()
        self._driving: dict[tuple[str, ...], tuple[np.ndarray, np.ndarray, bool]] = {}

    @property
    def width(self) -> int:
        """Number of value columns."""
        return self.values.shape[1]

    @property
    def duration(self) -> float:
        """Seconds from the first key to the last."""
        return float(self.times[-1] - self.times[0])

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(c.name for c in self.channels)

    def channel(self, values: np.ndarray, name: str) -> np.ndarray:
        """The columns of channel ``name`` in a sampled vector (or rows of vectors)."""
        if name not in self.slices:
            raise ClipError(f"clip {self.name!r}: no channel {name!r} (has "
                            f"{', '.join(self.names)})")
        return np.asarray(values)[..., self.slices[name]]

    def _segment(self, progress: float) -> tuple[int, float]:
        """The key ``i`` before ``progress`` (0..1, clamped; NaN counts as 0) and the fraction of
        the way to key ``i + 1``."""
        p = float(progress)
        p = 0.0 if p != p else min(max(p, 0.0), 1.0)
        i = min(max(bisect.bisect_right(self._u_list, p) - 1, 0), len(self._u_list) - 2)
        return i, (p - self._u_list[i]) / (self._u_list[i + 1] - self._u_list[i])

    def sample(self, progress: float) -> np.ndarray:
        """The pose at ``progress`` (0..1, clamped; NaN counts as 0) as a D-vector."""
        i, f = self._segment(progress)
        a, b = self.values[i], self.values[i + 1]
        out = a + f * (b - a)
        cols = self._cols["angle"]
        if cols.size:
            out[cols] = a[cols] + f * (np.remainder(b[cols] - a[cols] + np.pi, 2 * np.pi) - np.pi)
        cols = self._cols["frame"]
        if cols.size:
            out[cols] = b[cols] if f >= 1.0 else a[cols]
        cols = self._cols["quat"]
        if cols.size:
            out[cols] = quat_slerp(a[cols].reshape(-1, 4), b[cols].reshape(-1, 4), f).reshape(-1)
        return out

    def driven(self, names: tuple[str, ...], progress: float) -> tuple[np.ndarray, np.ndarray]:
        """The slots of a rig's ``names`` (joint angles, blendshapes) this clip drives (their
        indices in ``names``) and their values at ``progress``: ``sample(progress)`` at those
        channels' first columns. Scalar channels alone are interpolated by themselves: a hybrid
        humanoid's face read its 8 blendshapes through the slerp of its 9 quaternion joints
        (~100 us of a 130 us face pose)."""
        found = self._driving.get(names)
        if found is None:
            pairs = [(i, self.slices[n].start) for i, n in enumerate(names) if n in self.slices]
            cols = np.array([c for _, c in pairs], dtype=np.intp)
            plain = not np.isin(cols, np.concatenate([self._cols[t] for t in CHANNEL_TYPES
                                                      if t != "scalar"])).any()
            found = self._driving[names] = (np.array([i for i, _ in pairs], dtype=np.intp),
                                            cols, bool(plain))
        slots, cols, plain = found
        if not plain:
            return slots, self.sample(progress)[cols]
        i, f = self._segment(progress)
        a, b = self.values[i, cols], self.values[i + 1, cols]
        return slots, a + f * (b - a)

    def sample_many(self, progress: np.ndarray) -> np.ndarray:
        """Poses (M x D) at many progress values."""
        p = np.nan_to_num(np.asarray(progress, dtype=float).reshape(-1), nan=0.0)
        p = np.clip(p, 0.0, 1.0)
        k = len(self._u)
        i = np.clip(np.searchsorted(self._u, p, side="right") - 1, 0, k - 2)
        f = (p - self._u[i]) / (self._u[i + 1] - self._u[i])
        a = self.values[i]
        b = self.values[i + 1]
        out = a + f[:, None] * (b - a)
        cols = self._cols["angle"]
        if cols.size:
            d = np.remainder(b[:, cols] - a[:, cols] + np.pi, 2 * np.pi) - np.pi
            out[:, cols] = a[:, cols] + f[:, None] * d
        cols = self._cols["frame"]
        if cols.size:
            out[:, cols] = np.where(f[:, None] >= 1.0, b[:, cols], a[:, cols])
        cols = self._cols["quat"]
        if cols.size:
            qa = a[:, cols].reshape(len(p), -1, 4)
            qb = b[:, cols].reshape(len(p), -1, 4)
            ff = np.broadcast_to(f[:, None], qa.shape[:2])
            out[:, cols] = quat_slerp(qa, qb, ff).reshape(len(p), -1)
        return out

    def resampled(self, n: int) -> "Clip":
        """The clip at ``n`` evenly spaced progress values (MOP's duration normalisation)."""
        if n < 2:
            raise ClipError(f"clip {self.name!r}: cannot resample to {n} frames (need >= 2)")
        u = np.linspace(0.0, 1.0, n)
        times = self.times[0] + u * self.duration
        return Clip(self.name, self.channels, times, self.sample_many(u), self.loop)


def _check_clip(clip: Clip) -> None:
    where = f"clip {clip.name!r}"
    if not clip.channels:
        raise ClipError(f"{where}: no channels")
    seen: set[str] = set()
    for ch in clip.channels:
        if ch.type not in CHANNEL_TYPES:
            raise ClipError(f"{where}: channel {ch.name!r} has type {ch.type!r}; "
                            f"expected one of {', '.join(CHANNEL_TYPES)}")
        if ch.name in seen:
            raise ClipError(f"{where}: channel {ch.name!r} appears twice")
        seen.add(ch.name)
    width = sum(ch.width for ch in clip.channels)
    if clip.times.size < 2:
        raise ClipError(f"{where}: needs at least 2 keyframes, has {clip.times.size}")
    if clip.values.shape != (clip.times.size, width):
        raise ClipError(f"{where}: values are {clip.values.shape[0]} x {clip.values.shape[1]}; "
                        f"expected {clip.times.size} keys x {width} columns for its channels")
    if not (np.all(np.isfinite(clip.times)) and np.all(np.isfinite(clip.values))):
        bad = int(np.argmax(~np.isfinite(clip.values).all(axis=1) | ~np.isfinite(clip.times)))
        raise ClipError(f"{where}: keyframe {bad} holds a value that is not a finite number")
    far = np.abs(clip.values).max(axis=1)
    if far.max() > MAX_VALUE:   # a face's weight of 1e300 failed the view at every frame
        bad = int(np.argmax(far > MAX_VALUE))
        raise ClipError(f"{where}: keyframe {bad} holds {far[bad]:g}; at most {MAX_VALUE:g} (a "
                        "weight is about 0 to 1, an angle a few radians, a position metres)")
    steps = np.diff(clip.times)
    if np.any(steps <= 0):
        bad = int(np.argmax(steps <= 0)) + 1
        raise ClipError(f"{where}: key times must increase; key {bad} at "
                        f"{clip.times[bad]:g} s does not come after {clip.times[bad - 1]:g} s")


def clip_from_mapping(data: Any, where: str = "clip") -> Clip:
    """A clip from its JSON form::

        {"format": "tabletop.clip", "name": "wave", "loop": false,
         "channels": [{"name": "smile", "type": "scalar"}, ...],
         "times": [0.0, 0.5, ...], "values": [[...], [...], ...]}

    ``times`` may be omitted with ``"rate"`` (keys per second) given instead. ``where`` (e.g. the
    file name) starts every error message.
    """
    if not isinstance(data, Mapping):
        raise ClipError(f"{where}: expected a JSON object with channels and values")
    fmt = data.get("format", CLIP_FORMAT)
    if fmt != CLIP_FORMAT:
        raise ClipError(f"{where}: format is {fmt!r}; expected {CLIP_FORMAT!r}")
    unknown = set(data) - {"format", "version", "name", "loop", "channels", "times", "rate",
                           "values"}
    if unknown:
        raise ClipError(f"{where}: unknown key {sorted(unknown)[0]!r}")
    chans = data.get("channels")
    if not isinstance(chans, list) or not chans:
        raise ClipError(f"{where}: 'channels' must be a non-empty list of {{name, type}}")
    channels = []
    for i, c in enumerate(chans):
        if isinstance(c, str):
            c = {"name": c}
        if not isinstance(c, Mapping) or not isinstance(c.get("name"), str):
            raise ClipError(f"{where}: channels[{i}] needs a string 'name'")
        channels.append(Channel(c["name"], str(c.get("type", "scalar"))))
    values = data.get("values")
    try:
        arr = np.array(values, dtype=float)
    except (TypeError, ValueError):
        raise ClipError(f"{where}: 'values' must be a list of rows of numbers") from None
    if arr.ndim != 2:
        raise ClipError(f"{where}: 'values' must be a list of rows of numbers")
    if "times" in data:
        try:
            times = np.array(data["times"], dtype=float).reshape(-1)
        except (TypeError, ValueError):
            raise ClipError(f"{where}: 'times' must be a list of numbers (seconds)") from None
    else:
        rate = data.get("rate", 30.0)
        if isinstance(rate, bool) or not isinstance(rate, (int, float)) or not rate > 0:
            raise ClipError(f"{where}: 'rate' must be a positive number of keys per second")
        times = np.arange(arr.shape[0]) / float(rate)
    if times.size != arr.shape[0]:
        raise ClipError(f"{where}: {times.size} times but {arr.shape[0]} rows of values")
    name = data.get("name", where)
    try:
        return Clip(str(name), channels, times, arr, bool(data.get("loop", False)))
    except ClipError as exc:
        raise ClipError(f"{where}: {exc}") from None


def clip_to_mapping(clip: Clip) -> dict[str, Any]:
    """The JSON form of a clip (see :func:`clip_from_mapping`)."""
    return {"format": CLIP_FORMAT, "version": 1, "name": clip.name, "loop": clip.loop,
            "channels": [{"name": c.name, "type": c.type} for c in clip.channels],
            "times": [float(t) for t in clip.times],
            "values": [[float(v) for v in row] for row in clip.values]}


# --- time alignment -----------------------------------------------------------------------------

class TimeWarp:
    """Maps action progress (0..1) to motion progress (0..1), piecewise linear and increasing.

    The identity by default: MOP's duration normalisation. ``points`` [(action, motion), ...]
    starting at (0, 0) and ending at (1, 1) lines up key moments of the two.
    """

    def __init__(self, points: Sequence[Sequence[float]] = ((0.0, 0.0), (1.0, 1.0))) -> None:
        pts = np.asarray(points, dtype=float)
        if pts.ndim != 2 or pts.shape[1] != 2 or len(pts) < 2:
            raise ClipError("time warp: expected a list of at least 2 [action, motion] pairs")
        if not np.all(np.isfinite(pts)):
            raise ClipError("time warp: every point must be finite")
        if abs(pts[0, 0]) > 1e-9 or abs(pts[0, 1]) > 1e-9 or abs(pts[-1, 0] - 1) > 1e-9 \
                or abs(pts[-1, 1] - 1) > 1e-9:
            raise ClipError("time warp: must start at [0, 0] and end at [1, 1]")
        if np.any(np.diff(pts[:, 0]) <= 0) or np.any(np.diff(pts[:, 1]) < 0):
            raise ClipError("time warp: action progress must increase and motion progress "
                            "must not decrease")
        self.points = pts

    def __call__(self, progress: float | np.ndarray) -> np.ndarray | float:
        if isinstance(progress, float):
            # one progress, as a puppet asks each tick: clipped without the array round trip
            # (nan_to_num and clip cost 0.23 of examples/mop.yaml's 2.3 CPU s a 30 s run);
            # values to the bit as below
            p = 0.0 if progress != progress else min(max(progress, 0.0), 1.0)
            return float(np.interp(p, self.points[:, 0], self.points[:, 1]))
        p = np.clip(np.nan_to_num(np.asarray(progress, dtype=float), nan=0.0), 0.0, 1.0)
        out = np.interp(p, self.points[:, 0], self.points[:, 1])
        return float(out) if out.ndim == 0 else out
