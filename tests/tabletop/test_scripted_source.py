"""The scripted source's gesture files are read when its config is loaded, as a MOP template
is: a damaged one is refused naming the config key as well as the file and line (it was
refused at the build, in a kiosk's start too, naming the file alone), and the build takes the
rows read then instead of reading each file again."""

import pickle
import shutil
from collections import Counter
from pathlib import Path

import numpy as np
import pytest

from tabletop.config import load_config
from tabletop.files import read_csv
from tabletop.kiosk.attract import attract_performers
from tabletop import files
from tabletop.plugins import scripted
from tabletop.registry import BuildContext
from tabletop.schema import ConfigError
from tests.reads import counting_reads

ROOT = Path(__file__).resolve().parents[2]
GESTURES = ROOT / "examples" / "mop" / "gestures"


def test_a_damaged_gesture_file_is_refused_naming_its_key(tmp_path):
    shutil.copy(GESTURES / "line.csv", tmp_path / "line.csv")
    text = (GESTURES / "circle.csv").read_text()
    (tmp_path / "circle.csv").write_text(text[:-7])        # cut inside its last value
    cfg = tmp_path / "config.yaml"
    cfg.write_text("sources:\n  - kind: scripted\n    pucks: [1]\n    performers:\n"
                   "      - {puck: 2, home: [0.5, 0.4], gestures: [line.csv, circle.csv]}\n")
    with pytest.raises(ConfigError) as err:
        load_config(cfg)
    lines = len(text.splitlines())
    assert str(err.value).startswith(
        f"{cfg}: sources[0].performers[0].gestures[1]: {tmp_path / 'circle.csv'}: "
        f"line {lines}: column 'dy': ")


def _counting_reads(monkeypatch) -> Counter:
    return counting_reads(monkeypatch, files, "read_csv_lines")


def _line_and_circle(tmp_path: Path) -> Path:
    """A config whose performer draws copies of line.csv and circle.csv in ``tmp_path``."""
    for name in ("line.csv", "circle.csv"):
        shutil.copy(GESTURES / name, tmp_path / name)
    cfg_path = tmp_path / "config.yaml"
    cfg_path.write_text("sources:\n  - kind: scripted\n    pucks: [1]\n    performers:\n"
                        "      - {puck: 2, home: [0.5, 0.4], gestures: [line.csv, circle.csv]}\n")
    return cfg_path


def test_each_gesture_file_is_read_once_from_config_load_to_build(tmp_path, monkeypatch):
    cfg_path = _line_and_circle(tmp_path)
    reads = _counting_reads(monkeypatch)
    cfg = load_config(cfg_path)
    options = cfg["sources"][0]
    source = scripted.build(options, BuildContext((1.2, 0.8), 60.0, cfg, tmp_path))
    assert reads == {"line.csv": 1, "circle.csv": 1}
    # the config's value is still the file's path (a config loaded again equals it) ...
    gestures = options["performers"][0]["gestures"]
    assert gestures == [tmp_path / "line.csv", tmp_path / "circle.csv"]
    assert load_config(cfg_path) == cfg
    # ... and the performer draws the rows read then, as a pickled config would
    cols, data = read_csv(GESTURES / "circle.csv")
    circle = data[:, [cols.index("t"), cols.index("dx"), cols.index("dy")]]
    assert np.array_equal(source.performers[2].gestures[1], circle)
    assert np.array_equal(pickle.loads(pickle.dumps(gestures))[1].content, circle)


def test_attract_takes_the_templates_its_config_load_read(monkeypatch):
    cfg = load_config(ROOT / "examples" / "mop.yaml")
    reads = _counting_reads(monkeypatch)
    options = {"name": "attract", "pucks": [], "seed": 0,
               "performers": attract_performers(cfg, (1.2, 0.8))}
    source = scripted.build(options, BuildContext((1.2, 0.8), 60.0, cfg, ROOT))
    assert sorted(source.performers) == [1, 2]
    assert not reads         # each template was read once, by the config's load
    cols, data = read_csv(GESTURES / "circle.csv")
    circle = data[:, [cols.index("t"), cols.index("dx"), cols.index("dy")]]
    assert any(np.array_equal(g, circle) for g in source.performers[1].gestures)


def test_attract_reads_a_template_changed_since_the_config_load(tmp_path, monkeypatch):
    for name in ("line.csv", "circle.csv"):
        shutil.copy(GESTURES / name, tmp_path / name)
    cfg_path = tmp_path / "config.yaml"
    cfg_path.write_text(
        "sources: [{kind: scripted}]\nengines:\n  - kind: mop\n    performers:\n"
        "      - {name: hand, inputs: [{kind: puck, id: 1, features: [dx, dy]}]}\n"
        "    characters:\n      - name: lizard\n        kind: creature\n"
        "        performer: hand\n        actions:\n"
        "          - {name: line, template: line.csv, motion: walk}\n"
        "          - {name: circle, template: circle.csv, motion: curl}\n")
    cfg = load_config(cfg_path)
    shutil.copy(GESTURES / "zigzag.csv", tmp_path / "circle.csv")      # edited meanwhile
    reads = _counting_reads(monkeypatch)
    (performer,) = attract_performers(cfg, (1.2, 0.8))
    assert reads == {"circle.csv": 1}
    cols, data = read_csv(GESTURES / "zigzag.csv")
    zigzag = data[:, [cols.index("t"), cols.index("dx"), cols.index("dy")]]
    assert np.array_equal(performer["gestures"][1].content, zigzag)


def test_a_gesture_file_named_by_two_performers_is_read_once(tmp_path, monkeypatch):
    shutil.copy(GESTURES / "circle.csv", tmp_path / "circle.csv")
    cfg_path = tmp_path / "config.yaml"
    cfg_path.write_text("sources:\n  - kind: scripted\n    pucks: [1]\n    performers:\n"
                        "      - {puck: 2, home: [0.5, 0.4], gestures: [circle.csv]}\n"
                        "      - {puck: 3, home: [0.8, 0.4], gestures: [circle.csv]}\n")
    reads = _counting_reads(monkeypatch)
    cfg = load_config(cfg_path)
    assert reads == {"circle.csv": 1}
    assert load_config(cfg_path) == cfg


def test_a_gesture_file_that_is_also_a_template_is_read_once_per_load(monkeypatch):
    """examples/mop.yaml: the scripted performers draw the MOP templates' own files (each was
    read twice, by each reader)."""
    reads = counting_reads(monkeypatch, files, "read_text_within")     # (every CSV's text)
    cfg = load_config(ROOT / "examples" / "mop.yaml")
    names = {"circle.csv", "zigzag.csv", "figure_eight.csv", "line.csv", "wave.csv",
             "square.csv"}
    assert reads == {"mop.yaml": 1, **{name: 1 for name in names}}
    performer = cfg["sources"][0]["performers"][0]
    template = cfg["engines"][0]["characters"][0]["actions"][0]["template"]
    assert template.name == "circle.csv" and template.unchanged()
    cols, data = read_csv(GESTURES / "circle.csv")
    assert np.array_equal(template.content[1], data)
    assert np.array_equal(performer["gestures"][0].content,
                          data[:, [cols.index("t"), cols.index("dx"), cols.index("dy")]])


def test_a_gesture_changed_since_the_load_is_read_again_by_the_build(tmp_path, monkeypatch):
    """A curator saves a gesture file while the installation starts (after its config was
    loaded, before the build): the performer draws the file as saved, as the MOP engine
    follows a template changed in that window."""
    cfg_path = _line_and_circle(tmp_path)
    cfg = load_config(cfg_path)
    shutil.copy(GESTURES / "zigzag.csv", tmp_path / "circle.csv")      # saved meanwhile
    reads = _counting_reads(monkeypatch)
    source = scripted.build(cfg["sources"][0], BuildContext((1.2, 0.8), 60.0, cfg, tmp_path))
    assert reads == {"circle.csv": 1}
    cols, data = read_csv(GESTURES / "zigzag.csv")
    zigzag = data[:, [cols.index("t"), cols.index("dx"), cols.index("dy")]]
    assert np.array_equal(source.performers[2].gestures[1], zigzag)


def test_a_gesture_gone_bad_since_the_load_is_drawn_as_read_then(tmp_path, caplog):
    """A gesture file cut short between the config's load and the build: the start goes on
    with the rows read at the load, and says why."""
    cfg_path = _line_and_circle(tmp_path)
    cfg = load_config(cfg_path)
    text = (GESTURES / "circle.csv").read_text()
    (tmp_path / "circle.csv").write_text(text[:-7])        # cut inside its last value
    source = scripted.build(cfg["sources"][0], BuildContext((1.2, 0.8), 60.0, cfg, tmp_path))
    cols, data = read_csv(GESTURES / "circle.csv")
    circle = data[:, [cols.index("t"), cols.index("dx"), cols.index("dy")]]
    assert np.array_equal(source.performers[2].gestures[1], circle)
    assert "circle.csv" in caplog.text and "as it was read before" in caplog.text
