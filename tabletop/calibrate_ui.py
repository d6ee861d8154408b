"""The live lens-calibration window: the camera image, the board corners found in it, and a
coverage map of where the views taken so far put corners (cells turn from red to green).

A second line names the corners and edges of the image still short of views. Space grabs the
current view (when enough corners are seen), Enter solves with the views taken,
Esc gives up. The views are kept in memory and, with ``save_dir``, written there as PNG.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np

from calibration.charuco import (MIN_CORNERS, REGION_VIEWS, CalibrationInputError, coverage,
                                 coverage_gaps, detect_board)
from tabletop.drawing.images import image_surface

CELLS = (8, 6)
# what to do when there is no display to open the window on
WITHOUT_WINDOW = "take views as files and use --images DIR"


def coverage_colours(counts: np.ndarray) -> np.ndarray:
    """(rows, cols, 3) RGB per coverage cell: red (no view yet), amber (one), green (two or
    more), so the technician sees which parts of the image still need views."""
    out = np.empty(counts.shape + (3,), np.uint8)
    out[counts == 0] = (220, 40, 40)
    out[counts == 1] = (230, 170, 30)
    out[counts >= 2] = (40, 200, 70)
    return out


class CaptureWindow:
    """The live window over camera ``device`` (an index or a path)."""

    def __init__(self, device: str, detector: Any, save_dir: str | None = None,
                 reader: Any = None) -> None:
        self.device, self.detector = device, detector
        self.save_dir = Path(save_dir) if save_dir else None
        self.reader = reader
        self.views: list[tuple[str, np.ndarray]] = []
        self.points: list[np.ndarray] = []

    def _open(self) -> Any:
        import cv2
        cap = cv2.VideoCapture(int(self.device) if str(self.device).isdigit() else self.device)
        if not cap.isOpened():
            raise CalibrationInputError(f"camera {self.device}: cannot be opened")
        return cap

    def grab_view(self, grey: np.ndarray) -> bool:
        """Keep ``grey`` as a view when the board is seen well enough; True when kept."""
        import cv2
        corners, ids = detect_board(self.detector, grey)
        if len(ids) < MIN_CORNERS:
            return False
        name = f"view-{len(self.views):03d}.png"
        self.views.append((name, grey.copy()))
        self.points.append(corners)
        if self.save_dir is not None:
            from tabletop.files import atomic_write_bytes
            ok, data = cv2.imencode(".png", grey)
            atomic_write_bytes(self.save_dir / name, data.tobytes())
        return True

    def draw(self, screen: Any, grey: np.ndarray, font: Any) -> None:
        """The camera image with its corners, the coverage map over it, and the help line."""
        import pygame
        corners, ids = detect_board(self.detector, grey)
        h, w = grey.shape
        surf = image_surface(grey)
        screen.blit(pygame.transform.smoothscale(surf, screen.get_size()), (0, 0))
        sx, sy = screen.get_width() / w, screen.get_height() / h
        colours = coverage_colours(coverage(self.points, (w, h), CELLS))
        cell_w, cell_h = screen.get_width() / CELLS[0], screen.get_height() / CELLS[1]
        shade = pygame.Surface((int(cell_w) + 1, int(cell_h) + 1), pygame.SRCALPHA)
        for r in range(CELLS[1]):
            for c in range(CELLS[0]):
                shade.fill((*colours[r, c], 60))
                screen.blit(shade, (int(c * cell_w), int(r * cell_h)))
        ok = len(ids) >= MIN_CORNERS
        for p in corners:
            pygame.draw.circle(screen, (60, 230, 90) if ok else (230, 80, 60),
                               (p[0] * sx, p[1] * sy), 4)
        text = (f"{len(self.views)} views   {len(ids)} corners now   Space: grab   "
                "Enter: solve   Esc: quit")
        screen.blit(font.render(text, True, (255, 255, 255), (0, 0, 0)), (8, 8))
        screen.blit(font.render(self.needs((w, h)), True, (255, 255, 255), (0, 0, 0)),
                    (8, 8 + font.get_linesize()))

    def needs(self, size: tuple[int, int]) -> str:
        """What the views so far still lack: the image's corners and edges with fewer than
        ``REGION_VIEWS`` views (``calibrate camera`` refuses those), or that they are covered."""
        gaps = coverage_gaps(self.points, size)
        if not gaps:
            return "every corner and edge of the image covered"
        return (f"still needed ({REGION_VIEWS} views each): "
                + ", ".join(f"{name} ({n})" for name, n in gaps))

    def run(self) -> list[tuple[str, np.ndarray]]:
        """The live loop; returns the views grabbed when Enter is pressed."""
        import cv2
        os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
        import pygame
        from tabletop.display import headless_needed, start_display, window_size
        if headless_needed(False):
            raise CalibrationInputError(f"no display: the live camera calibration needs a screen "
                                        f"(or {WITHOUT_WINDOW})")
        start_display(False, instead=WITHOUT_WINDOW)   # as the projector view opens it
        try:
            reader = self.reader or self._open()
        except BaseException:
            pygame.display.quit()
            raise
        pygame.font.init()
        size = window_size((1280, 720), tuple(pygame.display.get_desktop_sizes()[0]))
        screen = pygame.display.set_mode(size, pygame.RESIZABLE)
        pygame.display.set_caption("tabletop calibrate camera")
        font = pygame.font.Font(None, 26)
        try:
            while True:
                ok, frame = reader.read()
                if not ok:
                    raise CalibrationInputError(f"camera {self.device}: no frame")
                grey = cv2.cvtColor(frame, cv2.COLOR_BGR2GRAY) if frame.ndim == 3 else frame
                for ev in pygame.event.get():
                    if ev.type == pygame.QUIT or (ev.type == pygame.KEYDOWN
                                                  and ev.key == pygame.K_ESCAPE):
                        raise CalibrationInputError("stopped before solving")
                    if ev.type == pygame.KEYDOWN and ev.key == pygame.K_SPACE:
                        self.grab_view(grey)
                    if ev.type == pygame.KEYDOWN and ev.key == pygame.K_RETURN:
                        return self.views
                self.draw(screen, grey, font)
                pygame.display.flip()
        finally:
            reader.release()
            pygame.display.quit()
