"""Crops of an image for region-of-interest detection: square boxes around predicted marker
centres, merged where that saves pixels, shelf-packed side by side into one mosaic, and
repeated detections of one marker from overlapping crops dropped. Units: image pixels."""

from __future__ import annotations

import math

import numpy as np

from tracking.markers import marker_centres

Box = tuple[int, int, int, int]  # x0, y0, x1, y1 (exclusive), pixels


def boxes_around(centres: np.ndarray, half_sizes: np.ndarray, width: int, height: int
                 ) -> list[Box]:
    """Square boxes (clipped to the ``width`` x ``height`` image) of half size ``half_sizes``
    around ``centres`` (N, 2), all in pixels."""
    out = []
    for (cx, cy), h in zip(np.asarray(centres, float), np.asarray(half_sizes, float)):
        if not (math.isfinite(cx) and math.isfinite(cy)):
            continue
        x0, y0 = max(0, int(math.floor(cx - h))), max(0, int(math.floor(cy - h)))
        x1, y1 = min(width, int(math.ceil(cx + h)) + 1), min(height, int(math.ceil(cy + h)) + 1)
        if x1 - x0 >= 8 and y1 - y0 >= 8:
            out.append((x0, y0, x1, y1))
    return out


def _area(b: Box) -> int:
    return (b[2] - b[0]) * (b[3] - b[1])


def merge_boxes(boxes: list[Box]) -> list[Box]:
    """Merge overlapping boxes into their bounding box wherever that costs no more pixels than
    the two crops apart, until no such pair is left (other overlaps stay as separate crops)."""
    merged = list(boxes)
    changed = True
    while changed:
        changed = False
        for i in range(len(merged)):
            for j in range(i + 1, len(merged)):
                a, b = merged[i], merged[j]
                if not (a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]):
                    continue
                u = (min(a[0], b[0]), min(a[1], b[1]), max(a[2], b[2]), max(a[3], b[3]))
                if _area(u) <= _area(a) + _area(b):
                    merged[i] = u
                    del merged[j]
                    changed = True
                    break
            if changed:
                break
    return merged


def pack_boxes(boxes: list[Box], gap: int) -> tuple[list[tuple[int, int]], tuple[int, int]]:
    """Shelf-pack boxes into a mosaic: each box's top-left (x, y) in the mosaic, and the mosaic's
    (width, height). ``gap`` pixels separate neighbouring crops."""
    if not boxes:
        return [], (0, 0)
    sizes = [(b[2] - b[0], b[3] - b[1]) for b in boxes]
    area = sum((w + gap) * (h + gap) for w, h in sizes)
    shelf_w = max(max(w for w, _ in sizes) + 2 * gap, int(math.sqrt(area) * 1.05))
    order = sorted(range(len(boxes)), key=lambda i: -sizes[i][1])
    places: list[tuple[int, int]] = [(0, 0)] * len(boxes)
    x, y, row_h, width = gap, gap, 0, 0
    for i in order:
        w, h = sizes[i]
        if x + w + gap > shelf_w and x > gap:
            x, y, row_h = gap, y + row_h + gap, 0
        places[i] = (x, y)
        x += w + gap
        row_h = max(row_h, h)
        width = max(width, x)
    return places, (width, y + row_h + gap)


def dedupe(ids: np.ndarray, corners: np.ndarray, tol_px: float = 3.0
           ) -> tuple[np.ndarray, np.ndarray]:
    """Drop repeated detections of one marker (same id, centres within ``tol_px``), as found
    in two overlapping crops; different places with one id are kept for the tracker to judge."""
    centres = marker_centres(corners)
    keep: list[int] = []
    for i in range(len(ids)):
        if not any(ids[j] == ids[i] and np.hypot(*(centres[j] - centres[i])) <= tol_px
                   for j in keep):
            keep.append(i)
    return ids[keep], corners[keep]
