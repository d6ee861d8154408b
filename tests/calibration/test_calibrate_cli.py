"""``tabletop calibrate`` end to end on rendered images: every step writes the file atomically
with a .bak, thresholds refuse unless --force, and bad input is refused in one line always (the
printed board and its sizes: test_calibrate_board.py)."""

import cv2
import numpy as np
import pytest
import yaml

from calibration.files import load_calibration, save_calibration
from calibration.transforms import table_grid
from tabletop.calibration_scenes import board_views, lens_only, table_rig, write_views
from tabletop.cli import main
from tracking.rig import marker_layout


def run(capsys, *argv):
    code = main(["calibrate", *map(str, argv)])
    out, err = capsys.readouterr()
    return code, out, err


def refused(capsys, *argv, words=""):
    code, out, err = run(capsys, *argv)
    assert code == 2, (out, err)
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err and words in lines[0], err
    return lines[0]


@pytest.fixture(scope="module")
def views():
    return board_views(14, seed=2)  # two views in each corner of the image


def test_camera_from_a_folder(tmp_path, capsys, views):
    K, _, imgs = views
    write_views(tmp_path / "v", imgs)
    cv2.imwrite(str(tmp_path / "v" / "zz-blank.png"), np.full((480, 640), 128, np.uint8))
    (tmp_path / "v" / "notes.txt").write_text("not an image")
    code, out, err = run(capsys, "camera", "--images", tmp_path / "v", "--out", tmp_path / "c.yaml")
    assert code == 0, err
    assert "skipped zz-blank.png: 0 board corners found" in out
    assert "view-13.png:" in out and "RMS reprojection error" in out
    cal = load_calibration(tmp_path / "c.yaml", require_table=False)
    assert abs(cal.camera_matrix[0, 0] / K[0, 0] - 1) < 0.03
    assert cal.image_size == (640, 480) and cal.camera_to_table is None
    assert 0 < cal.reprojection_error["intrinsics_px"] < 1.0


def test_camera_refusals(tmp_path, capsys, views):
    _, _, imgs = views
    write_views(tmp_path / "few", imgs[:3])
    refused(capsys, "camera", "--images", tmp_path / "few", "--out", tmp_path / "c.yaml",
            "--force", words="3 usable views of the board")
    refused(capsys, "camera", "--images", tmp_path / "none", "--out", tmp_path / "c.yaml",
            words="no such folder")
    (tmp_path / "a.png").write_bytes(b"not a folder")      # was "no such folder" too
    refused(capsys, "camera", "--images", tmp_path / "a.png", "--out", tmp_path / "c.yaml",
            words=f"{tmp_path / 'a.png'}: is a file, expected a folder of images")
    (tmp_path / "empty").mkdir()
    refused(capsys, "camera", "--images", tmp_path / "empty", "--out", tmp_path / "c.yaml",
            words="holds no PNG or JPEG")
    (tmp_path / "bad").mkdir()
    (tmp_path / "bad" / "a.png").write_bytes(b"not a png")
    refused(capsys, "camera", "--images", tmp_path / "bad", "--out", tmp_path / "c.yaml",
            words="not an image OpenCV can read")
    refused(capsys, "camera", "--images", tmp_path / "few", "--out", tmp_path / "c.yaml",
            "--board", "7x5x40", words="--board")
    assert not (tmp_path / "c.yaml").exists()


def test_views_missing_the_image_corners_are_refused_unless_forced(tmp_path, capsys, views):
    """Six views (the centre, each corner once, the top edge): the corners where the lens bends
    most have one view each, the edges below and beside none of their own."""
    _, _, imgs = views
    write_views(tmp_path / "six", imgs[:6])
    out = tmp_path / "c.yaml"
    line = refused(capsys, "camera", "--images", tmp_path / "six", "--out", out,
                   words="fewer than 2 views put board corners in the image's top-left corner "
                         "(1 view)")
    assert "bottom-right corner (1 view)" in line and "--force" in line and not out.exists()
    code, stdout, _ = run(capsys, "camera", "--images", tmp_path / "six", "--out", out, "--force")
    assert code == 0 and "kept because of --force" in stdout and out.exists()


def test_camera_error_threshold_refused_unless_forced(tmp_path, capsys, views):
    """Views with a wobble no lens makes (a rolling shutter on a shaking camera: pixels shifted
    by up to 2.5 px) cannot fit one lens: the RMS is over 1 px."""
    _, _, imgs = views
    yy, xx = np.mgrid[0:480, 0:640].astype(np.float32)
    wobble = [cv2.remap(v, xx + 2.5 * np.sin(yy / 30 + i), yy + 2.5 * np.cos(xx / 30 + 2 * i),
                        cv2.INTER_LINEAR) for i, v in enumerate(imgs)]
    write_views(tmp_path / "mixed", wobble)
    out = tmp_path / "c.yaml"
    line = refused(capsys, "camera", "--images", tmp_path / "mixed", "--out", out,
                   words="is over 1.0 px")
    assert "--force" in line and not out.exists()
    code, stdout, _ = run(capsys, "camera", "--images", tmp_path / "mixed", "--out", out,
                          "--force")
    assert code == 0 and "kept because of --force" in stdout
    assert load_calibration(out, require_table=False).reprojection_error["intrinsics_px"] > 1.0


@pytest.fixture(scope="module")
def rig():
    return table_rig()


def test_table_pattern_projector_chain_keeps_entries_and_backups(tmp_path, capsys, rig):
    cam = rig.camera
    out = tmp_path / "cal.yaml"
    save_calibration(out, lens_only(rig))
    rig.pucks = marker_layout(cam.s.table)
    rig.show(None)
    cv2.imwrite(str(tmp_path / "markers.png"), rig.grab())
    markers = [a for i, x, y, _ in rig.pucks for a in ("--marker", f"{i}={x},{y}")]
    code, stdout, err = run(capsys, "table", "--image", tmp_path / "markers.png", "--out", out,
                            *markers)
    assert code == 0, err
    assert "table fit: residual" in stdout and "previous file kept" in stdout
    lens_backup = yaml.safe_load((tmp_path / "cal.yaml.bak").read_text())
    assert lens_backup["camera_to_table"] is None
    cal = load_calibration(out)
    grid = table_grid(cam.s.table, 13, 9)
    assert np.linalg.norm(cal.image_to_table(cam.project(grid)) - grid, axis=1).max() <= 0.001
    assert np.allclose(cal.camera_matrix, cam.K)  # the lens entry was kept

    code, stdout, _ = run(capsys, "pattern", "--out", tmp_path / "pattern.png",
                          "--size", "1280,720")
    assert code == 0 and "1280x720" in stdout
    rig.pucks = []
    rig.show(cv2.imread(str(tmp_path / "pattern.png"), cv2.IMREAD_GRAYSCALE))
    cv2.imwrite(str(tmp_path / "seen.png"), rig.grab())
    code, stdout, err = run(capsys, "projector", "--pattern", tmp_path / "pattern.png",
                            "--image", tmp_path / "seen.png", "--calibration", out, "--out", out,
                            "--table", "1.2,0.8")
    assert code == 0, err
    cal2 = load_calibration(out)
    landed = cal2.projector_to_table(rig.projector.table_to_projector(grid))
    assert np.linalg.norm(landed - grid, axis=1).max() <= 0.002
    assert np.allclose(cal2.camera_to_table, cal.camera_to_table)
    assert cal2.reprojection_error["camera_to_table_m"] \
        == cal.reprojection_error["camera_to_table_m"]
    assert load_calibration(tmp_path / "cal.yaml.bak").table_to_projector is None
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "cal.yaml", "cal.yaml.bak", "markers.png", "pattern.png", "seen.png"]

    # The pattern not visible (projector off): refused, the file untouched.
    rig.show(None)
    cv2.imwrite(str(tmp_path / "dark.png"), rig.grab())
    before = out.read_bytes()
    refused(capsys, "projector", "--pattern", tmp_path / "pattern.png", "--image",
            tmp_path / "dark.png", "--calibration", out, "--out", out, "--force",
            words="the projected pattern is not visible")
    refused(capsys, "projector", "--pattern", tmp_path / "markers.png", "--image",
            tmp_path / "seen.png", "--calibration", out, "--out", out,
            words="not a calibration pattern")
    assert out.read_bytes() == before


def _marker_image(tmp_path, rig):
    """The rig's camera image of the marker layout (a PNG) and an output path beside it."""
    rig.pucks = marker_layout(rig.camera.s.table)
    rig.show(None)
    img = tmp_path / "m.png"
    cv2.imwrite(str(img), rig.grab())
    return img, tmp_path / "cal.yaml"


def test_table_refusals(tmp_path, capsys, rig):
    img, out = _marker_image(tmp_path, rig)
    row = [a for i, x, y, _ in rig.pucks[:4] for a in ("--marker", f"{i}={x},{y}")]
    refused(capsys, "table", "--image", img, "--out", out, "--force", *row,
            words="lie on one line")  # ids 0-3 lie along the near edge
    refused(capsys, "table", "--image", img, "--out", out, *row[:6], words="at least 4")
    refused(capsys, "table", "--image", img, "--out", out, "--marker", "3:0.1,0.2", *row,
            words="expected ID=X,Y")
    refused(capsys, "table", "--image", img, "--out", out, "--marker", "40=0.1,0.2", *row,
            words="marker(s) 40 of DICT_4X4_50 not found")
    refused(capsys, "table", "--image", img, "--out", out, "--marker", "999=0.1,0.2", *row,
            words="--marker 999=...: marker id 999 is not in DICT_4X4_50 (ids 0 to 49)")
    refused(capsys, "table", "--image", tmp_path / "nope.png", "--out", out, *row,
            words="image not found")
    refused(capsys, "table", "--image", tmp_path, "--out", out, *row,   # was "image not found"
            words=f"{tmp_path}: is a folder, expected an image file")
    # Markers given at wrong positions: a residual over the threshold, kept only with --force.
    grid = [a for i, x, y, _ in rig.pucks for a in ("--marker", f"{i}={x},{y}")]
    grid[1] = "0=0.1,0.1"  # 2 cm off
    refused(capsys, "table", "--image", img, "--out", out, *grid, words="over 2.0 mm")
    assert not out.exists()
    code, stdout, _ = run(capsys, "table", "--image", img, "--out", out, *grid, "--force")
    assert code == 0 and "kept because of --force" in stdout and out.exists()


def test_check_from_a_config_passes_and_fails_when_the_projector_moved(tmp_path, capsys):
    """The shipped synthetic camera with its simulated projector: calibrated with the true
    geometry, the check passes; after the projector moved 5 mm it fails."""
    from tabletop.config import load_config
    from tabletop.procam import simulated_procam
    cfg_path = tmp_path / "config.yaml"
    cfg_path.write_text(
        "table: {width: 1.2, height: 0.8}\n"
        "sources:\n  - {kind: synthetic_camera, name: camera, pucks: [1, 2], noise: 2}\n"
        "engines: []\ncalibration: cal.yaml\nview: {size: [1024, 600]}\n")
    from calibration.files import Calibration
    save_calibration(tmp_path / "cal.yaml", Calibration(np.eye(3)))
    cfg = load_config(cfg_path)
    rig = simulated_procam(cfg["sources"][0], cfg, (1024, 600))
    cam = rig.camera
    truth = Calibration(cam.image_to_table_homography(), rig.projector.H, cam.K, cam.dist,
                        (cam.w, cam.h))
    save_calibration(tmp_path / "cal.yaml", truth)
    code, stdout, err = run(capsys, "check", "--config", cfg_path)
    assert code == 0, (stdout, err)
    assert stdout.strip().splitlines()[-1].startswith("PASS: worst")
    assert stdout.count("mm") >= 3
    moved = Calibration(truth.camera_to_table, truth.table_to_projector
                        @ np.array([[1, 0, 0.005], [0, 1, 0], [0, 0, 1.0]]), cam.K, cam.dist)
    save_calibration(tmp_path / "cal.yaml", moved)
    code, stdout, _ = run(capsys, "check", "--config", cfg_path)
    assert code == 1 and stdout.strip().splitlines()[-1].startswith("FAIL: worst")
    save_calibration(tmp_path / "cal.yaml", Calibration(truth.camera_to_table))
    # the file is named: the check may read another calibration than the one just made
    refused(capsys, "check", "--config", cfg_path,
            words=f"{tmp_path / 'cal.yaml'}: table_to_projector: null; run `tabletop calibrate "
                  "projector` first")


def test_live_steps_without_a_display_and_a_corrupt_file_are_refused(tmp_path, capsys,
                                                                      monkeypatch):
    monkeypatch.setenv("SDL_VIDEODRIVER", "dummy")
    refused(capsys, "camera", "--device", "0", "--out", tmp_path / "c.yaml",
            words="needs a screen")
    out = tmp_path / "c.yaml"
    out.write_text("format: tabletop-calibration\nversion: 1\ncamera_to_table: [1, 2]\n")
    refused(capsys, "projector", "--live", "--calibration", out, "--out", out,
            words="camera_to_table")
    assert out.read_text().endswith("[1, 2]\n")  # never overwritten


def test_an_image_of_another_resolution_than_the_lens_is_refused(tmp_path, capsys, rig):
    out = tmp_path / "cal.yaml"
    save_calibration(out, lens_only(rig))
    small = tmp_path / "small.png"
    cv2.imwrite(str(small), np.full((480, 640), 128, np.uint8))
    refused(capsys, "table", "--image", small, "--out", out, "--marker", "0=0,0",
            "--marker", "1=1,0", "--marker", "2=1,1", "--marker", "3=0,1",
            words="640x480 pixels, but the lens was calibrated at 1280x720")


def test_images_are_png_files_and_steps_are_named(tmp_path, capsys):
    # PNG bytes under a .jpg name, or no suffix at all, were written without a word
    for step, more in (("board", ()), ("pattern", ("--size", "1280,720"))):
        for name in ("b.jpg", "b"):
            line = refused(capsys, step, "--out", tmp_path / name, *more, words="ending in .png")
            assert line.startswith(f"tabletop calibrate {step}: error: --out ")
            assert not (tmp_path / name).exists()
    # the file a step writes into is checked before its work: a folder, or a file that is
    # not a calibration (the installation's config.yaml), is refused at once
    markers = [a for i in range(4) for a in ("--marker", f"{i}={i * 0.1},{i % 2 * 0.1}")]
    refused(capsys, "table", "--image", tmp_path / "none.png", *markers, "--out", tmp_path,
            words=f"--out {tmp_path}: is a folder; give a file name such as "
                  f"{tmp_path / 'calibration.yaml'}")
    (tmp_path / "config.yaml").write_text("table: {width: 1.2, height: 0.8}\n")
    line = refused(capsys, "table", "--image", tmp_path / "none.png", *markers,
                   "--out", tmp_path / "config.yaml", words="config.yaml: table: unknown key")
    assert line.startswith("tabletop calibrate table: error:") and "image not found" not in line
    # ... said as --out's file, which is no calibration (it read as a calibration file's key)
    assert f"--out {tmp_path / 'config.yaml'}: the file is there and is no calibration" in line


def test_table_takes_the_lens_from_another_file_with_calibration(tmp_path, capsys, rig):
    """DESIGN: ``table`` undistorts the pixels with the intrinsics of ``--calibration`` when it
    is given (else of the existing CALIB.yaml): a new file fitted with a lens kept elsewhere
    carries that lens and maps within a millimetre; without any lens the same markers fit
    pixels as they are, and the rig's distortion shows."""
    cam = rig.camera
    save_calibration(tmp_path / "lens.yaml", lens_only(rig))
    rig.pucks = marker_layout(cam.s.table)
    rig.show(None)
    cv2.imwrite(str(tmp_path / "markers.png"), rig.grab())
    markers = [a for i, x, y, _ in rig.pucks for a in ("--marker", f"{i}={x},{y}")]
    grid = table_grid(cam.s.table, 13, 9)
    out = tmp_path / "new.yaml"
    code, stdout, err = run(capsys, "table", "--image", tmp_path / "markers.png", "--out", out,
                            "--calibration", tmp_path / "lens.yaml", *markers)
    assert code == 0, err
    assert "no lens calibration" not in stdout and not (tmp_path / "new.yaml.bak").exists()
    cal = load_calibration(out)
    assert np.allclose(cal.camera_matrix, cam.K)
    assert np.linalg.norm(cal.image_to_table(cam.project(grid)) - grid, axis=1).max() <= 0.001
    bare = tmp_path / "bare.yaml"
    code, stdout, _ = run(capsys, "table", "--image", tmp_path / "markers.png", "--out", bare,
                          *markers, "--force")
    assert code == 0 and "no lens calibration" in stdout
    off = np.linalg.norm(load_calibration(bare).image_to_table(cam.project(grid)) - grid, axis=1)
    assert off.max() > 0.002
    refused(capsys, "table", "--image", tmp_path / "markers.png", "--out", out,
            "--calibration", tmp_path / "absent.yaml", *markers, words="absent.yaml")


def test_camera_takes_the_views_in_name_order_png_and_jpeg(tmp_path, capsys, views):
    """DESIGN: ``camera`` reads every PNG/JPEG in DIR in name order (whatever order they were
    written in, whatever the case of the suffix) and prints each view's error: the printed
    views are the folder's images in name order."""
    _, _, imgs = views
    folder = tmp_path / "mixed"
    folder.mkdir()
    names = [f"{k:02d}-view.{('png', 'JPG', 'jpeg')[k % 3]}" for k in range(len(imgs))]
    for k in reversed(range(len(imgs))):        # written last to first
        cv2.imwrite(str(folder / names[k]), imgs[k], [cv2.IMWRITE_JPEG_QUALITY, 98])
    (folder / "notes.txt").write_text("not a view")
    code, out, err = run(capsys, "camera", "--images", folder, "--out", tmp_path / "c.yaml")
    assert code == 0, err
    printed = [ln.split(":")[0].strip() for ln in out.splitlines()
               if ln.startswith("  ") and ln.rstrip().endswith(" px")]
    assert printed == sorted(names)


def test_a_marker_given_twice_is_named(tmp_path, capsys):
    """``--marker 0=... --marker 0=...``: the line names the id given twice (it said "a marker
    id is given twice", leaving the installer to find which of the markers)."""
    markers = ["--marker", "0=0.1,0.1", "--marker", "3=1.1,0.1", "--marker", "3=1.1,0.7",
               "--marker", "2=0.1,0.7"]
    refused(capsys, "table", "--image", tmp_path / "none.png", *markers,
            "--out", tmp_path / "c.yaml", words="--marker: marker id 3 is given twice")


@pytest.mark.parametrize("step", ["camera", "projector"])
def test_a_live_window_on_a_display_named_but_not_there_is_one_line(tmp_path, step):
    """The live windows open their display as the projector view does (tabletop.view's
    start_display): DISPLAY naming no X server, without XDG_RUNTIME_DIR (a system service),
    is one line naming the display. They opened it with a plain pygame.display.init: the
    camera window drew offscreen until the camera ran dry ("camera ...: no frame"), the
    projector step said "display 1: only 1 connected", both under libwayland's
    "error: XDG_RUNTIME_DIR is invalid or not set in the environment."."""
    import os
    import subprocess
    import sys
    video = tmp_path / "camera.avi"
    w = cv2.VideoWriter(str(video), cv2.VideoWriter_fourcc(*"MJPG"), 10, (320, 240))
    for i in range(10):
        w.write(np.full((240, 320, 3), 20 * i, np.uint8))
    w.release()
    from calibration.files import Calibration
    save_calibration(tmp_path / "c.yaml", Calibration(np.eye(3)))
    argv = {"camera": ["--device", str(video), "--out", str(tmp_path / "lens.yaml")],
            "projector": ["--live", "--device", str(video), "--calibration",
                          str(tmp_path / "c.yaml"), "--out", str(tmp_path / "c.yaml")]}[step]
    env = {k: v for k, v in os.environ.items()
           if k not in ("SDL_VIDEODRIVER", "WAYLAND_DISPLAY", "XDG_RUNTIME_DIR")}
    env.update(DISPLAY=":4242")   # no server has that number
    r = subprocess.run([sys.executable, "-X", "importtime", "-m", "tabletop", "calibrate", step,
                        *argv], capture_output=True, text=True, env=env, timeout=120)
    lines = r.stderr.strip().splitlines()
    loaded = {ln.rsplit("|", 1)[-1].strip() for ln in lines if ln.startswith("import time:")}
    assert "tabletop.display" in loaded and "tabletop.view" not in loaded, \
        "the projector view's drawing loaded for the live window's display (0.9 -> 0.4 CPU s)"
    err = [ln for ln in lines if not ln.startswith("import time:")]
    assert r.returncode == 2 and len(err) == 1, r.stderr
    assert err[0].startswith(f"tabletop calibrate {step}: error: the display (DISPLAY=:4242) "
                             "cannot be opened: SDL found only its offscreen driver; start "
                             "the display, or "), err


@pytest.mark.parametrize("display", ["x", "-1", "1.5", "²"])
def test_a_projector_display_that_is_no_number_is_named(tmp_path, capsys, display):
    # ("x" was an internal error: ValueError: invalid literal for int())
    from calibration.files import Calibration
    save_calibration(tmp_path / "c.yaml", Calibration(np.eye(3)))
    refused(capsys, "projector", "--live", "--display", display, "--calibration",
            tmp_path / "c.yaml", "--out", tmp_path / "c.yaml",
            words=f"--display {display!r}: expected a display number (0, 1, ...)")


def test_where_a_live_step_cannot_write_is_said_before_the_views(tmp_path, capsys,
                                                                 unprivileged):
    """--out and --save-views are written after minutes of live views (the solve, each
    grab): a place that takes no file is refused before the window opens. A read-only
    --out folder and a --save-views naming a file failed only then."""
    import os
    import subprocess
    import sys
    (tmp_path / "notes.txt").write_text("notes")
    refused(capsys, "camera", "--device", "0", "--save-views", tmp_path / "notes.txt",
            "--out", tmp_path / "c.yaml", words=f"--save-views {tmp_path / 'notes.txt'}: "
            f"nothing can be written there: {tmp_path / 'notes.txt'} is a file")
    shut = tmp_path / "shut"
    shut.mkdir()
    shut.chmod(0o555)
    env = {**os.environ, "DISPLAY": ":4242"}   # (the display is never reached)
    r = subprocess.run([*unprivileged, sys.executable, "-m", "tabletop", "calibrate", "camera",
                        "--device", "0", "--out", str(shut / "c.yaml")],
                       capture_output=True, text=True, env=env, timeout=120)
    assert r.returncode == 2 and r.stderr.strip().splitlines() == [
        f"tabletop calibrate camera: error: --out {shut / 'c.yaml'}: nothing can be written "
        "there: Permission denied"], r.stderr


def test_four_markers_swapped_or_mirrored_are_refused(tmp_path, capsys, rig):
    """Four markers fit any four positions exactly: two ids' positions swapped, or the table
    measured from its other end (mirrored), were saved with "residual 0.00 mm". A fold is
    refused; a mirrored table (every angle reversed) unless --force."""
    img, out = _marker_image(tmp_path, rig)
    w, h = rig.camera.s.table
    corners = [min(rig.pucks, key=lambda p: (p[1] - cx) ** 2 + (p[2] - cy) ** 2)
               for cx, cy in ((0, 0), (w, 0), (w, h), (0, h))]
    at = {i: (x, y) for i, x, y, _ in corners}
    ids = list(at)

    def markers(pos):
        return [a for i in ids for a in ("--marker", f"{i}={pos[i][0]},{pos[i][1]}")]
    swapped = {**at, ids[2]: at[ids[3]], ids[3]: at[ids[2]]}
    refused(capsys, "table", "--image", img, "--out", out, "--force", *markers(swapped),
            words="fold the table over itself (two markers' positions swapped?)")
    mirrored = {i: (w - x, y) for i, (x, y) in at.items()}
    refused(capsys, "table", "--image", img, "--out", out, *markers(mirrored),
            words="positions are mirrored")
    assert not out.exists()
    code, stdout, _ = run(capsys, "table", "--image", img, "--out", out, *markers(at))
    assert code == 0 and out.exists(), stdout
