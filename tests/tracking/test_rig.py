"""The lens renderer's boards: its texture maps and its 2x2 pixel means are the plain
formulas' (a homography written out, numpy's mean) to the bit, so a faster form never moves the
rendered views the lens tests and bench/calibration solve."""

import cv2
import numpy as np

from calibration.transforms import apply_homography, homography_columns
from tracking.rig import LensRenderer, lens_camera, pixel_means


def test_a_board_view_is_the_plain_formulas_view_to_the_bit():
    size = (64, 48)
    K, dist = lens_camera(size)
    r = LensRenderer(K, dist, size, blur_sigma=0.0, noise_sigma=0.0)
    rng = np.random.default_rng(5)
    texture = (rng.random((60, 80)) * 255).astype(np.uint8)
    rvec, tvec = np.array([0.3, -0.2, 0.1]), np.array([-0.05, -0.04, 0.3])
    k = 0.002
    S = np.array([[k, 0.0, 0.5 * k], [0.0, k, 0.5 * k], [0.0, 0.0, 1.0]])
    R = cv2.Rodrigues(rvec)[0]
    H = np.linalg.inv(K @ np.column_stack([R[:, 0], R[:, 1], tvec]) @ S)

    x, y = r.ideal_x, r.ideal_y
    w_ = H[2, 0] * x + H[2, 1] * y + H[2, 2]
    written = np.column_stack([(H[0, 0] * x + H[0, 1] * y + H[0, 2]) / w_,
                               (H[1, 0] * x + H[1, 1] * y + H[1, 2]) / w_])
    assert np.array_equal(apply_homography(H, np.column_stack([x, y])), written)
    map_x, map_y = homography_columns(H, x, y)   # (the renderer's, on its contiguous columns)
    assert np.array_equal(map_x, written[:, 0]) and np.array_equal(map_y, written[:, 1])
    plain = written.astype(np.float32)

    w, h = size
    paper = texture.astype(np.float32) * (200.0 / 255.0) + 30.0
    tex = plain.reshape(2 * h, 2 * w, 2)
    fine = cv2.remap(paper, tex[..., 0], tex[..., 1], cv2.INTER_LINEAR,
                     borderMode=cv2.BORDER_CONSTANT, borderValue=90.0)
    want = np.clip(fine.reshape(h, 2, w, 2).mean(axis=(1, 3)), 0, 255).astype(np.uint8)
    got = r.view(texture, 1.0, k, rvec, tvec)
    assert np.array_equal(got, want)
    assert len(np.unique(got)) > 20      # the board fills the view: the pixels differ


def test_pixel_means_are_numpys_means_to_the_bit():
    samples = (np.random.default_rng(6).random((96, 128)) * 225 + 30).astype(np.float32)
    for n in (2, 4):
        want = samples.reshape(96 // n, n, 128 // n, n).mean(axis=(1, 3))
        got = pixel_means(samples, n)
        assert got.dtype == np.float32 and np.array_equal(got, want), n
