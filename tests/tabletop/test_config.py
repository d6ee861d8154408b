"""config.yaml validation: every bad input names the file, the key path and what is expected."""

from pathlib import Path

import pytest

from tabletop.config import load_config
from tabletop.schema import ConfigError

GOOD = """\
table: {width: 1.2, height: 0.8}
sources:
  - kind: scripted
    name: visitor
    pucks: [1, 2]
"""


def write(tmp_path: Path, text: str) -> Path:
    p = tmp_path / "config.yaml"
    p.write_text(text)
    return p


def error_of(tmp_path: Path, text: str) -> str:
    with pytest.raises(ConfigError) as info:
        load_config(write(tmp_path, text))
    return str(info.value)


def test_good_config_fills_defaults(tmp_path):
    cfg = load_config(write(tmp_path, GOOD))
    assert cfg["loop"]["rate_hz"] == 60.0
    assert cfg["view"]["size"] == [1280, 720]
    assert cfg["sources"][0] == {"kind": "scripted", "name": "visitor", "pucks": [1, 2], "seed": 0,
                                 "performers": []}


def test_shipped_config_is_valid():
    cfg = load_config(Path(__file__).resolve().parents[2] / "config.yaml")
    assert cfg["sources"], "the default installation has a source"
    assert cfg["view"]["overlay"] is False, "visitors see the table, not the operator overlay"


def test_unknown_key_names_its_path(tmp_path):
    msg = error_of(tmp_path, GOOD + "view:\n  sise: [640, 480]\n")
    assert "config.yaml" in msg and "view.sise" in msg and "unknown key" in msg
    assert "size" in msg  # says what would be right


def test_unknown_key_inside_a_component(tmp_path):
    msg = error_of(tmp_path, GOOD.replace("pucks: [1, 2]", "pucks: [1, 2]\n    speed: 3"))
    assert "sources[0].speed" in msg and "unknown key" in msg


def test_a_misspelt_key_names_the_likely_one(tmp_path):
    """A misspelt key (a British "behaviour", a marker "recrod") listed every key of its
    mapping and left the designer to find the one meant among them."""
    msg = error_of(tmp_path, GOOD + "view:\n  sise: [640, 480]\n")
    assert msg.endswith("view.sise: unknown key (known keys here: " + msg.split(
        "known keys here: ")[1].split(")")[0] + "); did you mean 'size'?"), msg
    msg = error_of(tmp_path, GOOD + "studio:\n  markers: {recrod: 45}\n")
    assert "studio.markers.recrod: unknown key" in msg and \
        msg.endswith("did you mean 'record'?"), msg
    msg = error_of(tmp_path, GOOD + "view:\n  zzz: 1\n")
    assert msg.endswith(")"), msg             # nothing near it: the known keys alone


def test_wrong_type(tmp_path):
    msg = error_of(tmp_path, GOOD.replace("width: 1.2", "width: wide"))
    assert "table.width" in msg and "expected a number" in msg and "'wide'" in msg


def test_wrong_type_in_list_item(tmp_path):
    msg = error_of(tmp_path, GOOD.replace("pucks: [1, 2]", "pucks: [1, two]"))
    assert "sources[0].pucks[1]" in msg and "integer" in msg


def test_out_of_range(tmp_path):
    msg = error_of(tmp_path, GOOD + "loop: {rate_hz: 0}\n")
    assert "loop.rate_hz" in msg and "out of range" in msg and "[1.0, 1000.0]" in msg


def test_missing_referenced_file(tmp_path):
    msg = error_of(tmp_path, GOOD + "calibration: nowhere/calib.yaml\n")
    assert "calibration" in msg and "does not exist" in msg and "nowhere/calib.yaml" in msg


def test_referenced_file_resolved_next_to_config(tmp_path):
    import numpy as np
    from calibration.files import Calibration, save_calibration
    save_calibration(tmp_path / "calib.yaml",
                     Calibration(camera_to_table=np.diag([0.001, 0.001, 1])))
    cfg = load_config(write(tmp_path, GOOD + "calibration: calib.yaml\n"))
    assert cfg["calibration"] == tmp_path / "calib.yaml"


def test_yaml_syntax_error_names_the_line(tmp_path):
    msg = error_of(tmp_path, GOOD + "view:\n  size: [1280, 720\n  overlay: true\n")
    assert "YAML syntax error" in msg and "line " in msg
    line = int(msg.split("line ")[1].split(",")[0])
    assert 8 <= line <= 10  # the unclosed bracket is on line 8 of the file


@pytest.mark.parametrize("stray", ["\x07", "\x00\x00\x00"])
def test_a_control_character_is_named_by_line_and_column(tmp_path, stray):
    """A bell pasted from a terminal, or the NUL bytes a power cut leaves at a file's end:
    its line and column, not the reader's character offset in "<unicode string>"."""
    msg = error_of(tmp_path, GOOD + "view:\n  size: [1280, 720]" + stray + "\n")
    line = GOOD.count("\n") + 2
    assert f"at line {line}, column 20:" in msg, msg
    assert f"U+{ord(stray[0]):04X}" in msg and "<unicode string>" not in msg


def test_missing_required_key(tmp_path):
    msg = error_of(tmp_path, "table: {width: 1.0, height: 1.0}\n")
    assert "sources" in msg and "missing" in msg


def test_list_lengths_and_kinds_said_as_they_are(tmp_path):
    # (it said "a list (1 items) of a source mapping with 'kind' (camera, osc, replay, ...)":
    # no source is called replay)
    msg = error_of(tmp_path, "table: {width: 1.0, height: 1.0}\n")
    assert ("sources: missing; expected a list (at least 1 item) of a source mapping with "
            "'kind' (camera, osc, scripted, serial, synthetic_camera)") in msg
    msg = error_of(tmp_path, GOOD + "view: {size: [640]}\n")
    assert ("view.size: expected a list (2 items) of an integer number of pixels in [64, 8192], "
            "got 1 item") in msg


def test_an_exponent_without_a_point_says_how_to_write_it(tmp_path):
    # PyYAML (YAML 1.1) reads 1e3 as the text '1e3': "got a string '1e3'" alone puzzled
    msg = error_of(tmp_path, GOOD + "recorder: {max_mb: 1e3}\n")
    assert "recorder.max_mb" in msg and "got a string '1e3'" in msg and "write 1.0e+3" in msg
    assert "write 2.5e+2" in error_of(tmp_path, GOOD + "recorder: {max_mb: 2.5e2}\n")
    assert load_config(write(tmp_path, GOOD + "recorder: {max_mb: 1.0e+3}\n"))[
        "recorder"]["max_mb"] == 1000.0


def test_unknown_component_kind(tmp_path):
    msg = error_of(tmp_path, GOOD.replace("kind: scripted", "kind: telepathy"))
    assert "sources[0].kind" in msg and "telepathy" in msg and "scripted" in msg


def test_duplicate_component_names(tmp_path):
    text = GOOD + "  - kind: scripted\n    name: visitor\n"
    msg = error_of(tmp_path, text)
    assert "sources[1].name" in msg and "duplicate" in msg


def test_empty_file(tmp_path):
    assert "empty" in error_of(tmp_path, "")


def test_missing_config_file(tmp_path):
    with pytest.raises(ConfigError, match="not found"):
        load_config(tmp_path / "absent.yaml")


def test_a_main_character_no_engine_makes_names_the_file(tmp_path, capsys):
    """A build-time check (the character a reactor reacts to) names the file like the schema's."""
    from tabletop.cli import main as cli
    lover = Path(__file__).resolve().parents[2] / "behaviors" / "library" / "lover"
    path = write(tmp_path, GOOD + f"engines:\n  - kind: puppet_master\n    name: l\n"
                                  f"    behavior: {lover}\n    main: {{character: nobody}}\n")
    assert cli(["run", "--config", str(path), "--headless", "--seconds", "0.1"]) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and err[0].startswith(f"tabletop run: error: {path}: engines[0].main: ")
    assert "'nobody'" in err[0]


ROOT = Path(__file__).resolve().parents[2]


def _set(shipped: str, where: tuple, value: float) -> str:
    """The refusal of the shipped config ``shipped`` (under the repository) with ``value`` put
    at ``where`` (keys and list indexes)."""
    from tabletop.config import validate_config
    from tabletop.files import read_yaml
    data = read_yaml(ROOT / shipped)
    node = data
    for k in where[:-1]:
        node = node.setdefault(k, {}) if isinstance(k, str) else node[k]
    node[where[-1]] = value
    with pytest.raises(ConfigError) as info:
        validate_config(data, shipped, (ROOT / shipped).parent)
    return str(info.value)


@pytest.mark.parametrize("shipped, where, value, path", [
    ("examples/mop.yaml", ("engines", 0, "performers", 0, "inputs", 0, "rest_time"), 800,
     "engines[0].performers[0].inputs[0].rest_time"),
    ("config.yaml", ("sources", 0, "hands", "every_s"), 15000, "sources[0].hands.every_s"),
    ("config.yaml", ("kiosk", "idle_s"), 60000, "kiosk.idle_s"),
    ("config.yaml", ("engines", 0, "designer", "min_seconds"), 2000,
     "engines[0].designer.min_seconds"),
])
def test_a_time_given_in_milliseconds_is_refused_saying_seconds(shipped, where, value, path):
    """Times with no upper bound took milliseconds: a puck still for 800 s ended no gesture,
    a hand came over the table every four hours (found giving them in milliseconds)."""
    msg = _set(shipped, where, value)
    assert f"{shipped}: {path}: expected a number of seconds in [" in msg, msg
    assert msg.endswith(f"got {float(value)} (out of range; milliseconds given?)"), msg
    assert "\n" not in msg
    assert "milliseconds" not in _set(shipped, where, -1.0)   # too small: no such question


@pytest.mark.parametrize("where, value, said", [
    (("kiosk", "stall_s"), 30000, "kiosk.stall_s: expected a number of seconds in [0.5, 600.0], "
     "got 30000.0 (out of range; milliseconds given?)"),
    (("kiosk", "stall_s"), 1e7, "kiosk.stall_s: expected a number of seconds in [0.5, 600.0], "
     "got 10000000.0 (out of range)"),   # a thousandth is still too long: not milliseconds
    (("table", "width"), 1200, "table.width: expected a number of metres in [0.05, 20.0], "
     "got 1200.0 (out of range; millimetres given?)"),
    (("loop", "rate_hz"), 5000, "loop.rate_hz: expected a number of Hz in [1.0, 1000.0], "
     "got 5000.0 (out of range)"),
    (("sources", 0, "tilt_deg"), 90, "sources[0].tilt_deg: expected a number of degrees in "
     "[0.0, 40.0], got 90.0 (out of range)"),
    (("sources", 0, "resolution"), [10, 10], "sources[0].resolution[0]: expected an integer "
     "number of pixels in [64, 7680], got 10 (out of range) (and 1 more: "
     "sources[0].resolution[1]: expected an integer number of pixels in [64, 7680], got 10 "
     "(out of range))"),
])
def test_a_bounded_value_with_a_unit_is_refused_naming_its_unit(where, value, said):
    """stall_s, table.width, tilt_deg ... refused a value as "a number in [0.5, 600.0]": the
    unit (in the key's name or only in its documentation) is said, and a value a thousand
    times too large in seconds or metres is asked about as milliseconds or millimetres."""
    assert _set("config.yaml", where, value) == f"config.yaml: {said}"


def test_a_config_over_a_megabyte_is_refused_before_it_is_parsed(tmp_path):
    """A wrong file of tens of MB given as the config parsed for tens of seconds before its
    error (5 MB: 2.7 s of CPU). Over 1 MB (the largest shipped config is 4.9 kB) it is refused
    unread: the syntax error at its end is never reached."""
    import os
    import threading
    big = GOOD + "# a long comment\n" * 70_000 + "view: [unclosed\n"   # 1.2 MB
    msg = error_of(tmp_path, big)
    assert msg == (f"{tmp_path / 'config.yaml'}: {len(big):,} bytes, more than a config holds "
                   "(at most 1,048,576); not read (another file given?)"), msg
    assert "syntax" in error_of(tmp_path, big[-100_000:])   # shorter: parsed, said
    pipe = tmp_path / "pipe.yaml"
    os.mkfifo(pipe)
    writer = threading.Thread(target=pipe.write_text, args=(big,))
    writer.start()
    with pytest.raises(ConfigError) as info:
        load_config(pipe)
    writer.join()
    assert f"{len(big):,} bytes, more than a config holds" in str(info.value)
