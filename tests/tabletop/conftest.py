"""Fixtures of the tabletop tests."""

from pathlib import Path

import pytest


@pytest.fixture
def demo(tmp_path) -> Path:
    """A 3 s designer demonstration CSV at 40 Hz: both pucks drifting right."""
    rows = ["t,main_x,main_y,main_dir,react_x,react_y,react_dir"]
    rows += [f"{i / 40},{0.3 + 0.002 * i},0.4,0,{0.5 + 0.001 * i},0.45,0" for i in range(120)]
    p = tmp_path / "demo.csv"
    p.write_text("\n".join(rows) + "\n")
    return p
