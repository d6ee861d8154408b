"""Each kind of input file is refused, in one line naming it and its size, when it is larger
than such a file holds: before it is parsed (a wrong file of tens of MB was read and parsed
for seconds, up to the 128 MB every text input is capped at)."""

from __future__ import annotations

from pathlib import Path

import pytest

from tabletop import file_io
from tabletop.frames import InputError


def _grown(path: Path, start: str, size: int) -> Path:
    """``path`` holding ``start`` then NUL bytes up to ``size`` (a sparse file: cheap)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(start)
    with open(path, "r+b") as f:
        f.truncate(size)
    return path


def _demonstration(p: Path) -> None:
    from tabletop.library import read_demonstration
    read_demonstration(p)


def _behaviour(p: Path) -> None:
    from tabletop.library import read_description
    read_description(p.parent)


def _calibration(p: Path) -> None:
    from calibration.files import load_calibration
    load_calibration(p)


def _template(p: Path) -> None:
    from tabletop.plugins.mop_files import load_template
    load_template(p, ("dx", "dy"), 30.0)


def _actions(p: Path) -> None:
    from tabletop.plugins.mop_library import ActionsFile
    ActionsFile(p.parent.parent, p.parent.name).entries()


def _clip(p: Path) -> None:
    from behaviors.motion.deepmimic import load_motion
    load_motion(p)


def _json_clip(p: Path) -> None:
    from tabletop.plugins.mop_files import MotionLoader
    MotionLoader("creature", p.parent)(p.name)


def _sprite_sheet(p: Path) -> None:
    from tabletop.plugins.mop_rigs import make_rig
    make_rig({"kind": "sprite", "sheet": str(p)})


def _designed(p: Path) -> None:
    from behaviors.touch_pose.designed import read_take
    from behaviors.touch_pose.humanoid import Humanoid
    read_take(p, Humanoid())


@pytest.mark.parametrize("name, start, cap, kind, read", [
    ("demonstration.csv", "t,main_x,main_y,main_dir,react_x,react_y,react_dir\n",
     file_io.MAX_DEMONSTRATION_BYTES, "demonstration", _demonstration),
    ("pet/behavior.yaml", "format: tabletop-behavior\n", file_io.MAX_DESCRIPTION_BYTES,
     "behavior.yaml", _behaviour),
    ("calibration.yaml", "camera_matrix:\n", file_io.MAX_CALIBRATION_BYTES, "calibration",
     _calibration),
    ("wave.csv", "t,dx,dy\n", file_io.MAX_TEMPLATE_BYTES, "template CSV", _template),
    ("lib/bird/actions.yaml", "actions:\n", file_io.MAX_DESCRIPTION_BYTES, "actions.yaml",
     _actions),
    ("walk.txt", '{"Frames": [', file_io.MAX_CLIP_BYTES, "DeepMimic clip", _clip),
    ("hop.json", '{"frames": [', file_io.MAX_CLIP_BYTES, "clip", _json_clip),
    ("bird.json", '{"frames": [', file_io.MAX_CLIP_BYTES, "sprite sheet", _sprite_sheet),
    ("wave.json", '{"format": ', file_io.MAX_CLIP_BYTES, "designed action", _designed),
])
def test_an_input_larger_than_its_kind_holds_is_refused_unparsed(tmp_path, name, start, cap,
                                                                 kind, read):
    p = _grown(tmp_path / name, start, cap + 1)
    with pytest.raises(InputError) as info:
        read(p)
    assert str(info.value) == (f"{p}: {cap + 1:,} bytes, more than a {kind} holds (at most "
                               f"{cap:,}); not read (another file given?)")


def test_the_caps_hold_the_shipped_files_and_long_takes():
    """Measured: every shipped demonstration, template and behaviour is far below its cap; an
    hour's demonstration at 60 Hz written as the studio writes it (full precision) fits."""
    import numpy as np

    from tabletop.library import demonstration_csv
    root = Path(__file__).resolve().parents[2]
    for pattern, cap in (("behaviors/library/*/demonstration.csv",
                          file_io.MAX_DEMONSTRATION_BYTES),
                         ("behaviors/library/*/behavior.yaml", file_io.MAX_DESCRIPTION_BYTES),
                         ("examples/mop/gestures/*.csv", file_io.MAX_TEMPLATE_BYTES),
                         ("examples/mop/*.json", file_io.MAX_CLIP_BYTES)):
        sizes = [p.stat().st_size for p in root.glob(pattern)]
        assert sizes and max(sizes) < cap / 100, pattern
    rows = np.random.default_rng(0).uniform(-3.1, 3.1, (600, 7))   # 10 s at 60 Hz
    per_hour = len(demonstration_csv(rows)) * 360
    assert 20e6 < per_hour < file_io.MAX_DEMONSTRATION_BYTES / 2, per_hour


def test_a_csv_value_over_csvs_field_limit_is_refused_naming_its_line(tmp_path):
    """(it was an internal error: "field larger than field limit (131072)")"""
    from tabletop.files import FileFormatError, read_csv
    p = tmp_path / "wave.csv"
    p.write_text("t,dx,dy\n0,0,0\n" + "1" * 200_000 + ",0,0\n")
    with pytest.raises(FileFormatError) as info:
        read_csv(p)
    assert str(info.value) == (f"{p}: line 3: field larger than field limit (131072) (not a "
                               "CSV file?)")


def test_a_behavior_yaml_larger_than_one_holds_is_not_renamed_in(tmp_path):
    """A rename rewrites the name line of behavior.yaml; one over its cap is left as it is
    (it was read whole)."""
    from tabletop.library import write_name
    p = tmp_path / "pet" / "behavior.yaml"
    p.parent.mkdir()
    text = "name: pet\n" + "# a comment\n" * (file_io.MAX_DESCRIPTION_BYTES // 12)
    p.write_text(text)                 # (valid YAML: on its own it would be renamed in)
    assert write_name(p.parent, "cat") is None
    assert p.read_text() == text
