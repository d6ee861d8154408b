"""The check measured live inside ``tabletop run`` (shown on the overlay), and the projector's
resolution recorded in the calibration file and checked against the view at start-up."""

import threading
import time

import numpy as np
import pytest

from calibration.files import (Calibration, CalibrationError, calibration_from_dict,
                               load_calibration, save_calibration)
from tabletop.cli import main
from tabletop.config import load_config
from tabletop.frames import Frame, Puck
from tabletop.live_check import LiveCheck
from tabletop.procam import check_inputs, check_lines, run_check, simulated_procam

VIEW = (1024, 600)
# The two pucks draw a short stroke now and then and rest at home 1.2-2 s in between: a check
# needs them still from the dark frame to the lit one.
CONFIG = ("table: {width: 1.2, height: 0.8}\n"
          "sources:\n  - {kind: synthetic_camera, name: camera, pucks: [1, 2], noise: 2,\n"
          "      performers: [{puck: 1, home: [0.3, 0.25], gestures: [stroke.csv]},\n"
          "                   {puck: 2, home: [0.85, 0.55], gestures: [stroke.csv]}]}\n"
          "engines: []\ncalibration: cal.yaml\n"
          "view: {size: [1024, 600], headless: true, calibration_check: true}\n")


def write_installation(tmp_path, shift_m: float = 0.0, projector_size=VIEW):
    """A config with the synthetic camera and the exact calibration of its simulated rig (the
    projector shifted ``shift_m`` metres along x after calibrating)."""
    path = tmp_path / "config.yaml"
    path.write_text(CONFIG)
    (tmp_path / "stroke.csv").write_text("t,dx,dy\n0,0,0\n0.4,0.04,0.01\n0.8,0.08,0\n")
    save_calibration(tmp_path / "cal.yaml", Calibration(np.eye(3)))
    cfg = load_config(path)
    rig = simulated_procam(cfg["sources"][0], cfg, VIEW)
    cam = rig.camera
    t2p = rig.projector.H @ np.array([[1, 0, shift_m], [0, 1, 0], [0, 0, 1.0]])
    save_calibration(tmp_path / "cal.yaml", Calibration(
        cam.image_to_table_homography(), t2p, cam.K, cam.dist, (cam.w, cam.h),
        projector_size=projector_size))
    return path


def frame_with(pucks):
    return Frame(seq=1, t=0.0, pucks=tuple(Puck(id=i, x=x, y=y, angle=a) for i, x, y, a in pucks))


@pytest.mark.parametrize("shift_m, verdict", [(0.0, "PASS"), (0.005, "FAIL")])
def test_live_check_measures_the_pucks_and_gives_overlay_lines(tmp_path, shift_m, verdict):
    """On the simulated rig (pucks in two corners and the middle): the check's lines, PASS with
    the true calibration, FAIL with the projector 5 mm off."""
    cfg = load_config(write_installation(tmp_path, shift_m))
    cal, detector, src = check_inputs(cfg, "config")
    rig = simulated_procam(src, cfg, VIEW)
    check = LiveCheck(rig, cal, detector)
    assert check.lines() == ["calibration check: waiting for the first measurement"]
    check.consume(frame_with([]))
    assert check.measured == 0 and "no puck tracked yet" in check.lines()[0]
    pucks = [(1, 0.07, 0.07, 0.0), (2, 1.13, 0.73, 1.0), (3, 0.6, 0.4, 2.0)]
    rig.pucks = pucks
    check.consume(frame_with(pucks))
    check.close()
    lines = check.lines()
    assert check.measured == 1, lines
    assert lines[-1].startswith(f"{verdict}: worst") and "over 3 pucks" in lines[-1]
    figures = [float(line.split(": ")[1].split()[0]) for line in lines[1:-1]]
    assert sorted(line.split()[1] for line in lines[1:-1]) == ["1", "2", "3"]
    if verdict == "PASS":
        assert max(figures) <= 2.0
    else:  # a projector 5 mm off is measured 5 mm off, give or take
        assert all(3.5 <= f <= 6.5 for f in figures), figures
    check.consume(frame_with(pucks))  # not due again for 10 s: no new measurement
    check.close()
    assert check.measured == 1


def test_run_shows_the_check_on_the_overlay(tmp_path):
    """``view.calibration_check: true``: the running view shows the crosses in place of the show,
    the running synthetic camera sees them through a simulated projector, and the view draws
    the check's lines on its overlay, which it switches on."""
    from tabletop.app import build_live
    inst = build_live(load_config(write_installation(tmp_path)), headless=True)
    check = next(s for s in inst.sinks if isinstance(s, LiveCheck))
    view = next(s for s in inst.sinks if s.name == "view")
    assert view.show_overlay and check.lines in view.notices
    check.every_s = 0.5  # the visitor's pucks move: check again until one stood still

    drawn: list[tuple] = []   # the first measured check the view drew

    def stop_after_the_check():  # once the view has drawn a measured check (60 s at most)
        # read from what the view drew, not compared with the check's newest lines: a check
        # every 0.5 s replaces them while the overlay (refreshed every 0.25 s) catches up
        for _ in range(1200):
            key = view.renderer._overlay_key
            heads = [i for i, line in enumerate(key) if line.startswith("calibration check at")]
            if heads and key[-1].startswith(("PASS", "FAIL")):
                drawn.append(tuple(key[heads[-1]:]))
                break
            time.sleep(0.05)
        inst.loop.stop.set()

    watcher = threading.Thread(target=stop_after_the_check)
    watcher.start()
    inst.loop.run(seconds=60.0)
    watcher.join()
    check.close()
    assert check.measured >= 1 and drawn, check.lines()
    # A later check may have begun while the loop stopped (every 0.5 s here): the verdict that
    # counts is the one the view drew.
    lines = drawn[0]
    assert lines[-1].startswith("PASS: worst"), lines
    # the last overlay the view drew: the stats, then the check
    overlay = view.renderer._overlay_key
    assert overlay[0].startswith("tick") and overlay[-1].startswith(("PASS", "FAIL",
                                                                     "NOT", "calib"))


def test_projector_size_is_recorded_and_old_files_still_load(tmp_path):
    cal = Calibration(np.eye(3), np.eye(3), projector_size=(1280, 720))
    save_calibration(tmp_path / "c.yaml", cal)
    assert load_calibration(tmp_path / "c.yaml").projector_size == (1280, 720)
    old = {k: v for k, v in cal.to_dict().items() if k != "projector_size"}
    assert calibration_from_dict(old).projector_size is None
    with pytest.raises(CalibrationError, match="c.yaml: projector_size: expected"):
        calibration_from_dict(dict(old, projector_size=[1280]), "c.yaml")


def test_a_view_of_another_size_than_the_calibrated_projector_is_refused(tmp_path, capsys):
    path = write_installation(tmp_path, projector_size=(1280, 720))
    code = main(["run", "--config", str(path), "--seconds", "0.2", "--headless"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1, err
    assert "cal.yaml: projector_size:" in err[0] and "1280x720" in err[0]
    assert "view.size is 1024x600" in err[0]
    code = main(["calibrate", "check", "--config", str(path)])
    assert code == 2 and "projector_size" in capsys.readouterr().err


def test_a_camera_of_another_size_than_the_calibrated_one_names_the_file_and_key(tmp_path,
                                                                                capsys):
    path = write_installation(tmp_path)
    cal = load_calibration(tmp_path / "cal.yaml")
    cal.image_size = (640, 480)
    save_calibration(tmp_path / "cal.yaml", cal)
    assert main(["calibrate", "check", "--config", str(path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "cal.yaml: image_size: the calibration is for 640x480" in err[0], err


def test_a_puck_moved_during_the_check_is_not_measured(tmp_path):
    """A hand moves puck 2 by 2 cm between the dark and the lit frame: its cross cannot be
    compared, so it is named and left out; the still pucks are measured."""
    cfg = load_config(write_installation(tmp_path))
    cal, detector, src = check_inputs(cfg, "config")
    rig = simulated_procam(src, cfg, VIEW)
    rig.pucks = [(1, 0.07, 0.07, 0.0), (2, 0.6, 0.4, 2.0)]
    grab, grabs = rig.grab, []

    def grab_with_a_hand():
        grabs.append(1)
        if len(grabs) == 2:  # the lit frame
            rig.pucks = [(1, 0.07, 0.07, 0.0), (2, 0.62, 0.4, 2.0)]
        return grab()

    rig.grab = grab_with_a_hand
    lines, passed = check_lines(run_check(rig, cal, detector), 2.0)
    assert passed and "puck 2 at 0.600, 0.400 m: moved during the check" in "\n".join(lines)
    assert lines[-1].startswith("PASS: worst") and "over 1 puck (" in lines[-1]
    rig.pucks = [(2, 0.6, 0.4, 2.0)]
    grabs.clear()
    lines, passed = check_lines(run_check(rig, cal, detector), 2.0)
    assert not passed and lines[-1].startswith("NOT MEASURED: every puck moved")
