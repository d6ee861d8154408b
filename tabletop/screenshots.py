"""Screenshots for the README, made by the installation itself.

Runs each shipped configuration headless (SDL's dummy driver) for a few seconds with snapshots
on, exactly as ``tabletop run --headless --seconds S`` with ``view.snapshot_every_s`` would, and
keeps its last snapshot as ``docs/screenshots/NAME.png``. Used by ``make screenshots``.

    python -m tabletop.screenshots [--seconds 6] [--out docs/screenshots]
"""

from __future__ import annotations

import argparse
import shutil
import tempfile
from pathlib import Path

from tabletop.app import build_live
from tabletop.config import load_config

ROOT = Path(__file__).resolve().parents[1]

SHOTS = {"default": ROOT / "config.yaml", "mop": ROOT / "examples" / "mop.yaml"}


def shoot(config: Path, seconds: float, out: Path, overlay: bool) -> Path:
    """Run ``config`` headless for ``seconds`` and copy its last snapshot to ``out``."""
    cfg = load_config(config)
    with tempfile.TemporaryDirectory() as tmp:
        cfg["view"] = dict(cfg["view"], headless=True, overlay=overlay, snapshot_every_s=1.0,
                           snapshot_folder=tmp)
        cfg["recorder"] = dict(cfg["recorder"], enabled=False)
        inst = build_live(cfg, headless=True)
        inst.loop.run(seconds=seconds)
        shots = sorted(Path(tmp).glob("snapshot-*.png"))
        if not shots:
            raise SystemExit(f"screenshots: {config}: no snapshot was written")
        out.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(shots[-1], out)
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=6.0)
    ap.add_argument("--out", type=Path, default=ROOT / "docs" / "screenshots")
    ap.add_argument("--overlay", action="store_true", help="keep the operator overlay on")
    ap.add_argument("--only", choices=sorted(SHOTS), help="one configuration only")
    args = ap.parse_args(argv)
    for name, config in SHOTS.items():
        if args.only and name != args.only:
            continue
        print(shoot(config, args.seconds, args.out / f"{name}.png", args.overlay))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
