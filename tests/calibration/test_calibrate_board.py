"""``tabletop calibrate board`` (and the pictures' sizes): the printed ChArUco board is OpenCV's
current one at its printed size and resolution; sizes that cannot work are refused in one line."""

import cv2
import numpy as np
import pytest

from calibration.files import save_calibration
from tests.calibration.test_calibrate_cli import refused, run


def test_board_writes_the_picture_and_its_size(tmp_path, capsys):
    code, stdout, _ = run(capsys, "board", "--out", tmp_path / "b.png", "--dpi", "150")
    import re
    w_mm, h_mm = map(float, re.search(r"([0-9.]+) x ([0-9.]+) mm", stdout).groups())
    assert code == 0 and w_mm == pytest.approx(300, abs=0.3) and h_mm == pytest.approx(220, abs=0.3)
    img = cv2.imread(str(tmp_path / "b.png"), cv2.IMREAD_GRAYSCALE)
    assert img.shape == (round(h_mm / 25.4 * 150), round(w_mm / 25.4 * 150))
    refused(capsys, "board", "--out", tmp_path / "b.png", "--dpi", "-3", words="--dpi")
    refused(capsys, "pattern", "--out", tmp_path / "p.png", "--size", "1280", words="--size")
    # the whole value is quoted, then the part that is wrong (it quoted only "0")
    refused(capsys, "pattern", "--out", tmp_path / "p.png", "--size", "0,720",
            words="--size '0,720': '0' must be a positive number")
    for size in ("1e9,720", "8193,720", "100,720"):   # 1e9 ran out of memory, naming nothing
        refused(capsys, "pattern", "--out", tmp_path / "p.png", "--size", size,
                words=f"--size {size}: from 160 to 8192 pixels each way")
    from calibration.files import Calibration
    save_calibration(tmp_path / "c.yaml", Calibration(np.eye(3)))
    refused(capsys, "projector", "--live", "--calibration", tmp_path / "c.yaml", "--out",
            tmp_path / "c.yaml", "--size", "20000,20000", words="--size 20000,20000: from 160")
    assert not (tmp_path / "p.png").exists()


def test_board_file_carries_its_print_resolution(tmp_path, capsys):
    # a PNG without its resolution prints at the viewer's 72 or 96 dpi: a 300 dpi board 3-4
    # times too large; with it, "100% scale" prints the squares at their size
    from PIL import Image
    code, stdout, _ = run(capsys, "board", "--out", tmp_path / "b.png", "--dpi", "150")
    assert code == 0
    with Image.open(tmp_path / "b.png") as im:
        dpi, width_px = im.info["dpi"], im.size[0]
    assert dpi == pytest.approx((150, 150), abs=0.05)
    assert width_px / dpi[0] * 25.4 == pytest.approx(300, abs=0.3)   # the printed width, mm


@pytest.mark.parametrize("spec, dpi", [(None, "300"), ("9x6:25:18:DICT_6X6_250", "100")])
def test_the_printed_board_is_opencvs_current_charuco_board(tmp_path, spec, dpi):
    """DESIGN: ``--board COLSxROWS:SQUARE_MM:MARKER_MM:DICTIONARY`` (default
    7x5:40:30:DICT_5X5_100) is OpenCV's ``CharucoBoard((COLS, ROWS), square, marker,
    dictionary)``, current pattern: an outside script's plain OpenCV board, made from the spec
    alone, finds every inner corner of the PNG (as a process writes it) where the printed
    squares put it, and a legacy board (which differs for an even number of rows) does not."""
    import subprocess
    import sys
    out = tmp_path / "board.png"
    args = ["--board", spec] if spec else []
    r = subprocess.run([sys.executable, "-m", "tabletop", "calibrate", "board", "--out", str(out),
                        "--dpi", dpi, *args], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0 and r.stderr == "", r.stderr
    size, square, marker, name = (spec or "7x5:40:30:DICT_5X5_100").split(":")
    cols, rows = map(int, size.split("x"))
    img = cv2.imread(str(out), cv2.IMREAD_GRAYSCALE)
    dictionary = cv2.aruco.getPredefinedDictionary(getattr(cv2.aruco, name))
    found = {}
    for legacy in (False, True):
        board = cv2.aruco.CharucoBoard((cols, rows), float(square) / 1e3, float(marker) / 1e3,
                                       dictionary)
        board.setLegacyPattern(legacy)
        corners, ids, _, _ = cv2.aruco.CharucoDetector(board).detectBoard(img)
        found[legacy] = (corners, ids)
    corners, ids = found[False]
    n = (cols - 1) * (rows - 1)
    assert ids is not None and sorted(ids.ravel().tolist()) == list(range(n))
    if rows % 2 == 0:
        assert found[True][1] is None or len(found[True][1]) < n / 2
    px = float(square) / 25.4 * float(dpi)                 # one square in pixels
    h, w = img.shape
    x0, y0 = (w - cols * px) / 2, (h - rows * px) / 2        # the board inside its margin
    for k, c in zip(ids.ravel(), corners.reshape(-1, 2)):
        expect = (x0 + (k % (cols - 1) + 1) * px, y0 + (k // (cols - 1) + 1) * px)
        assert np.hypot(*(c - expect)) <= 2.0, (k, c, expect)   # 2% of a square at 100 dpi
