"""Camera images (as OpenCV gives them) as pygame surfaces, for the windows that show what a
camera sees: the live lens calibration (:mod:`tabletop.calibrate_ui`) and the projector steps
and live check (:mod:`tabletop.procam`, :mod:`tabletop.live_check`). pygame is imported when a
surface is made, so importing this module opens no display library."""

from __future__ import annotations

from typing import Any

import numpy as np


def image_surface(image: np.ndarray) -> Any:
    """``image`` (H, W) grey or (H, W, 3) BGR, as OpenCV gives it, as a pygame surface of
    (W, H) pixels."""
    import pygame
    rgb = np.repeat(image[..., None], 3, axis=2) if image.ndim == 2 else image[..., ::-1]
    return pygame.surfarray.make_surface(np.ascontiguousarray(rgb.swapaxes(0, 1)))
