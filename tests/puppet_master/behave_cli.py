"""What the ``tabletop behave`` tests share: the CSV headers, the shipped library, the
demonstration and main path they start from (table metres, seconds), and the command."""

from pathlib import Path

from tabletop.cli import main as cli
from tabletop.files import write_csv
from tests.puppet_master import demos as pm_demos

DEMO_HEADER = ["t", "main_x", "main_y", "main_dir", "react_x", "react_y", "react_dir"]
MAIN_HEADER = ["t", "main_x", "main_y", "main_dir"]
SHIPPED = Path(__file__).resolve().parents[2] / "behaviors" / "library"


def write_files(d: Path):
    """A demonstration (``demo.csv``, 30 s) and a main path (``main.csv``, 12 s at 30 Hz, its
    times from 100 s: any time base) in ``d``; returns (d, the main path's rows)."""
    write_csv(d / "demo.csv", DEMO_HEADER,
              pm_demos.follow_behind(pm_demos.main_path(41, 30)).tolist())
    main = pm_demos.main_path(42, 12, rate_hz=30)
    main[:, 0] += 100.0                                   # any time base
    write_csv(d / "main.csv", MAIN_HEADER, main.tolist())
    return d, main


def behave(*args) -> int:
    return cli(["behave", *map(str, args)])
