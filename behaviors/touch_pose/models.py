"""The learned models of touch-pose control, built once and kept in the user's cache folder.

Learning the posing model and the six action models takes a few seconds (sampling the clips,
forward kinematics of every sample, pose distances, MDS). The result is kept on disk in
``$XDG_CACHE_HOME/tabletop`` (``~/.cache/tabletop`` when unset), never in the repository, as one
``.npz`` file (plain arrays, no pickled objects) named after a SHA-256 of everything the models
are learned from: every DeepMimic clip and the humanoid URDF of the ``pybullet`` wheel, the source
of the modules that build them (which hold every parameter), the numpy version and
:data:`FORMAT`. Any change to one of them is another file, so a stale model is never used. The
file is written atomically; one that cannot be read, lacks an array, holds a non-finite number or
another key is refused and the models are learned again (and the file rewritten). A folder that
cannot be written only costs the learning time.
"""

from __future__ import annotations

import hashlib
import io
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Mapping

import numpy as np

from behaviors.motion.deepmimic import data_path, humanoid_urdf
from behaviors.touch_pose.action import ActionModel, build_action
from behaviors.touch_pose.humanoid import Humanoid, Pose
from behaviors.touch_pose.latent import LearnedModel
from behaviors.touch_pose.samples import ACTIONS, posing_samples, standing_pose
from tabletop.files import atomic_write_bytes

#: Bumped when the stored layout changes.
FORMAT = 2
PREFIX = "touch_pose-models-"
#: Modules whose source decides what is learned (their parameters live in them).
SOURCES = ("behaviors/motion/clips.py", "behaviors/motion/deepmimic.py",
           "behaviors/motion/skeleton.py", "behaviors/touch_pose/humanoid.py",
           "behaviors/touch_pose/samples.py", "behaviors/touch_pose/latent.py",
           "behaviors/touch_pose/action.py", "behaviors/touch_pose/models.py")
_ROOT = Path(__file__).resolve().parents[2]
_ACTION_FIELDS = ("duration", "stroke", "stroke_t", "vector", "start")


@dataclass
class Models:
    """Everything learned once and shared by any number of characters."""

    body: Humanoid
    posing: LearnedModel
    actions: list[ActionModel]
    stand: Pose


def build_models(body: Humanoid | None = None) -> Models:
    """Learn the posing model and every action model (a few seconds)."""
    body = body or Humanoid()
    return Models(body, LearnedModel(body, posing_samples(body)),
                  [build_action(body, s) for s in ACTIONS], standing_pose(body))


def cache_folder() -> Path:
    """``$XDG_CACHE_HOME/tabletop``, or ``~/.cache/tabletop`` when that is unset or relative."""
    base = os.environ.get("XDG_CACHE_HOME", "")
    root = Path(base) if base and os.path.isabs(base) else Path.home() / ".cache"
    return root / "tabletop"


def input_key() -> str:
    """SHA-256 (hex) of everything the models are learned from (see the module doc)."""
    h = hashlib.sha256(f"format {FORMAT} numpy {np.__version__}\n".encode())
    files = [humanoid_urdf()] + sorted((data_path() / "data" / "motions").glob("humanoid3d_*.txt"))
    files += [_ROOT / s for s in SOURCES]
    for f in files:
        data = f.read_bytes()
        h.update(f"{f.name} {len(data)}\n".encode())
        h.update(data)
    return h.hexdigest()


def to_arrays(models: Models, key: str) -> dict[str, np.ndarray]:
    """The models as named plain arrays (what the cache file holds)."""
    out = {"key": np.array(key), "stand_root": models.stand.root, "stand_rots": models.stand.rots,
           "actions": np.array([a.name for a in models.actions])}
    out.update({f"posing_{k}": v for k, v in models.posing.arrays().items()})
    for i, a in enumerate(models.actions):
        out.update({f"action{i}_{k}": v for k, v in a.model.arrays().items()})
        out.update({f"action{i}_{k}": np.asarray(getattr(a, k), dtype=float)
                    for k in _ACTION_FIELDS})
    return out


def from_arrays(body: Humanoid, arrays: Mapping[str, np.ndarray], key: str) -> Models:
    """The models back from :func:`to_arrays`'s arrays; ValueError if they are not those of
    ``key`` and the current actions, or hold a non-finite number."""
    if str(arrays["key"]) != key:
        raise ValueError("learned for other inputs")
    if [str(n) for n in arrays["actions"]] != [s.name for s in ACTIONS]:
        raise ValueError("other actions")
    for name in arrays.files if hasattr(arrays, "files") else arrays:
        a = arrays[name]
        if a.dtype.kind == "f" and not np.all(np.isfinite(a)):
            raise ValueError(f"{name} is not finite")

    def model(prefix: str) -> LearnedModel:
        return LearnedModel.from_arrays(body, {k: arrays[prefix + k] for k in LearnedModel.STORED})

    actions = []
    for i, spec in enumerate(ACTIONS):
        f = {k: np.array(arrays[f"action{i}_{k}"], dtype=float) for k in _ACTION_FIELDS}
        actions.append(ActionModel(spec, float(f["duration"]), model(f"action{i}_"), f["stroke"],
                                   f["stroke_t"], f["vector"], float(f["start"])))
    stand = Pose(np.array(arrays["stand_root"], dtype=float),
                 np.array(arrays["stand_rots"], dtype=float))
    return Models(body, model("posing_"), actions, stand)


def save(models: Models, path: Path, key: str) -> None:
    """Write the models to ``path`` atomically."""
    buf = io.BytesIO()
    np.savez(buf, **to_arrays(models, key))
    atomic_write_bytes(path, buf.getvalue())


def load(body: Humanoid, path: Path, key: str) -> Models | None:
    """The models kept in ``path`` for ``key``; None if missing, unreadable or not valid."""
    try:
        with np.load(path, allow_pickle=False) as arrays:
            return from_arrays(body, arrays, key)
    except Exception:  # noqa: BLE001 - whatever is wrong with the file, it is learned again
        return None


def load_or_build(folder: Path | None = None) -> tuple[Models, str]:
    """(models, "cache" or "built"): from the cache file for the current inputs if it is valid,
    else learned and written there (stale files of other inputs are removed)."""
    folder = cache_folder() if folder is None else Path(folder)
    key = input_key()
    path = folder / f"{PREFIX}{key[:32]}.npz"
    body = Humanoid()
    models = load(body, path, key)
    if models is not None:
        return models, "cache"
    models = build_models(body)
    try:
        save(models, path, key)
        for old in folder.glob(f"{PREFIX}*.npz"):
            if old != path:
                old.unlink(missing_ok=True)
    except OSError:
        pass  # a read-only or full cache folder: the models are simply learned each time
    return models, "built"
