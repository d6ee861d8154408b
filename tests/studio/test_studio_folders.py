"""How the status line names a studio folder (tabletop.studio.folders.named_folder)."""

import os

from tabletop.studio.folders import named_folder


def test_a_folder_is_named_relative_to_the_config_within_it_else_absolute(tmp_path):
    base = tmp_path / "show"
    assert named_folder(base / "studio", base) == os.path.join("studio", "")
    assert named_folder(base / "..x" / "studio", base) == os.path.join("..x", "studio", "")
    outside = tmp_path / "elsewhere"
    assert named_folder(outside, base) == os.path.join(str(outside), "")
