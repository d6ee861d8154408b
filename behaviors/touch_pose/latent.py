"""The learned model of style-based IK (paper 003, section 4): sample postures in a latent space.

- Pose distance (as in Kovar et al.'s motion graphs): the sum over all joints and parts of the
  distance between corresponding points, after the two postures are aligned on their pelvis
  (horizontal position and heading removed; height and tilt kept, they are part of the pose).
- Latent space: classical multidimensional scaling of that distance matrix (2-D by default),
  so distances between postures are preserved as well as 2 dimensions allow.
- Grid: the latent space's bounding box is cut into cells, about two samples per cell; each
  non-empty cell has a representative, the sample nearest the cell's centre.
- Constraint distance: the average over the touches of the distance between a touch's half-line
  and the touched part of a sample; with the orthographic camera that is the screen distance.
- Synthesis: the cell whose representative is nearest the constraints is chosen; the samples of
  that cell and its 8 neighbours get weights 1 / (d + eps)^2 (normalised) and are blended
  (quaternions per joint, the relative pelvis position linearly). The neighbours are included
  because a cell alone holds one to a few samples, too few to interpolate between; with them the
  blended pose changes smoothly as a touch moves (measured: the blended hand moved by at most
  a few centimetres per centimetre of drag, against whole-pose jumps from one cell to the next).

Weights and joint blend, measured (bench/touch_pose_blend.py; the blend's constraint distance
on the held-out postures below, median / p90, m; a right-hand goal swept 0.6 m in 2 mm steps:
steps where the blended hand moved over 5 times the goal's step, and its path per metre):
1/(d+0.02)^1 0.063/0.183, 7 jumps, 1.77; ^2 with eps 0.005 / 0.02 / 0.05: 0.028/0.109 /
0.035/0.116 / 0.044/0.134, 6 / 6 / 7 jumps, 1.54-1.56; ^4: 0.016/0.081, 4 jumps, 1.48;
Gaussian exp(-(d/0.05)^2/2): 0.026/0.080, 6 jumps, 1.43; rotation vectors averaged about the
heaviest sample instead of the normalised quaternion sum: 0.036/0.119, 6 jumps, 1.54 (no
better; the sum is cheaper). The fourth power, the closest
blend, was tried in the engine's posing: after IK the finger-to-part distances barely moved
(bench/touch_pose_posing.py drags, p90 0.0027 -> 0.0025 and 0.0105 -> 0.0096 table m) while
the largest output joint turn per frame in the bow (its posing drag switching into the action,
bench/touch_pose_turns.py) rose 8.6 -> 11.7 degrees, and in the action models the kick's
automatic run 31.9 -> 35.2 and spin kick's drag 69.9 -> 74.0; so the square is kept.

Dimensions and grid, measured on 60 held-out postures (dance and walk frames between the
samples) touched on 1, 2 or 3 parts from two views, as the blend's constraint distance before
IK (median / 90th percentile, metres): 2-D with ~2 samples per cell 0.039 / 0.18; 2-D with ~4
0.058 / 0.24; 2-D with ~8 0.084 / 0.31; 3-D with ~2 or ~4 0.056 / 0.22. So 2-D, ~2 per cell.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from behaviors.motion.clips import quat_normalize
from behaviors.touch_pose.humanoid import Humanoid, Pose
from behaviors.touch_pose.samples import relative

#: Inverse-distance weights: 1 / (d + EPS)^2, d in metres of the character's scale.
EPS = 0.02


def inverse_square(d: np.ndarray) -> np.ndarray:
    """The blend's weights for constraint distances ``d`` (m): 1 / (d + EPS)^2."""
    return 1.0 / (d + EPS) ** 2


def aligned_points(body: Humanoid, pose: Pose) -> np.ndarray:
    """All joint and part points (19, 3) of ``pose`` aligned on its pelvis (see module doc)."""
    return body.points(relative(pose, pose, in_place=False))


def pose_distances(points: np.ndarray) -> np.ndarray:
    """(K, K) sums over points of Euclidean distances between aligned postures (K, N, 3)."""
    diff = points[:, None, :, :] - points[None, :, :, :]
    return np.sqrt(np.einsum("abnk,abnk->abn", diff, diff)).sum(axis=2)


def classical_mds(dist: np.ndarray, dims: int = 2) -> np.ndarray:
    """(K, dims) coordinates whose Euclidean distances best preserve ``dist`` (classical MDS)."""
    k = dist.shape[0]
    j = np.eye(k) - np.ones((k, k)) / k
    b = -0.5 * j @ (dist ** 2) @ j
    vals, vecs = np.linalg.eigh(b)
    order = np.argsort(vals)[::-1][:dims]
    return vecs[:, order] * np.sqrt(np.maximum(vals[order], 0.0))


@dataclass
class Blend:
    """A synthesised posture: sample indices, their weights, the relative pose, generalised time."""

    index: np.ndarray
    weight: np.ndarray
    pose: Pose
    time: float


class LearnedModel:
    """Sample postures (relative to their initial state), their latent coordinates and grid.

    ``times``: generalised time (0..1) of each sample for an action model, else None.
    """

    #: What :meth:`arrays` stores and :meth:`from_arrays` needs: everything learned.
    STORED = ("rots", "roots", "times", "motion", "parts", "distance", "latent", "per_cell")

    def __init__(self, body: Humanoid, poses: list[Pose], times: np.ndarray | None = None,
                 dims: int = 2, per_cell: float = 2.0, motion: np.ndarray | None = None) -> None:
        self.body = body
        self.rots = np.array([p.rots for p in poses])
        self.roots = np.array([p.root for p in poses])
        self.times = np.zeros(len(poses)) if times is None else np.asarray(times, dtype=float)
        #: the sample motion each sample comes from (0, 1, ...; each in time order)
        self.motion = np.zeros(len(poses), dtype=int) if motion is None else np.asarray(motion, int)
        self.parts = np.array([body.parts(p) for p in poses])  # (K, 6, 3) relative frame
        pts = np.array([aligned_points(body, p) for p in poses])
        self.distance = pose_distances(pts)
        self.latent = classical_mds(self.distance, dims)
        self.per_cell = float(per_cell)
        self._grid()

    def arrays(self) -> dict[str, np.ndarray]:
        """The learned arrays (see :data:`STORED`), e.g. to keep on disk."""
        return {k: np.asarray(getattr(self, k)) for k in self.STORED}

    @classmethod
    def from_arrays(cls, body: Humanoid, arrays: dict[str, np.ndarray]) -> "LearnedModel":
        """The model learned earlier whose :meth:`arrays` these are (the grid is rebuilt)."""
        self = cls.__new__(cls)
        self.body = body
        for k in cls.STORED:
            setattr(self, k, np.array(arrays[k], dtype=float))
        self.per_cell = float(self.per_cell)
        self.motion = self.motion.astype(int)
        self._grid()
        return self

    def _grid(self) -> None:
        """Cells over the latent space's bounding box, a representative per cell, neighbours."""
        k, dims = self.latent.shape
        lo, hi = self.latent.min(axis=0), self.latent.max(axis=0)
        g = max(1, int(math.ceil((k / self.per_cell) ** (1.0 / dims))))
        self.grid = g
        span = np.where(hi - lo > 1e-12, hi - lo, 1.0)
        cell = np.minimum(((self.latent - lo) / span * g).astype(int), g - 1)
        self.cell = cell
        self.cells: dict[tuple[int, ...], np.ndarray] = {}
        for key in {tuple(c) for c in cell.tolist()}:
            self.cells[key] = np.flatnonzero((cell == key).all(axis=1))
        reps, keys = [], []
        for key, members in self.cells.items():
            centre = lo + (np.array(key) + 0.5) / g * span
            reps.append(members[np.argmin(np.linalg.norm(self.latent[members] - centre, axis=1))])
            keys.append(key)
        self.rep = np.array(reps)
        self.rep_key = keys
        # candidate samples of each cell: its own and its neighbours'
        self._near: dict[tuple[int, ...], np.ndarray] = {}
        offsets = np.array(np.meshgrid(*[[-1, 0, 1]] * dims)).reshape(dims, -1).T
        for key in keys:
            idx = [self.cells[tuple(k)] for k in (np.array(key) + offsets).tolist()
                   if tuple(k) in self.cells]
            self._near[key] = np.concatenate(idx)

    def __len__(self) -> int:
        return len(self.rots)

    def screen_parts(self, index: np.ndarray, parts: np.ndarray, view: np.ndarray,
                     offset: np.ndarray) -> np.ndarray:
        """Screen points (len(index), len(parts), 2) of samples' parts placed on the character:
        ``view`` (2, 3) maps relative-frame points to the screen, ``offset`` (2,) adds after.
        Every sample's parts are projected once per view and placement (they change only when
        the camera turns or the character's base moves)."""
        key = view.tobytes() + offset.tobytes()
        if self.__dict__.get("_screen_key") != key:
            self._screen = self.parts @ view.T + offset
            self._screen_key = key
        return self._screen[index][:, parts]

    def constraint_distance(self, index: np.ndarray, parts: np.ndarray, targets: np.ndarray,
                            view: np.ndarray, offset: np.ndarray) -> np.ndarray:
        """Average screen distance (metres) between each sample's touched parts and the touches."""
        d = self.screen_parts(index, parts, view, offset) - targets
        return np.sqrt(np.einsum("kcj,kcj->kc", d, d)).mean(axis=1)

    def synthesize(self, parts: np.ndarray, targets: np.ndarray, view: np.ndarray,
                   offset: np.ndarray,
                   weights: Callable[[np.ndarray], np.ndarray] = inverse_square) -> Blend:
        """The blended posture for touches on ``parts`` (indices into PARTS) at screen
        ``targets`` (C, 2): the best cell by its representative, then ``weights`` of the
        constraint distances (m) over its and its neighbours' samples."""
        d_rep = self.constraint_distance(self.rep, parts, targets, view, offset)
        key = self.rep_key[int(np.argmin(d_rep))]
        index = self._near[key]
        d = self.constraint_distance(index, parts, targets, view, offset)
        return self.blend(index, weights(d))

    def blend(self, index: np.ndarray, weight: np.ndarray) -> Blend:
        """Blend samples ``index`` with (unnormalised) weights: quaternions per joint, root
        linearly."""
        w = np.asarray(weight, dtype=float)
        w = w / w.sum()
        q = self.rots[index]  # (n, 13, 4)
        ref = q[int(np.argmax(w))]
        sign = np.where(np.einsum("njk,jk->nj", q, ref) < 0.0, -1.0, 1.0)
        rots = quat_normalize(np.einsum("n,nj,njk->jk", w, sign, q))
        root = w @ self.roots[index]
        return Blend(index, w, Pose(root, rots), float(w @ self.times[index]))

    def motion_weights(self, blend: Blend | None) -> np.ndarray:
        """Each sample motion's share (sums to 1) of ``blend``'s weights; equal without one."""
        n = int(self.motion.max()) + 1
        if blend is None:
            return np.full(n, 1.0 / n)
        w = np.bincount(self.motion[blend.index], blend.weight, minlength=n)
        return w / w.sum()

    def at_time(self, blend: Blend | None, u: float) -> Blend:
        """The posture at generalised time ``u`` with ``blend``'s weights kept (section 5): each
        sample motion's posture at ``u`` (between its two samples around ``u``, blended by their
        time distance), blended by the motion's share of the weights (equal shares for None)."""
        index, weight = [], []
        for m, share in enumerate(self.motion_weights(blend)):
            if share <= 0.0:
                continue
            own = np.flatnonzero(self.motion == m)
            t = self.times[own]
            k = int(np.clip(np.searchsorted(t, u, side="right") - 1, 0, len(t) - 2))
            f = float(np.clip((u - t[k]) / max(t[k + 1] - t[k], 1e-9), 0.0, 1.0))
            index += [own[k], own[k + 1]]
            weight += [share * (1.0 - f + 1e-12), share * (f + 1e-12)]
        out = self.blend(np.array(index), np.array(weight))
        out.time = float(u)
        return out


def yaw_view(camera_matrix: np.ndarray, base_xz: np.ndarray, base_yaw: float,
             ) -> tuple[np.ndarray, np.ndarray]:
    """(view (2, 3), offset (2,)) mapping relative-frame points of a character based at
    ``base_xz`` with heading ``base_yaw`` to the screen of a camera (its 2 x 3 matrix)."""
    c, s = math.cos(base_yaw), math.sin(base_yaw)
    rot = np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])
    base = np.array([base_xz[0], 0.0, base_xz[1]])
    return camera_matrix @ rot, camera_matrix @ base

