"""Table metres to projector pixels: the mapping every drawing of the view goes through."""

from __future__ import annotations

import math

import numpy as np

from calibration.transforms import apply_homography, fitted_rectangle
from tabletop.drawing.reading import Reading


class TableToScreen:
    """Maps table metres to projector pixels with a 3x3 homography: the calibration's
    ``table_to_projector`` when there is one (keystone and all).

    Without a calibration the table is fitted into the window with ``margin`` pixels around it,
    x to the right and y up (the table seen from above).
    """

    def __init__(self, table: tuple[float, float], size: tuple[int, int], margin: int = 24,
                 homography: np.ndarray | None = None) -> None:
        if homography is None:
            homography = fitted_rectangle(table, size, margin)
        self.H = np.asarray(homography, dtype=float)
        self._centre = (table[0] / 2, table[1] / 2)
        self._reading: Reading | None = None
        self._h = [float(v) for v in self.H.ravel()]
        # an affine map (no keystone; the uncalibrated fit): a character's few points in one
        # small product instead of the general homography's column by column arithmetic
        h = self._h
        self._affine = (h[6] == 0.0 and h[7] == 0.0 and h[8] != 0.0)
        if self._affine:
            self._AT = np.array([[h[0], h[3]], [h[1], h[4]]]) / h[8]
            self._t = np.array([h[2], h[5]]) / h[8]

    def points(self, xy: np.ndarray) -> np.ndarray:
        """(N, 2) table metres -> (N, 2) pixels."""
        if self._affine and len(xy) <= 64:
            return np.asarray(xy, dtype=float).reshape(-1, 2) @ self._AT + self._t
        return apply_homography(self.H, xy)

    def point(self, x: float, y: float) -> tuple[float, float]:
        """One table point (metres) -> pixels (plain floats: no array on this hot path)."""
        h = self._h
        w = h[6] * x + h[7] * y + h[8]
        return (h[0] * x + h[1] * y + h[2]) / w, (h[3] * x + h[4] * y + h[5]) / w

    def scale_at(self, x: float, y: float) -> float:
        """Pixels per metre near (x, y)."""
        return self.place(x, y, 0.0)[2]

    def screen_angle(self, x: float, y: float, a: float) -> float:
        """The screen angle (radians, y down) of the table direction ``a`` at (x, y)."""
        return self.place(x, y, a)[3]

    def place(self, x: float, y: float, a: float) -> tuple[float, float, float, float]:
        """(pixel x, pixel y, pixels per metre, screen angle of the table direction ``a``) at
        (x, y): :meth:`point`, :meth:`scale_at` and :meth:`screen_angle` in one go."""
        px, py = self.point(x, y)
        bx, by = self.point(x + 0.01, y)
        qx, qy = self.point(x + 0.01 * math.cos(a), y + 0.01 * math.sin(a))
        return px, py, math.hypot(bx - px, by - py) / 0.01, math.atan2(qy - py, qx - px)

    def reading(self) -> Reading:
        """How words read on the table from its near edge (:class:`~tabletop.drawing.reading.
        Reading`), taken at the table's centre: the one orientation every word of the view
        is turned by."""
        if self._reading is None:     # (asked several times a frame: the map never changes)
            self._reading = Reading.of(self.point, *self._centre)
        return self._reading
