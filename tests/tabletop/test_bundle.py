"""Self-contained configs: what a recording's header carries and how a replay unpacks it."""

import json
from pathlib import Path

import pytest

from tabletop import bundle
from tabletop.bundle import BundleError, extract, portable
from tabletop.config import load_config, validate_config

ROOT = Path(__file__).resolve().parents[2]


def write_config(folder: Path, outside: Path) -> Path:
    (folder / "gestures").mkdir(parents=True)
    (folder / "gestures" / "g.csv").write_text("t,dx,dy\n0,0,0\n1,0.1,0\n")
    outside.mkdir()
    (outside / "far.csv").write_text("t,dx,dy\n0,0,0\n1,0,0.1\n")
    cfg = folder / "kiosk.yaml"
    cfg.write_text(f"""
sources:
  - kind: scripted
    performers:
      - {{puck: 3, home: [0.5, 0.4], gestures: [gestures/g.csv, {outside / 'far.csv'}]}}
engines:
  - kind: puppet_master
    name: lover
    behavior: {ROOT / 'behaviors' / 'library' / 'lover'}
    designer: {{enabled: true, library: {outside / 'kept'}}}
view: {{enabled: false, snapshot_folder: snaps}}
""")
    return cfg


def test_paths_inside_keep_their_names_others_are_renamed_and_all_validate_again(tmp_path):
    cfg = load_config(write_config(tmp_path / "repo", tmp_path / "far"))
    written, files, external = portable(cfg.raw, cfg.refs)
    assert external == []
    perf = written["sources"][0]["performers"][0]
    assert perf["gestures"][0] == "gestures/g.csv"
    assert perf["gestures"][1].startswith("_external/") and perf["gestures"][1].endswith("/far.csv")
    assert written["engines"][0]["behavior"].startswith("_external/")
    assert written["engines"][0]["designer"]["library"].startswith("_outside/")  # an output
    assert written["view"]["snapshot_folder"] == "snaps"
    assert files["gestures/g.csv"]["text"] == "t,dx,dy\n0,0,0\n1,0.1,0\n"
    assert {n.rsplit("/", 1)[1] for n in files} == {"g.csv", "far.csv", "behavior.yaml",
                                                    "demonstration.csv"}
    # Unpacked anywhere, the config validates again and reads the same files.
    json.dumps(written)
    there = tmp_path / "there"
    extract(json.loads(json.dumps(files)), there)
    again = validate_config(written, "recorded", there)
    gestures = again["sources"][0]["performers"][0]["gestures"]
    assert [p.read_text() for p in gestures] == [
        (tmp_path / "repo" / "gestures" / "g.csv").read_text(),
        (tmp_path / "far" / "far.csv").read_text()]
    assert again["engines"][0]["designer"]["library"].is_relative_to(there)


def test_a_librarys_trash_and_unfinished_writes_are_not_embedded(tmp_path):
    """A designer's library kept inside the config's folder is embedded, but not what its
    studio deleted (.trash) or an atomic write left unfinished: every recording carried them."""
    cfg_path = write_config(tmp_path / "repo", tmp_path / "far")
    cfg_path.write_text(cfg_path.read_text().replace(str(tmp_path / "far" / "kept"), "kept"))
    kept = tmp_path / "repo" / "kept"
    for folder in ("lover", ".trash/lover.1", ".lover-2.x.tmp"):
        (kept / folder).mkdir(parents=True)
        (kept / folder / "demonstration.csv").write_text("t,main_x\n0,0\n")
    cfg = load_config(cfg_path)
    written, files, external = portable(cfg.raw, cfg.refs)
    assert written["engines"][0]["designer"]["library"] == "kept" and external == []
    assert [n for n in files if n.startswith("kept/")] == ["kept/lover/demonstration.csv"]


def test_a_file_too_large_stays_outside(tmp_path, monkeypatch):
    monkeypatch.setattr(bundle, "FILE_LIMIT", 10)
    cfg = load_config(write_config(tmp_path / "repo", tmp_path / "far"))
    written, files, external = portable(cfg.raw, cfg.refs)
    assert "sources[0].performers[0].gestures[0]" in external
    assert written["sources"][0]["performers"][0]["gestures"][0] == str(
        tmp_path / "repo" / "gestures" / "g.csv")
    assert "gestures/g.csv" not in files


@pytest.mark.parametrize("files, words", [
    ({"../evil.csv": {"text": "x"}}, "not a safe"),
    ({"/etc/evil": {"text": "x"}}, "not a safe"),
    ({"a.csv": {"text": "x", "sha256": "0" * 64}}, "checksum"),
    ({"a.bin": {"base64": "!!!"}}, "damaged"),
    ({"a.csv": "x"}, "expected a mapping"),
    (["a.csv"], "expected a mapping"),
])
def test_damaged_or_unsafe_files_are_refused(tmp_path, files, words):
    with pytest.raises(BundleError, match=words):
        extract(files, tmp_path)
    assert not any(tmp_path.iterdir())
