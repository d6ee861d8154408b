"""Whether a calibration file's numbers can describe a real camera over a real table.

A file whose numbers are finite and well-shaped can still be absurd: a focal length of 1e300
pixels, a principal point a mile off the image, a k1 of 1e9 or -50 (the lens would fold the
image back on itself within the image), or a homography putting a kilometre of table in one
pixel. Loaded as they were, such files turned every marker into one point, NaN or nothing, with
no word why. Each function returns what is wrong ('' when nothing is), for a message that names
the file and the key.
"""

from __future__ import annotations

import math

import numpy as np

# The field of view a pinhole lens model may have across the image's short side, degrees: below
# 1 a camera 3 m above the table sees 5 cm of it; at 180 the model ends.
FOV_DEG = (1.0, 179.0)
# Table metres one camera pixel may cover at the image's centre: from a micrometre (a camera
# touching the table) to the largest table of config.yaml (20 m) in one pixel.
METRES_PER_PIXEL = (1e-6, 20.0)
MAX_IMAGE_PX = 16384   # the largest camera image config.yaml takes (camera resolution)
# Undistorted radii (normalised: tan of the angle off the axis) searched for the image's edge.
RADII = np.geomspace(1e-6, 1e4, 20_000)


def radial(distortion: np.ndarray, r: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """OpenCV's radial model: distorted radius r (1 + k1 r^2 + k2 r^4 + k3 r^6) / (1 + k4 r^2
    + k5 r^4 + k6 r^6) of each undistorted radius ``r`` (normalised), and that denominator."""
    k = np.zeros(8)
    k[:min(8, len(distortion))] = distortion[:8]
    r2 = r * r
    num = 1.0 + r2 * (k[0] + r2 * (k[1] + r2 * k[4]))
    den = 1.0 + r2 * (k[5] + r2 * (k[6] + r2 * k[7]))
    with np.errstate(all="ignore"):
        return r * num / den, den


def lens_problem(K: np.ndarray, distortion: np.ndarray,
                 image_size: tuple[int, int] | None) -> tuple[str, str]:
    """(key, what is wrong) for intrinsics that no real lens has over ``image_size`` (W, H)
    pixels (None: an image centred on the principal point); ('', '') when plausible.

    The principal point lies in the image; the radial model grows steadily from the centre out
    to half the image's short side (tangential terms, a few pixels, are left out) and reaches it
    within FOV_DEG. A model that folds back only beyond that, in the image's corners (a k3
    fitted without views there), is let through: it errs where few markers go, and a table
    that ran with it should not stop on it."""
    cx, cy = float(K[0, 2]), float(K[1, 2])
    w, h = image_size if image_size is not None else (2.0 * cx, 2.0 * cy)
    if not (0.0 <= cx <= w and 0.0 <= cy <= h and 0.0 < w <= MAX_IMAGE_PX
            and 0.0 < h <= MAX_IMAGE_PX):
        where = (f"the {w:g}x{h:g} image" if image_size is not None
                 else f"any camera's image (0 to {MAX_IMAGE_PX} px)")
        return ("intrinsics.camera_matrix",
                f"the principal point ({cx:g}, {cy:g}) px lies outside {where}")
    if abs(K[0, 1]) > K[0, 0]:
        return ("intrinsics.camera_matrix",
                f"the skew {K[0, 1]:g} px exceeds fx = {K[0, 0]:g} px (pixel rows sheared by "
                "over 45 degrees; OpenCV's calibration fits 0)")
    rho_edge = float(min(w / K[0, 0], h / K[1, 1])) / 2.0   # normalised, half the short side
    rd, den = radial(np.asarray(distortion, float), RADII)
    bad = ~np.isfinite(rd) | (den <= 0) | (np.diff(rd, prepend=0.0) <= 0)
    reach = np.flatnonzero(rd >= rho_edge)
    end = int(reach[0]) if reach.size else len(RADII)
    if np.any(bad[:end]):
        peak = float(rd[int(np.argmax(bad[:end]))])
        return ("intrinsics.distortion",
                f"{[float(v) for v in distortion]} folds the image back on itself "
                f"{max(peak, 0.0) / rho_edge:.0%} of the way from its centre to its long edges "
                "(no lens does; coefficients in OpenCV's order k1, k2, p1, p2, k3, ...?)")
    fov = 2.0 * math.degrees(math.atan(RADII[end])) if reach.size else 180.0
    lo, hi = FOV_DEG
    if not lo <= fov <= hi:
        return ("intrinsics",
                f"fx = {K[0, 0]:g}, fy = {K[1, 1]:g} px with this distortion give a {fov:.3g} "
                f"degree field of view across the image's short side; expected {lo:g} to "
                f"{hi:g} (focal lengths in pixels)")
    return "", ""


def scale_problem(camera_to_table: np.ndarray, centre_px: tuple[float, float]) -> str:
    """What is wrong with a camera -> table homography whose pixel at ``centre_px`` covers a
    table area outside METRES_PER_PIXEL (squared), or ''."""
    p = np.array([[centre_px[0], centre_px[1], 1.0], [centre_px[0] + 1.0, centre_px[1], 1.0],
                  [centre_px[0], centre_px[1] + 1.0, 1.0]])
    with np.errstate(all="ignore"):
        q = p @ np.asarray(camera_to_table, float).T
        xy = q[:, :2] / q[:, 2:]
        side = math.sqrt(abs(np.linalg.det(np.stack([xy[1] - xy[0], xy[2] - xy[0]]))))
    lo, hi = METRES_PER_PIXEL
    if math.isfinite(side) and lo <= side <= hi:
        return ""
    return (f"a pixel at the image's centre ({centre_px[0]:g}, {centre_px[1]:g}) covers "
            f"{side:.3g} m of table; expected {lo:g} to {hi:g} (table metres, not millimetres)")
