"""Actions designed at the table: a take of posed postures becomes a touch-pose action.

A take is the character's posture (its posing target, :class:`~behaviors.touch_pose.humanoid.Pose`)
sampled every tick while a designer poses it with their fingers. It becomes an action in the
sense of paper 003, section 5, made as the sample motions' actions are
(:func:`behaviors.touch_pose.action.build_action`): its frames, relative to the first (as
:func:`~behaviors.touch_pose.samples.clip_poses` makes them), are the action's learned model;
its primary part is the part that travelled farthest (metres of path, character frame); its
stroke is that part's path from where it has moved a tenth of its way to where it is farthest
from its start (``stroke_end``, generalised time); stillness is allowed throughout (the designer
chooses the pace), and a finger lifted before the stroke's middle runs the action back to its
start (not done), after it on to its end.

Stored as ``<library>/<name>/action.json`` (written whole or not at all)::

    {"format": "tabletop.touch_pose_action", "version": 1, "name": ..., "part": ...,
     "times": [s, ...], "root": [[x, y, z], ...], "rots": [[[w, x, y, z] x 13], ...]}
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Sequence

import numpy as np

from behaviors.touch_pose.action import ACTION_SAMPLES, ActionModel
from behaviors.touch_pose.humanoid import PARTS, Humanoid, Pose
from behaviors.touch_pose.latent import LearnedModel
from behaviors.touch_pose.samples import ActionSpec, Segment, relative
from tabletop.frames import MAX_POSITION_M, InputError
from tabletop.files import (MAX_CLIP_BYTES, NameTaken, UnreadableText, json_loads, new_folder,
                            read_text_within)

FORMAT = "tabletop.touch_pose_action"
FILE = "action.json"
#: Most frames of a take the learned model keeps (evenly spaced; 60 = 2 s at 30 fps). Learning
#: costs 23, 52 and 89 ms CPU for 45, 60 and 90 frames (a 120-frame punch, shared machine).
MAX_FRAMES = 60
#: Shortest take that becomes an action (seconds) and least travel of its primary part (m).
MIN_SECONDS = 0.5
MIN_TRAVEL = 0.05
#: Longest stored take (seconds): a damaged file whose last time was 1e300 loaded as an action
#: lasting 1e300 s.
MAX_SECONDS = 3600.0


class DesignedActionError(InputError):
    """A take or a stored action cannot become an action; the message names why (and the file)."""


class ActionNameTaken(DesignedActionError, NameTaken):
    """The library holds an action of that name already (:func:`save_action`)."""


def primary_part(body: Humanoid, poses: Sequence[Pose]) -> str:
    """The part whose path through ``poses`` is longest (character metres)."""
    parts = np.array([body.parts(p) for p in poses])          # (n, 6, 3)
    travel = np.linalg.norm(np.diff(parts, axis=0), axis=2).sum(axis=0)
    return PARTS[int(np.argmax(travel))]


def designed_action(body: Humanoid, name: str, times: np.ndarray, poses: Sequence[Pose],
                    part: str | None = None) -> ActionModel:
    """The action of a take: ``times`` (s, increasing) and the posture at each.
    DesignedActionError when it is too short or its primary part hardly moves."""
    times = np.asarray(times, dtype=float)
    if len(poses) < 3 or len(times) != len(poses) or times[-1] - times[0] < MIN_SECONDS:
        secs = float(times[-1] - times[0]) if len(times) else 0.0
        raise DesignedActionError(f"take too short ({secs:.1f} s, needs {MIN_SECONDS:g} s)")
    keep = np.unique(np.round(np.linspace(0, len(poses) - 1, min(len(poses), MAX_FRAMES)))
                     .astype(int))
    times = times[keep]
    rel = [relative(poses[i], poses[0]) for i in keep]
    part = part or primary_part(body, rel)
    k = PARTS.index(part)
    traj = np.array([body.parts(p)[k] for p in rel])
    away = np.linalg.norm(traj - traj[0], axis=1)
    if away.max() < MIN_TRAVEL:
        raise DesignedActionError(f"the {part.replace('_', ' ')} hardly moves "
                                  f"({away.max():.2f} m): pose a motion to record an action")
    duration = float(times[-1] - times[0])
    u = (times - times[0]) / duration
    end = max(int(np.argmax(away)), 2)
    stroke_end = float(u[end])
    first = int(np.argmax(away[: end + 1] > 0.1 * away[end]))
    start = float(u[first])
    us = np.linspace(start, stroke_end, ACTION_SAMPLES)
    stroke = np.stack([np.interp(us, u, traj[:, d]) for d in range(3)], axis=1)
    stroke -= stroke[0]
    spec = ActionSpec(name, name, part, stroke_end,
                      (Segment(0.0, True, -1), Segment((start + stroke_end) / 2, True, 1)))
    model = LearnedModel(body, rel, times=u, motion=np.zeros(len(rel), dtype=int))
    return ActionModel(spec, duration, model, stroke, (us - start) * duration,
                       stroke[-1].copy(), start)


def to_json(name: str, part: str, times: np.ndarray, poses: Sequence[Pose]) -> str:
    """The stored form of a take (see the module docstring)."""
    return json.dumps({"format": FORMAT, "version": 1, "name": name, "part": part,
                       "times": [float(t) for t in times],
                       "root": [p.root.tolist() for p in poses],
                       "rots": [p.rots.tolist() for p in poses]})


def read_take(path: Path, body: Humanoid) -> tuple[str, np.ndarray, list[Pose]]:
    """(part, times, poses) of a stored action; DesignedActionError naming the file."""
    try:
        d = json_loads(read_text_within(Path(path), MAX_CLIP_BYTES, "designed action",
                                        DesignedActionError))
    except (OSError, UnreadableText, json.JSONDecodeError) as exc:
        raise DesignedActionError(f"{path}: cannot read the action: {exc}") from None
    try:
        if not isinstance(d, dict) or d.get("format") != FORMAT:
            raise ValueError(f"not a {FORMAT} file")
        part = str(d["part"])
        if part not in PARTS:
            raise ValueError(f"part {part!r} is not one of {', '.join(PARTS)}")
        times = np.asarray(d["times"], dtype=float)
        if times.ndim != 1 or times.size == 0:   # (an empty take stopped the start: IndexError)
            raise ValueError("times must be a list of numbers, one per frame")
        root = np.asarray(d["root"], dtype=float).reshape(len(times), 3)
        rots = np.asarray(d["rots"], dtype=float).reshape(len(times), len(body.names), 4)
        if not (np.all(np.isfinite(times)) and np.all(np.isfinite(root))
                and np.all(np.isfinite(rots))) or np.any(np.diff(times) <= 0):
            raise ValueError("times must increase and every number be finite")
    except (KeyError, TypeError, ValueError) as exc:
        what = f"missing {exc}" if isinstance(exc, KeyError) else str(exc)
        raise DesignedActionError(f"{path}: not a touch-pose action ({what})") from None
    far = np.flatnonzero(np.abs(root).max(axis=1) > MAX_POSITION_M)
    if far.size:   # 1e300 loaded with only numpy's overflow warning
        raise DesignedActionError(f"{path}: frame {int(far[0]) + 1}: root {root[far[0]].tolist()} "
                                  f"is beyond {MAX_POSITION_M:g} m")
    if times[-1] - times[0] > MAX_SECONDS:
        raise DesignedActionError(f"{path}: the take lasts {times[-1] - times[0]:g} s; at most "
                                  f"{MAX_SECONDS:g} s")
    with np.errstate(over="ignore"):
        norms = np.linalg.norm(rots, axis=2, keepdims=True)
    bad = np.flatnonzero(((norms < 1e-9) | ~np.isfinite(norms)).any(axis=(1, 2)))
    if bad.size:   # a quaternion of 1e300 was refused as "a zero rotation"
        n = norms[bad[0]]
        length = float(n.min() if n.min() < 1e-9 else n.max())
        raise DesignedActionError(f"{path}: frame {int(bad[0]) + 1}: a rotation of length "
                                  f"{length:g}, not a rotation quaternion")
    return part, times, [Pose(r, q / n) for r, q, n in zip(root, rots, norms)]


def load_action(folder: Path, body: Humanoid) -> ActionModel:
    """The action stored in ``folder`` (named after the folder)."""
    part, times, poses = read_take(Path(folder) / FILE, body)
    try:
        return designed_action(body, Path(folder).name, times, poses, part)
    except DesignedActionError as exc:
        raise DesignedActionError(f"{Path(folder) / FILE}: {exc}") from None


def list_actions(library: Path) -> list[str]:
    """Names of the action folders (those holding an action.json) in ``library``, sorted."""
    lib = Path(library)
    if not lib.is_dir():
        return []
    return sorted(p.name for p in lib.iterdir()
                  if not p.name.startswith(".") and (p / FILE).is_file())


def load_library(library: Path, body: Humanoid) -> tuple[list[ActionModel], list[str]]:
    """(the library's actions, a message per bad one: skipped, the others load)."""
    actions, problems = [], []
    for name in list_actions(library):
        try:
            actions.append(load_action(Path(library) / name, body))
        except DesignedActionError as exc:
            problems.append(str(exc))
    return actions, problems


def save_action(library: Path, name: str, part: str, times: np.ndarray,
                poses: Sequence[Pose]) -> Path:
    """Save a take as ``<library>/<name>/`` (a new folder appears whole or not at all)."""
    lib, text = Path(library), to_json(name, part, times, poses)
    target = lib / name
    try:
        lib.mkdir(parents=True, exist_ok=True)
        if target.exists():
            raise ActionNameTaken(f"{target}: an action of that name already exists")
        new_folder(target, {FILE: text})
    except OSError as exc:
        raise DesignedActionError(f"{target}: cannot save the action: {exc.strerror or exc}") \
            from None
    return target
