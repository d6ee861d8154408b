"""The synthetic camera's optics: Gaussian blur, then radial/tangential lens distortion.

A frame differs from the empty table only where pucks and hands were drawn, so the background is
put through the optics once (:meth:`Optics.set_background`) and each frame only in its changed
("dirty") rectangles (:meth:`Optics.apply`); the result equals blurring and distorting the whole
frame. Units: image pixels, x right / y down; ``K`` and ``dist`` as in OpenCV.
"""

from __future__ import annotations

import math

import cv2
import numpy as np

Rect = tuple[int, int, int, int]   # x0, y0, x1, y1 pixels (x1, y1 excluded)


class Optics:
    """Blur (``blur_sigma`` pixels) and lens distortion (OpenCV ``dist``, (k1, k2, p1, p2, k3))
    of a ``size`` = (w, h) pixel pinhole camera with matrix ``K``. ``full_frame``: put the whole
    frame through them every time (same image, slower; for checking)."""

    def __init__(self, K: np.ndarray, dist: np.ndarray, size: tuple[int, int],
                 blur_sigma: float, full_frame: bool = False) -> None:
        self.K, self.dist = K, dist
        self.w, self.h = size
        self.blur_sigma, self.full_frame = blur_sigma, full_frame
        self.map: tuple[np.ndarray, np.ndarray] | None = None
        if np.any(dist != 0.0):
            # For each output (distorted) pixel, where it lies in the ideal pinhole image.
            yy, xx = np.mgrid[0:self.h, 0:self.w].astype(np.float32)
            pts = np.stack([xx.ravel(), yy.ravel()], axis=1).reshape(-1, 1, 2)
            ideal = cv2.undistortPoints(pts, K, dist, P=K).reshape(self.h, self.w, 2)
            self.map = cv2.convertMaps(ideal[..., 0].astype(np.float32),
                                       ideal[..., 1].astype(np.float32), cv2.CV_16SC2)

    def set_background(self, background: np.ndarray) -> None:
        """The background (ideal image pixels) through the optics, computed once."""
        bg = background
        if self.blur_sigma > 0:
            bg = cv2.GaussianBlur(bg, (0, 0), self.blur_sigma)
        self._bg_blurred = bg
        if self.map is not None:
            bg = cv2.remap(bg, self.map[0], self.map[1], cv2.INTER_LINEAR,
                           borderMode=cv2.BORDER_REPLICATE)
        self._bg_final = bg

    def apply(self, ideal: np.ndarray, dirty: list[Rect]) -> np.ndarray:
        """Optics on the drawn ideal image: blur, then lens distortion. Only the dirty rectangles
        differ from the background given to :meth:`set_background`."""
        if self.full_frame:
            dirty = [(0, 0, self.w, self.h)]
        sigma = self.blur_sigma
        r = int(math.ceil(3.0 * sigma)) + 1 if sigma > 0 else 0  # how far blur spreads a change
        blurred = self._bg_blurred.copy() if self.map is not None else self._bg_final.copy()
        changed = []
        for x0, y0, x1, y1 in dirty:
            # The blur changes pixels up to r beyond the drawing; computing them needs r more.
            cx0, cy0 = max(x0 - r, 0), max(y0 - r, 0)
            cx1, cy1 = min(x1 + r, self.w), min(y1 + r, self.h)
            gx0, gy0 = max(cx0 - r, 0), max(cy0 - r, 0)
            gx1, gy1 = min(cx1 + r, self.w), min(cy1 + r, self.h)
            region = ideal[gy0:gy1, gx0:gx1]
            if sigma > 0:
                region = cv2.GaussianBlur(region, (0, 0), sigma)
            blurred[cy0:cy1, cx0:cx1] = region[cy0 - gy0:cy1 - gy0, cx0 - gx0:cx1 - gx0]
            changed.append((cx0, cy0, cx1, cy1))
        if self.map is None:
            return blurred
        out = self._bg_final.copy()
        for rect in changed:
            d = self.distorted_rect(rect)
            if d is None:
                continue
            x0, y0, x1, y1 = d
            out[y0:y1, x0:x1] = cv2.remap(blurred, self.map[0][y0:y1, x0:x1],
                                          self.map[1][y0:y1, x0:x1], cv2.INTER_LINEAR,
                                          borderMode=cv2.BORDER_REPLICATE)
        return out

    def distorted_rect(self, rect: Rect) -> Rect | None:
        """Bounding box in the distorted image of an ideal-image rectangle (with 4 px to spare)."""
        x0, y0, x1, y1 = rect
        u = np.linspace(0.0, 1.0, 6)
        xs, ys = x0 - 1 + u * (x1 - x0 + 1), y0 - 1 + u * (y1 - y0 + 1)
        edge = np.concatenate([np.column_stack([xs, np.full(6, y0 - 1.0)]),
                               np.column_stack([xs, np.full(6, y1 + 0.0)]),
                               np.column_stack([np.full(6, x0 - 1.0), ys]),
                               np.column_stack([np.full(6, x1 + 0.0), ys])])
        Kinv = np.linalg.inv(self.K)
        norm = np.column_stack([edge, np.ones(len(edge))]) @ Kinv.T
        img, _ = cv2.projectPoints(norm, np.zeros(3), np.zeros(3), self.K, self.dist)
        img = img.reshape(-1, 2)
        lo = np.maximum(np.floor(img.min(axis=0)).astype(int) - 4, 0)
        hi = np.minimum(np.ceil(img.max(axis=0)).astype(int) + 5, [self.w, self.h])
        # Distorted pixels whose source lies outside the image replicate its border pixels.
        lo = np.where([x0 <= 0, y0 <= 0], 0, lo)
        hi = np.where([x1 >= self.w, y1 >= self.h], [self.w, self.h], hi)
        if np.any(hi <= lo):
            return None
        return int(lo[0]), int(lo[1]), int(hi[0]), int(hi[1])
