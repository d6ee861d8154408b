"""A figure's bones read as the drawing needs them, found once per bone set: a figure's
limbs, spine and knots packed for :func:`tabletop.drawing.character_kernel.figure`, a face's
loops packed for :func:`tabletop.drawing.character_kernel.face`, and where a hybrid's face
rides on its body. Pure over point counts and bone pairs (parent -> child point indices)."""

from __future__ import annotations

import functools
from typing import Sequence

import numpy as np

from tabletop.drawing.palette import remember


def _chains(bones: Sequence[tuple[int, int]]) -> list[list[int]]:
    """Bones grouped into runs of consecutive bones (b of one is a of the next)."""
    out: list[list[int]] = []
    for a, b in bones:
        if out and out[-1][-1] == a:
            out[-1].append(b)
        else:
            out.append([a, b])
    return out


def _spine(bones: Sequence[tuple[int, int]]) -> list[int]:
    """The figure's spine: from the first bone's parent, always on to the first-listed child
    (a humanoid's pelvis -> chest -> neck -> head, a creature's hips -> shoulders -> nose)."""
    children: dict[int, list[int]] = {}
    for a, b in bones:
        children.setdefault(a, []).append(b)
    path = [bones[0][0]]
    while path[-1] in children and len(path) <= len(bones):
        nxt = children[path[-1]][0]
        if nxt in path:
            break
        path.append(nxt)
    return path


def _subtree_sizes(n: int, bones: Sequence[tuple[int, int]]) -> np.ndarray:
    """For each point, how many points hang below it (bones run parent -> child)."""
    size = np.ones(n)
    for a, b in reversed(list(bones)):
        if 0 <= a < n and 0 <= b < n:
            size[a] += size[b]
    return size


def _valid_bones(n: int, bones: Sequence[tuple[int, int]]) -> list[tuple[int, int]]:
    return [(a, b) for a, b in bones if 0 <= a < n and 0 <= b < n and a != b]


def pack_topology(bones: list, limb_points: list, spine_points: list, knots: list,
                  spine: list, n_limbs: int) -> np.ndarray:
    """A figure's topology as one int array for
    :func:`tabletop.drawing.character_kernel.figure`: a header of (bones, limbs, limb points,
    spine points, knots, spine length), then the bones (limbs first) as pairs, the limb
    points, spine points, knots and the spine."""
    flat = [p for ab in bones for p in ab]
    return np.array([len(bones), n_limbs, len(limb_points), len(spine_points), len(knots),
                     len(spine)] + flat + list(limb_points) + list(spine_points) + list(knots)
                    + list(spine), dtype=np.int64)


def pack_loops(loops: list) -> np.ndarray:
    """A face's loops ((point indices, closed) pairs) as one int array for
    :func:`tabletop.drawing.character_kernel.face`: their count, (start, length, closed) per
    loop, then every loop's indices."""
    head = [len(loops)]
    flat: list[int] = []
    start = 1 + 3 * len(loops)
    for idx, closed in loops:
        head += [start + len(flat), len(idx), int(closed)]
        flat += list(idx)
    return np.array(head + flat, dtype=np.int64)


_topologies: dict[tuple, tuple | None] = {}


def topology(n: int, bones: Sequence[tuple[int, int]]) -> tuple | None:
    """(relative thickness per point, the spine's points but its last, the topology packed for
    :func:`tabletop.drawing.character_kernel.figure`: valid bones limbs first, the spine over
    them) of a figure, computed once per bone set; None when no bone is valid."""
    key = (n, tuple(bones))
    try:
        return _topologies[key]
    except KeyError:
        pass
    valid = _valid_bones(n, bones)
    topo = None
    if valid:
        sub = _subtree_sizes(n, valid)
        rel = 0.45 + 0.55 * np.sqrt(sub / sub.max())
        spine = _spine(valid)
        in_spine = set(spine)
        on_spine = [a in in_spine and b in in_spine for a, b in valid]
        order = sorted(range(len(valid)), key=lambda i: (on_spine[i], -sub[valid[i][1]]))
        knots = [i for i in range(n) if sub[i] > 1 and i not in in_spine]
        used = {p for ab in valid for p in ab}
        spine_points = [i for i in spine if i != spine[-1]]
        tp = pack_topology([valid[i] for i in order], sorted(used - in_spine), spine_points,
                             knots, spine, sum(not f for f in on_spine))
        topo = (rel, np.array(spine_points, dtype=np.int64), tp)
    return remember(_topologies, key, topo, 256)


def _loops(bones: Sequence[tuple[int, int]]) -> list[tuple[list[int], bool]]:
    """Runs of bones as (points, closed): a run is closed when it ends where it began."""
    out = []
    for ch in _chains(bones):
        closed = len(ch) > 3 and ch[0] == ch[-1]
        out.append((ch[:-1] if closed else ch, closed))
    return out


@functools.lru_cache(maxsize=64)
def face_loops(n: int, bones: tuple) -> tuple[np.ndarray, np.ndarray] | None:
    """A face's loops (see :func:`_loops`) packed for
    :func:`tabletop.drawing.character_kernel.face`, and its head's points (the first closed
    loop; none without one), found once per bone set; None without loops."""
    loops = _loops(_valid_bones(n, bones))
    if not loops:
        return None
    heads = [idx for idx, closed in loops if closed] + [[]]
    return pack_loops(loops), np.array(heads[0], dtype=np.int64)


@functools.lru_cache(maxsize=64)
def hybrid_parts(n: int, bones: tuple) -> tuple[int, tuple, tuple] | None:
    """A hybrid's parts (a body with a face riding on it, MOP section 3): (index of the face's
    first point, the body's bones, the face's bones numbered from 0). The body is every point
    joined to the first bone's; the face's loops follow it. None when there is no such split."""
    valid = _valid_bones(n, bones)
    if not valid:
        return None
    body = {valid[0][0]}
    grew = True
    while grew:
        grew = False
        for a, b in valid:
            if (a in body) != (b in body):
                body.update((a, b))
                grew = True
    k = max(body) + 1
    if k >= n or any(a < k <= b or b < k <= a for a, b in valid):
        return None
    return (k, tuple((a, b) for a, b in valid if b < k),
            tuple((a - k, b - k) for a, b in valid if a >= k))
