"""Screenshots for the README, made by the installation itself.

Runs each shipped configuration headless (SDL's dummy driver) for some seconds with snapshots
on, exactly as ``tabletop run --headless --seconds S`` with ``view.snapshot_every_s`` would, and
keeps the liveliest snapshot of the run's second half as ``docs/screenshots/NAME.png``. Used by
``make screenshots``.

    python -m tabletop.screenshots [--seconds S] [--only NAME] [--out docs/screenshots]
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
from pathlib import Path

import numpy as np

os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")

import pygame  # noqa: E402

from tabletop.app import build_live  # noqa: E402
from tabletop.commands import positive_number  # noqa: E402
from tabletop.config import load_config  # noqa: E402
from tabletop.files import atomic_write_bytes  # noqa: E402
from tabletop.frames import InputError  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]

# name -> (configuration, seconds to run: long enough for the MOP performers to be mid-gesture)
SHOTS = {"default": (ROOT / "config.yaml", 8.0), "mop": (ROOT / "examples" / "mop.yaml", 24.0)}


def vividness(path: Path) -> float:
    """How much coloured light a snapshot holds (mean saturation x value): characters in play
    are vivid, resting ones calmer."""
    img = pygame.surfarray.pixels3d(pygame.image.load(str(path))).astype(np.int16)
    return float((img.max(axis=2) - img.min(axis=2)).mean())


def shoot(config: Path, seconds: float, out: Path, overlay: bool) -> Path:
    """Run ``config`` headless for ``seconds`` with a snapshot every half second and copy the
    liveliest of the second half (:func:`vividness`) to ``out``."""
    cfg = load_config(config)
    with tempfile.TemporaryDirectory() as tmp:
        cfg["view"] = dict(cfg["view"], headless=True, overlay=overlay, snapshot_every_s=0.5,
                           snapshot_folder=tmp, snapshot_overlay=overlay)
        cfg["recorder"] = dict(cfg["recorder"], enabled=False)
        inst = build_live(cfg, headless=True)
        inst.loop.run(seconds=seconds)
        shots = sorted(Path(tmp).glob("snapshot-*.png"))
        if not shots:
            raise SystemExit(f"screenshots: {config}: no snapshot was written")
        best = max(shots[len(shots) // 2:], key=vividness)
        out.parent.mkdir(parents=True, exist_ok=True)
        atomic_write_bytes(out, best.read_bytes())   # a README picture is whole or not there
    return out


def _seconds(text: str) -> float:
    try:
        return positive_number(text, "--seconds", "seconds")
    except InputError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=_seconds, default=None,
                    help="run time of each configuration (default: 8 s, MOP 24 s)")
    ap.add_argument("--out", type=Path, default=ROOT / "docs" / "screenshots")
    ap.add_argument("--overlay", action="store_true", help="keep the operator overlay on")
    ap.add_argument("--only", choices=sorted(SHOTS), help="one configuration only")
    args = ap.parse_args(argv)
    if args.out.exists() and not args.out.is_dir():
        ap.error(f"--out {args.out}: is a file; give the folder the pictures go into")
    try:
        args.out.mkdir(parents=True, exist_ok=True)   # refused now, not after the runs
    except OSError as exc:
        print(f"screenshots: error: {args.out}: {exc.strerror or exc}", file=sys.stderr)
        return 1
    for name, (config, seconds) in SHOTS.items():
        if args.only and name != args.only:
            continue
        try:
            print(shoot(config, args.seconds or seconds, args.out / f"{name}.png", args.overlay))
        except OSError as exc:
            print(f"screenshots: error: {exc.filename or args.out}: {exc.strerror or exc}",
                  file=sys.stderr)
            return 1
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
