"""Marker-like clutter printed on the synthetic table: what an overhead camera also sees.

Paper squares lie on the table top, baked into the synthetic camera's background (so pucks slide
over them): ``square`` (a black-bordered grid of random cells, the look of a marker),
``partial`` (a marker of the camera's own dictionary, ids 0-7, with one to three cells partly
scuffed over or a strip of it torn off) and ``other`` (a marker of another dictionary: 4x4 ids
past 50, 5x5, AprilTag). Each may or may not decode as an id of the camera's dictionary: that
is what it is for (OpenCV's detector, 24 prints on a 1.2 x 0.8 m table, seeds 1-40: two of 960
read as an id, one of them a puck's). Sides 0.035-0.065 m, positions and angles uniform on the
table, all from the given seed. Off (0 prints) by default: the frames are then as before.
"""

from __future__ import annotations

import cv2
import numpy as np

from tracking.markers import dictionary_by_name

KINDS = ("square", "partial", "other")
CELL_PX = 16
COPIED_IDS = 8   # partial prints copy ids 0-7, the ids an installation gives its pucks first
OTHERS = (("DICT_4X4_1000", 50, 1000), ("DICT_5X5_100", 0, 100), ("DICT_APRILTAG_36h11", 0, 587))


def _pattern(kind: str, dictionary: cv2.aruco.Dictionary, rng: np.random.Generator
             ) -> np.ndarray:
    """The printed pattern (uint8, black 0 / white 255), border included, without paper."""
    n = dictionary.markerSize
    if kind == "square":
        cells = np.where(rng.random((n, n)) < 0.5, 255, 0).astype(np.uint8)
        grid = np.zeros((n + 2, n + 2), np.uint8)
        grid[1:-1, 1:-1] = cells
        return cv2.resize(grid, None, fx=CELL_PX, fy=CELL_PX, interpolation=cv2.INTER_NEAREST)
    if kind == "partial":
        side = (n + 2) * CELL_PX
        img = cv2.aruco.generateImageMarker(dictionary, int(rng.integers(0, COPIED_IDS)), side)
        if rng.random() < 0.5:   # scuffed: one to three inner cells partly painted over
            for _ in range(int(rng.integers(1, 4))):
                r, c = rng.integers(1, n + 1, 2) * CELL_PX
                k = int(rng.integers(1, CELL_PX + 1))
                img[r:r + k, c:c + CELL_PX] = 255 - img[r + 1, c + 1]
        else:                    # torn: a strip of 1-2 cells gone from one side
            k = int(rng.integers(1, 3)) * CELL_PX
            img = np.rot90(img, int(rng.integers(0, 4))).copy()
            img[:, -k:] = 255
        return img
    name, lo, hi = OTHERS[int(rng.integers(0, len(OTHERS)))]
    other = dictionary_by_name(name)
    side = (other.markerSize + 2) * CELL_PX
    return cv2.aruco.generateImageMarker(other, int(rng.integers(lo, hi)), side)


def draw_clutter(background: np.ndarray, table_to_image: np.ndarray, table: tuple[float, float],
                 dictionary: cv2.aruco.Dictionary, count: int, seed: int) -> np.ndarray:
    """``background`` (uint8 grey, ideal image pixels) with ``count`` clutter items printed on
    the table, kinds in turn; ``table_to_image``: homography from table metres to pixels."""
    rng = np.random.default_rng((seed, 0xC1))
    img = background.astype(np.float32)
    h, w = img.shape
    for i in range(count):
        pat = _pattern(KINDS[i % len(KINDS)], dictionary, rng).astype(np.float32)
        pad = pat.shape[0] // 6 + 2                      # white paper around the print
        tex = np.pad(pat * (210.0 / 255.0) + 20.0, pad, constant_values=230.0)
        side = rng.uniform(0.035, 0.065)                 # printed side, border included (m)
        k = side / pat.shape[0]
        x, y = rng.uniform(0.05, table[0] - 0.05), rng.uniform(0.05, table[1] - 0.05)
        a = rng.uniform(-np.pi, np.pi)
        c, s = np.cos(a), np.sin(a)
        off = (tex.shape[0] - 1) / 2.0
        to_table = np.array([[c * k, s * k, x - (c + s) * k * off],
                             [s * k, -c * k, y - (s - c) * k * off], [0.0, 0.0, 1.0]])
        M = table_to_image @ to_table
        n = tex.shape[0]
        quad = np.array([[0, 0, 1], [n, 0, 1], [n, n, 1], [0, n, 1]], float) @ M.T
        quad = quad[:, :2] / quad[:, 2:3]
        x0, y0 = np.maximum(np.floor(quad.min(axis=0)).astype(int) - 1, 0)
        x1, y1 = np.minimum(np.ceil(quad.max(axis=0)).astype(int) + 2, [w, h])
        if x1 - x0 < 2 or y1 - y0 < 2:
            continue
        M = np.array([[1.0, 0.0, -x0], [0.0, 1.0, -y0], [0.0, 0.0, 1.0]]) @ M
        size = (int(x1 - x0), int(y1 - y0))
        warped = cv2.warpPerspective(tex, M, size, flags=cv2.INTER_LINEAR)
        mask = cv2.warpPerspective(np.ones_like(tex), M, size, flags=cv2.INTER_LINEAR)
        roi = img[y0:y1, x0:x1]
        roi += mask * (warped / np.maximum(mask, 1e-6) - roi)
    return np.clip(img, 0, 255).astype(np.uint8)
