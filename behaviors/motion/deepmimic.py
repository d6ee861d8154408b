"""DeepMimic humanoid motion clips (``pybullet_data/data/motions/humanoid3d_*.txt``) as clips.

The file is JSON ``{"Loop": "wrap" | "none", "Frames": [[...44 numbers...], ...]}``. Each frame:
its duration in seconds (time to the next frame; about 1/30 s), the root position (3, model units,
y up), then rotations in the order pybullet's ``deep_mimic/env/humanoid_pose_interpolator.py``
reads them: root, chest, neck, right hip, right knee, right ankle, right shoulder, right elbow,
left hip, left knee, left ankle, left shoulder, left elbow. Ball joints are quaternions stored w
first; knees and elbows are single angles (radians) about the joint's hinge axis.

Channel names are the joint names of ``pybullet_data/humanoid/humanoid.urdf`` so the clip drives
:class:`behaviors.motion.skeleton.UrdfSkeleton` directly; the root is ``root_x``, ``root_y``,
``root_z`` and ``root_rot``.

``pybullet_data`` comes with the ``pybullet`` wheel; only its data path is used here, the physics
engine is never imported.
"""

from __future__ import annotations

import difflib
import importlib.util
import json
from pathlib import Path
from typing import Iterable, Mapping

import numpy as np

from behaviors.motion.clips import Channel, Clip, ClipError
from tabletop.files import MAX_CLIP_BYTES, UnreadableText, json_loads, read_text_within

# (channel name, kind) in frame order after the duration; "pos" is 3 scalars.
HUMANOID_LAYOUT: tuple[tuple[str, str], ...] = (
    ("root", "pos"), ("root_rot", "quat"), ("chest", "quat"), ("neck", "quat"),
    ("right_hip", "quat"), ("right_knee", "angle"), ("right_ankle", "quat"),
    ("right_shoulder", "quat"), ("right_elbow", "angle"),
    ("left_hip", "quat"), ("left_knee", "angle"), ("left_ankle", "quat"),
    ("left_shoulder", "quat"), ("left_elbow", "angle"),
)
FRAME_WIDTH = 44  # duration + 3 + 4 * 9 quaternions (incl. root) + 4 hinge angles
#: Clip root positions -> humanoid.urdf units: pybullet's DeepMimic environment loads the URDF at
#: globalScaling 0.25, and the clips' root heights (about 0.85) match that scaled body.
ROOT_SCALE = 4.0


def humanoid_channels() -> tuple[Channel, ...]:
    """The clip channels of a DeepMimic humanoid frame (without its duration)."""
    out: list[Channel] = []
    for name, kind in HUMANOID_LAYOUT:
        if kind == "pos":
            out += [Channel(f"{name}_x"), Channel(f"{name}_y"), Channel(f"{name}_z")]
        else:
            out.append(Channel(name, kind))
    return tuple(out)


def data_path() -> Path:
    """The folder of the ``pybullet_data`` package, without importing the pybullet engine."""
    spec = importlib.util.find_spec("pybullet_data")
    if spec is None or not spec.submodule_search_locations:
        raise ClipError("pybullet_data is not installed: it comes with the pybullet wheel "
                        "(pip install pybullet==3.2.7)")
    return Path(list(spec.submodule_search_locations)[0])


def humanoid_urdf() -> Path:
    """Path of ``pybullet_data/humanoid/humanoid.urdf``; a clear error if it is missing."""
    p = data_path() / "humanoid" / "humanoid.urdf"
    if not p.is_file():
        raise ClipError(f"{p}: humanoid skeleton file not found in pybullet_data")
    return p


def motion_path(name: str) -> Path:
    """Path of a DeepMimic clip by file name or short name (``walk`` -> humanoid3d_walk.txt)."""
    folder = data_path() / "data" / "motions"
    for candidate in (name, f"{name}.txt", f"humanoid3d_{name}.txt"):
        p = folder / candidate
        if p.is_file():
            return p
    known = sorted(p.name[len("humanoid3d_"):-len(".txt")]
                   for p in folder.glob("humanoid3d_*.txt"))   # (a misspelt name: the right one)
    short = Path(name).name.removesuffix(".txt").removeprefix("humanoid3d_")
    close = difflib.get_close_matches(short, known, n=1)
    hint = f"did you mean {close[0]!r}? " if close else ""
    raise ClipError(f"{folder / name}: DeepMimic clip not found (looked for {name!r}, "
                    f"{name}.txt and humanoid3d_{name}.txt); {hint}the clips: {', '.join(known)}")


def parse_motion(data: object, where: str, name: str | None = None) -> Clip:
    """A humanoid clip from a parsed DeepMimic JSON object; errors start with ``where``."""
    if not isinstance(data, Mapping) or "Frames" not in data:
        raise ClipError(f"{where}: not a DeepMimic motion (expected a JSON object with 'Frames')")
    frames = data["Frames"]
    if not isinstance(frames, list) or len(frames) < 2:
        raise ClipError(f"{where}: 'Frames' must hold at least 2 frames")
    rows = []
    for i, f in enumerate(frames):
        if not isinstance(f, list) or len(f) != FRAME_WIDTH:
            n = len(f) if isinstance(f, list) else "no"
            raise ClipError(f"{where}: frame {i} has {n} numbers; a humanoid frame has "
                            f"{FRAME_WIDTH} (duration, root position, rotations)")
        try:
            row = np.array(f, dtype=float)
        except (TypeError, ValueError):
            raise ClipError(f"{where}: frame {i} holds something that is not a number") from None
        if not np.all(np.isfinite(row)):
            raise ClipError(f"{where}: frame {i} holds a value that is not a finite number")
        rows.append(row)
    arr = np.vstack(rows)
    durations = arr[:-1, 0]
    if np.any(durations <= 0):
        bad = int(np.argmax(durations <= 0))
        raise ClipError(f"{where}: frame {bad} has duration {durations[bad]:g} s; must be > 0")
    times = np.concatenate([[0.0], np.cumsum(durations)])
    loop = str(data.get("Loop", "none")).lower() == "wrap"
    return Clip(name or Path(where).stem, humanoid_channels(), times, arr[:, 1:], loop)


def load_motion(path_or_name: str | Path) -> Clip:
    """Read a DeepMimic humanoid clip from a file path, or by short name from pybullet_data."""
    p = Path(path_or_name)
    if not p.suffix and not p.is_file():
        p = motion_path(str(path_or_name))
    try:
        text = read_text_within(p, MAX_CLIP_BYTES, "DeepMimic clip", ClipError)
    except FileNotFoundError:
        raise ClipError(f"{p}: DeepMimic clip not found") from None
    except (OSError, UnreadableText) as exc:
        raise ClipError(f"{p}: cannot read DeepMimic clip: {exc}") from None
    try:
        data = json_loads(text)
    except json.JSONDecodeError as exc:
        raise ClipError(f"{p}: not valid JSON at line {exc.lineno}: {exc.msg}") from None
    name = p.stem.removeprefix("humanoid3d_")
    return parse_motion(data, str(p), name)


def humanoid_pose(clip: Clip, values: np.ndarray,
                  joints: Iterable[str] | None = None) -> tuple[np.ndarray, np.ndarray, dict]:
    """(root position (3,), root rotation quaternion (4,), joint rotations by URDF joint name)
    of one sampled humanoid vector, ready for :meth:`UrdfSkeleton.forward`. ``joints``: the
    skeleton's joint names to take from the clip (default: the DeepMimic layout's)."""
    root = np.array([values[clip.slices["root_x"]][0], values[clip.slices["root_y"]][0],
                     values[clip.slices["root_z"]][0]])
    rot = values[clip.slices["root_rot"]]
    names = [name for name, kind in HUMANOID_LAYOUT[2:]] if joints is None else joints
    return root, rot, {n: values[clip.slices[n]] for n in names if n in clip.slices}
