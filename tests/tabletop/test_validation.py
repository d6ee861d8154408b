"""Bad configs found at start-up: one line naming the file and the key, a non-zero exit, and
nothing of OpenCV's or Python's internals (bad options: test_validation_cli.py; bad output
paths: test_validation_outputs.py)."""

import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

from calibration.files import Calibration, save_calibration
from tabletop.cli import main as tabletop

BASE = "sources:\n  - kind: scripted\n    pucks: [1, 2]\nview: {enabled: false}\n"


def run_config(tmp_path: Path, text: str, capfd, *extra: str) -> tuple[int, str]:
    cfg = tmp_path / "kiosk.yaml"
    cfg.write_text(text)
    code = tabletop(["run", "--config", str(cfg), "--seconds", "0.2", "--headless", *extra])
    return code, capfd.readouterr().err


def one_line(err: str) -> str:
    lines = [ln for ln in err.strip().splitlines() if ln.strip()]
    assert len(lines) == 1, err
    assert "Traceback" not in err and "internal error" not in err
    return lines[0]


def run_snippet(tmp_path: Path, snippet: str, capfd) -> tuple[int, str]:
    """``snippet`` run with the view off and a gesture ``g.csv`` beside it: the exit code and
    the one line said."""
    (tmp_path / "g.csv").write_text("t,dx,dy\n0,0,0\n1,0.1,0\n")
    code, err = run_config(tmp_path, snippet + "view: {enabled: false}\n", capfd)
    return code, one_line(err)


@pytest.mark.parametrize("content, words", [
    ("just: garbage: [\n", ["YAML syntax error"]),
    ("format: tabletop-calibration\nversion: 1\ncamera_to_table: [[1, 0], [0, 1]]\n",
     ["camera_to_table", "3x3"]),
    ("format: tabletop-calibration\nversion: 1\n"
     "camera_to_table: [[1, 2, 3], [2, 4, 6], [0, 0, 1]]\n", ["singular"]),
])
def test_a_bad_top_level_calibration_fails_at_start_up(tmp_path, capfd, content, words):
    (tmp_path / "calib.yaml").write_text(content)
    code, err = run_config(tmp_path, BASE + "calibration: calib.yaml\n", capfd)
    line = one_line(err)
    assert code == 2 and "kiosk.yaml: calibration:" in line and "calib.yaml" in line
    for w in words:
        assert w in line


def test_the_top_level_calibration_maps_the_view(tmp_path):
    from tabletop.app import build_live
    from tabletop.config import load_config

    t2p = np.array([[500.0, 20.0, 100.0], [-10.0, -480.0, 600.0], [0.0, 0.0, 1.0]])
    save_calibration(tmp_path / "calib.yaml",
                     Calibration(camera_to_table=np.diag([0.001, 0.001, 1.0]),
                                 table_to_projector=t2p))
    cfg_file = tmp_path / "c.yaml"
    cfg_file.write_text("sources: [{kind: scripted}]\ncalibration: calib.yaml\n"
                        "view: {headless: true, size: [640, 360]}\n")
    inst = build_live(load_config(cfg_file), headless=True)
    try:
        view = inst.sinks[0]
        np.testing.assert_allclose(view.renderer.map.H, t2p / t2p[2, 2])
        assert view.renderer.map.point(0.1, 0.2) == pytest.approx((154.0, 503.0))
    finally:
        inst.loop.close()


@pytest.mark.parametrize("snippet, key", [
    ("sources:\n  - kind: synthetic_camera\n    pucks: [1, 50]\n", "sources[0].pucks[1]"),
    ("sources:\n  - kind: synthetic_camera\n    pucks: []\n    performers:\n"
     "      - {puck: 99, home: [0.5, 0.5], gestures: [g.csv]}\n", "sources[0].performers[0].puck"),
    ("sources:\n  - kind: synthetic_camera\n    dictionary: DICT_4X4_100\n    pucks: [120]\n",
     "sources[0].pucks[0]"),
    ("sources:\n  - kind: scripted\ntracking:\n  puck_ids: {\"77\": 1}\n", "tracking.puck_ids.77"),
])
def test_marker_ids_outside_the_dictionary(tmp_path, capfd, snippet, key):
    code, line = run_snippet(tmp_path, snippet, capfd)
    assert code == 2 and f"kiosk.yaml: {key}: marker id" in line and "not in DICT_4X4" in line


@pytest.mark.parametrize("snippet, key", [
    ("sources:\n  - kind: synthetic_camera\n    pucks: [1]\n    performers:\n"
     "      - {puck: 1, home: [1.0e+300, 0.4], gestures: [g.csv]}\n",
     "sources[0].performers[0].home: [1e+300, 0.4] is off the 1.2 x 0.8 m table"),
    ("sources:\n  - kind: scripted\n    pucks: [1]\n    performers:\n"
     "      - {puck: 1, home: [0.5, 0.9], gestures: [g.csv]}\n",
     "sources[0].performers[0].home: [0.5, 0.9] is off"),
    ("sources:\n  - kind: scripted\nengines:\n  - {kind: touch_pose, at: [-0.1, 0.4]}\n",
     "engines[0].at: [-0.1, 0.4] is off"),
])
def test_places_off_the_table(tmp_path, capfd, snippet, key):
    code, line = run_snippet(tmp_path, snippet, capfd)
    assert code == 2 and f"kiosk.yaml: {key}" in line


@pytest.mark.parametrize("snippet, key, words", [
    ("sources:\n  - {kind: synthetic_camera, pucks: [1, 2, 1]}\n", "sources[0].pucks[2]",
     "puck 1 is also pucks[0]; give each puck once"),
    ("sources:\n  - kind: scripted\n    pucks: []\n    performers:\n"
     "      - {puck: 3, home: [0.5, 0.5], gestures: [g.csv]}\n"
     "      - {puck: 3, home: [0.2, 0.5], gestures: [g.csv]}\n", "sources[0].performers[1].puck",
     "puck 3 is also performers[0]; give each puck once"),
    ("sources: [{kind: scripted}]\nkiosk: {attract: {pucks: [4, 4]}}\n", "kiosk.attract.pucks[1]",
     "puck 4 is also pucks[0]; give each puck once"),
    # two sources moving one puck merged silently: one puck jumping between their paths
    ("sources:\n  - {kind: scripted, name: a, pucks: [1, 2]}\n"
     "  - {kind: scripted, name: b, pucks: [3, 2]}\n", "sources[1].pucks[1]",
     "puck 2 is also moved by sources[0].pucks[1] (a); two sources moving one puck merge"),
    ("sources:\n  - {kind: synthetic_camera, name: cam, pucks: [1, 2]}\n  - kind: scripted\n"
     "    name: hand\n    pucks: []\n    performers:\n"
     "      - {puck: 1, home: [0.5, 0.5], gestures: [g.csv]}\n",
     "sources[1].performers[0].puck", "puck 1 is also moved by sources[0].pucks[0] (cam)"),
    # a performer's speed [2, 0.5] ran with the scripted source raising in every tick (its
    # pucks never came); a scale_range without 1 stopped the build naming no key
    ("sources:\n  - kind: scripted\n    pucks: []\n    performers:\n"
     "      - {puck: 3, home: [0.5, 0.5], gestures: [g.csv], speed: [2, 0.5]}\n",
     "sources[0].performers[0].speed", "expected [least, most], each a number in [0.05, 20.0], "
     "got [2, 0.5]"),
    ("sources: [{kind: scripted, pucks: [1]}]\nengines:\n  - kind: mop\n    follower: "
     "{scale_range: [1.2, 1.8]}\n    performers: [{name: p, inputs: [{kind: puck, id: 1, "
     "features: [dx, dy]}]}]\n    characters: [{name: c, kind: creature, performer: p, "
     "actions: [{name: a, template: g.csv, motion: walk}]}]\n",
     "engines[0].follower.scale_range", "expected [least, most] holding 1, each a number in "
     "[0.05, 20.0], got [1.2, 1.8]"),
])
def test_a_puck_given_twice_or_a_range_the_wrong_way_round(tmp_path, capfd, snippet, key, words):
    code, line = run_snippet(tmp_path, snippet, capfd)
    assert code == 2 and f"kiosk.yaml: {key}: {words}" in line


@pytest.mark.parametrize("snippet, key, words", [
    ("studio: {markers: {record: 45, stop: 45}}\n", "studio.markers.stop",
     "marker 45 is also studio.markers.record"),
    ("studio: {markers: {keep: 2}}\n", "studio.markers.keep",
     "marker 2 is a puck of sources[0].pucks"),
])
def test_studio_markers_each_their_own(tmp_path, capfd, snippet, key, words):
    # one marker sending two commands would start and stop a take at once; a visitor's puck
    # used as a control marker would vanish from the characters' inputs
    code, err = run_config(tmp_path, BASE + snippet, capfd)
    line = one_line(err)
    assert code == 2 and f"kiosk.yaml: {key}: {words}" in line


def test_studio_marker_outside_the_dictionary(tmp_path, capfd):
    code, err = run_config(tmp_path, "sources: [{kind: synthetic_camera, pucks: [1]}]\n"
                           "view: {enabled: false}\nstudio: {markers: {next: 50}}\n", capfd)
    line = one_line(err)
    assert code == 2 and "studio.markers.next: marker id 50 is not in DICT_4X4_50" in line


@pytest.mark.parametrize("snippet, words", [
    ("kiosk: {backoff_s: [30, 0.1]}\n", "kiosk.backoff_s: the first wait 30 s is longer"),
    ("kiosk: {service_key: F13x}\n", "kiosk.service_key: 'F13x' is not a key name"),
    ("kiosk: {crash_log: notes.txt/crashes.log}\n", "kiosk.crash_log: {tmp}/notes.txt/crashes"
     ".log cannot be written: {tmp}/notes.txt is a file, not a folder"),
    ("kiosk: {status_file: notes.txt/a/status.json}\n", "kiosk.status_file: {tmp}/notes.txt/a/"
     "status.json cannot be written: {tmp}/notes.txt is a file, not a folder"),
    # a status written over the config replaced it with the status JSON, the config was gone
    ("kiosk: {status_file: kiosk.yaml}\n", "kiosk.status_file: {tmp}/kiosk.yaml is the config "
     "file itself"),
    ("kiosk: {log_file: .kiosk.yaml.last-good}\n", "kiosk.log_file: {tmp}/.kiosk.yaml.last-good "
     "is the config's last good copy"),
    ("kiosk: {status_file: s.json, log_file: s.json}\n", "kiosk.log_file: {tmp}/s.json is also "
     "kiosk.status_file"),
    # a file of the technician's (another config, notes): the status would replace it
    ("kiosk: {status_file: notes.txt}\n", "kiosk.status_file: {tmp}/notes.txt holds something "
     "else than a kiosk status (a JSON object); the status written there every second would "
     "replace it: name another file"),
    # a log of the technician's (notes, another program's): appended to, then rotated away
    ("kiosk: {log_file: notes.txt}\n", "kiosk.log_file: {tmp}/notes.txt holds something else "
     "than a log of the kiosk (it begins 'a file where a folder was meant'); its lines would be "
     "appended there and the file rotated away: name another file"),
    ("kiosk: {crash_log: notes.txt}\n", "kiosk.crash_log: {tmp}/notes.txt holds something "
     "else than a log of the kiosk (it begins 'a file where"),
])
def test_kiosk_settings_that_cannot_work(tmp_path, capfd, snippet, words):
    # (they ran: a back-off that never grew, a service key warned about only once the kiosk
    # was up, replaced by F12, a status file warned about at every heartbeat and a crash log
    # never written)
    (tmp_path / "notes.txt").write_text("a file where a folder was meant")
    words = words.format(tmp=tmp_path)
    code, err = run_config(tmp_path, BASE + snippet, capfd)
    assert code == 2 and f"kiosk.yaml: {words}" in one_line(err)


def test_the_kiosk_s_own_logs_are_its_own_and_a_backup_of_someone_else_s_is_not(tmp_path,
                                                                                capfd):
    """A log and crash log written by the kiosk's own writers (an earlier run, a restart) are
    taken up again; a file where a rotation would put the log's backup, holding something
    else, is refused as the log itself would be."""
    import logging

    from tabletop.kiosk.crash_log import append_crash, crash_entry
    from tabletop.kiosk.health import setup_log_file
    handler = setup_log_file(tmp_path / "k.log", max_bytes=10_000, backups=3)
    try:
        for i in range(700):   # rotated: k.log and k.log.1 .. k.log.3
            logging.getLogger("tabletop").info("line %d of an earlier run", i)
    finally:
        logging.getLogger("tabletop").removeHandler(handler)
        handler.close()
    append_crash(tmp_path / "c.log", crash_entry(1, "crashed", 2.5, 99, 1, ["boom"]), 10_000, 3)
    keys = "kiosk: {log_file: k.log, crash_log: c.log, log_max_bytes: 10000, log_backups: 3}\n"
    assert (tmp_path / "k.log.3").exists()
    assert run_config(tmp_path, BASE + keys, capfd)[0] == 0
    (tmp_path / "k.log.2").write_text("ssh keys of the gallery\n")
    code, err = run_config(tmp_path, BASE + keys, capfd)
    assert code == 2 and one_line(err).endswith(
        f"kiosk.yaml: kiosk.log_file: {tmp_path}/k.log.2, where the log's backup 2 goes, holds "
        "something else than a log of the kiosk (it begins 'ssh keys of the gallery'); a "
        "rotation would replace it: name another file")
    assert (tmp_path / "k.log.2").read_text() == "ssh keys of the gallery\n"


def test_a_last_good_copy_may_not_write_over_the_config_it_stands_for(tmp_path):
    # a copy kept by an earlier version: run for kiosk.yaml, its status would replace kiosk.yaml
    from tabletop.config import ConfigError, load_config
    kept = tmp_path / ".kiosk.yaml.last-good"
    kept.write_text(BASE + "kiosk: {status_file: kiosk.yaml}\n")
    with pytest.raises(ConfigError, match="kiosk.status_file: .*/kiosk.yaml is the config file"):
        load_config(kept)


def test_a_studio_folder_that_cannot_be_made(tmp_path, capfd):
    (tmp_path / "afile").write_text("a file, not a folder")
    code, err = run_config(tmp_path, BASE + "studio: {folder: afile/studio}\n", capfd)
    line = one_line(err)
    assert code == 2 and "kiosk.yaml: studio.folder: cannot hold the session log" in line
    assert "afile is not a folder" in line


def test_a_key_given_twice(tmp_path, capfd):
    code, err = run_config(tmp_path, BASE + "loop: {rate_hz: 30}\nloop: {rate_hz: 60}\n", capfd)
    line = one_line(err)
    assert code == 2 and "kiosk.yaml" in line and "'loop' is given twice" in line
    assert "line 6" in line


def test_a_sprite_that_is_not_an_image(tmp_path, capfd):
    (tmp_path / "lover.png").write_bytes(b"\x89PNG but not really")
    code, err = run_config(tmp_path, "sources: [{kind: scripted}]\n"
                           "view: {sprites: {lover: lover.png}}\n", capfd)
    line = one_line(err)
    assert code == 2 and "kiosk.yaml: view.sprites.lover: 'lover.png' is not an image" in line


def test_a_sprite_of_a_character_no_engine_makes(tmp_path, capfd):
    # (a misspelt name was never drawn, silently)
    import shutil
    shutil.copy(Path(__file__).resolve().parents[2] / "docs" / "board.png", tmp_path / "s.png")
    lover = Path(__file__).resolve().parents[2] / "behaviors" / "library" / "lover"
    code, err = run_config(tmp_path, "sources: [{kind: scripted}]\nengines:\n  - {kind: "
                           f"puppet_master, name: lover, behavior: {lover}, main: {{puck: 1}}}}\n"
                           "view: {enabled: false, sprites: {lovr: s.png}}\n", capfd)
    assert code == 2 and one_line(err).endswith("kiosk.yaml: view.sprites.lovr: no engine makes "
                                                "a character 'lovr' (characters: lover)")


def test_a_display_this_machine_does_not_have():
    import os
    os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
    import pygame
    from tabletop.schema import ConfigError
    from tabletop.display import check_display

    pygame.display.init()
    n = pygame.display.get_num_displays()
    assert check_display(n - 1) == n - 1
    with pytest.raises(ConfigError, match=f"view.display: display {n + 2} does not exist"):
        check_display(n + 2)


def test_a_recorder_folder_that_cannot_be_made(tmp_path, capfd):
    code, err = run_config(tmp_path, BASE + "recorder: {enabled: true, folder: /proc/x}\n", capfd)
    line = one_line(err)
    assert code == 2 and "kiosk.yaml: recorder.folder:" in line and "/proc/x" in line


def test_a_snapshot_folder_that_cannot_be_made(tmp_path, capfd):
    code, err = run_config(tmp_path, "sources: [{kind: scripted}]\n"
                           "view: {snapshot_every_s: 5, snapshot_folder: /proc/x}\n", capfd)
    line = one_line(err)
    assert code == 2 and "kiosk.yaml: view.snapshot_folder: /proc/x: cannot be used" in line


@pytest.fixture
def read_only_folder(tmp_path):
    """A folder that exists and takes no file: without write permission, or as root (whom
    permissions do not stop) a read-only tmpfs mounted on it."""
    folder = tmp_path / "ro"
    folder.mkdir()
    if os.geteuid() != 0:
        folder.chmod(0o555)
        yield folder
        folder.chmod(0o755)
        return
    if subprocess.run(["mount", "-t", "tmpfs", "-o", "ro,size=64k", "tmpfs", str(folder)],
                      capture_output=True).returncode != 0:
        pytest.skip("root without mount: no read-only folder to be had")
    yield folder
    subprocess.run(["umount", str(folder)], capture_output=True)


def test_a_snapshot_folder_that_takes_no_file(read_only_folder, tmp_path, capfd):
    # it ran, one warning, and never saved a snapshot
    code, err = run_config(tmp_path, "sources: [{kind: scripted}]\n"
                           f"view: {{snapshot_every_s: 5, snapshot_folder: {read_only_folder}}}\n",
                           capfd)
    line = one_line(err)
    assert code == 2 and f"view.snapshot_folder: {read_only_folder}: cannot be used" in line
    assert not list(read_only_folder.iterdir())


@pytest.mark.parametrize("value", [".inf", "-.inf", ".nan", "1e999"])
def test_numbers_must_be_finite(tmp_path, capfd, value):
    code, err = run_config(tmp_path, BASE + f"table: {{width: 1.2, height: {value}}}\n", capfd)
    assert code == 2 and "kiosk.yaml: table.height: expected a number" in one_line(err)


def cli(capfd, *args: str) -> tuple[int, str]:
    code = tabletop([str(a) for a in args])
    return code, capfd.readouterr().err


def test_a_file_that_is_no_config_is_named_in_one_short_line(tmp_path, capfd):
    """A CSV given as the config is one YAML string: the line says what it got, not all of it."""
    rows = "t,main_x,main_y\n" + "".join(f"{i / 40},{0.3 + 0.001 * i},0.4\n" for i in range(400))
    code, err = run_config(tmp_path, rows, capfd)
    line = one_line(err)
    assert code == 2 and "kiosk.yaml: <top>: expected a mapping" in line
    assert "got a string 't,main_x" in line and len(line) < 400


def test_a_key_yaml_1_1_reads_as_a_boolean_is_named_as_written(tmp_path, capfd):
    """``on:``, ``yes:`` as keys: named as written at their path (it said ``got a mapping
    {True: False}`` and ``view.True: unknown key``); as values they are still booleans."""
    sources = "sources: [{kind: scripted, pucks: [1]}]\n"
    code, err = run_config(tmp_path, sources + "view: {enabled: false, overlay: {on: false}}\n",
                           capfd)
    assert code == 2 and one_line(err).endswith(
        "kiosk.yaml: view.overlay: expected true or false, got a mapping {'on': False}")
    code, err = run_config(tmp_path, sources + "view: {enabled: false, yes: 1}\n", capfd)
    assert code == 2 and "kiosk.yaml: view.yes: unknown key (known keys here: " in one_line(err)
    code, err = run_config(tmp_path, sources + "view: {enabled: off, overlay: on}\n", capfd)
    assert code == 0, err


def test_an_empty_value_is_said_to_be_empty(tmp_path, capfd):
    # (it said "got nothing (null) None")
    code, err = run_config(tmp_path, BASE + "table:\n  width:\n", capfd)
    assert code == 2 and one_line(err).endswith(
        "kiosk.yaml: table.width: expected a number of metres in [0.05, 20.0], got nothing (an "
        "empty value, or null)")


def test_a_library_file_given_as_the_config_says_what_it_is(tmp_path, capfd):
    """A behaviour's behavior.yaml given as the config said only "format: unknown key", a
    MOP character's actions.yaml "actions: unknown key": each says what it is and where it
    goes, for run and calibrate check alike."""
    import shutil
    folder = tmp_path / "lover"
    shutil.copytree(Path(__file__).resolve().parents[2] / "behaviors" / "library" / "lover",
                    folder)
    actions = tmp_path / "actions.yaml"
    actions.write_text("actions:\n  - {name: a, template: a.csv, motion: walk}\n")
    for command in (["run", "--headless", "--seconds", "1"], ["calibrate", "check"]):
        code, err = cli(capfd, *command, "--config", folder / "behavior.yaml")
        assert code == 2 and f"{folder / 'behavior.yaml'}: a behaviour's behavior.yaml, not a " \
            f"config; an engine plays its folder (behavior: {folder})" in one_line(err), err
        code, err = cli(capfd, *command, "--config", actions)
        assert code == 2 and f"{actions}: a MOP character's actions file" in one_line(err), err


def test_a_puck_no_source_moves_is_warned_of(tmp_path):
    """An engine's puck that none of the config's listed-puck sources moves (puck 3 with a
    synthetic camera of pucks 1 and 2) started without a word: the character never moved.
    It is warned of at start, naming the key; a camera may bring any puck: no warning."""
    from tabletop.config import validate_config
    from tabletop.config_checks import unmoved_engine_pucks

    def said(source: dict, designer: dict) -> list[str]:
        return unmoved_engine_pucks(validate_config({"sources": [source], "engines": [
            {"kind": "puppet_master", "name": "lover", "main": {"puck": 3},
             "designer": designer}]}, "c.yaml", tmp_path))
    synthetic = {"kind": "synthetic_camera", "pucks": [1, 2]}
    assert said(synthetic, {"enabled": True, "main_puck": 3, "react_puck": 2}) == [
        f"engines[0].{k}: puck 3 is moved by no source (the sources move pucks 1, 2); what "
        "waits for it never moves" for k in ("main.puck", "designer.main_puck")]
    pucks = {"enabled": True, "main_puck": 1, "react_puck": 2}
    assert said({"kind": "scripted", "pucks": [1, 2, 3]}, pucks) == []
    assert said({"kind": "camera"}, pucks) == []


def test_an_engine_puck_missing_from_the_named_pucks(tmp_path, capfd):
    # the tracker shows only the named pucks: the character would never see puck 1
    lover = Path(__file__).resolve().parents[2] / "behaviors" / "library" / "lover"
    code, err = run_config(tmp_path, "sources: [{kind: scripted}]\nengines:\n  - {kind: "
                           f"puppet_master, name: lover, behavior: {lover}, main: {{puck: 1}}}}\n"
                           "tracking: {pucks: [2, 3]}\nview: {enabled: false}\n", capfd)
    assert code == 2 and one_line(err).endswith("kiosk.yaml: engines[0].main.puck: puck 1 is not "
                                                "in tracking.pucks [2, 3]; the tracker shows only "
                                                "those: add it there")
