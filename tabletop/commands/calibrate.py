"""``tabletop calibrate``: the board, the lens, the table, the projector and the morning check.

Every step writes the calibration file (``calibration/files.py``) atomically, keeps the other
entries of an existing file and leaves the previous file beside it as ``CALIB.yaml.bak``. A
result whose error is over its threshold is refused with its figures unless ``--force``; bad
input (a missing folder, an unreadable image, a wrong ``--board`` or ``--marker``, collinear
markers, a pattern not found) is refused with one line whatever the flags.
"""

from __future__ import annotations

import argparse
import datetime as _dt
import math
from pathlib import Path
from typing import TYPE_CHECKING, Any

from tabletop.commands import positive_number
from tabletop.errors import InputError

if TYPE_CHECKING:
    import numpy as np

HELP = ("calibrate an installation: print the board, solve the camera lens, fit the table and "
        "the projector, and check that crosses land under the pucks")

IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg")
DEFAULT_BOARD = "7x5:40:30:DICT_5X5_100"  # calibration.charuco's default (no OpenCV for --help)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    sub = parser.add_subparsers(dest="step", metavar="STEP", required=True)
    out = "the calibration file written"
    board = "ChArUco board COLSxROWS:SQUARE_MM:MARKER_MM:DICTIONARY (default %(default)s)"
    p = sub.add_parser("board", help="draw the ChArUco board to print, and say its size")
    p.add_argument("--out", required=True, metavar="BOARD.png", help="the board image to print")
    p.add_argument("--board", default=DEFAULT_BOARD, metavar="SPEC", help=board)
    p.add_argument("--dpi", default="300", metavar="DPI", help="printer resolution, dots per inch "
                                                                "(default 300)")
    p = sub.add_parser("camera", help="solve the camera lens from views of the printed board")
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("--images", metavar="DIR", help="a folder of PNG/JPEG views of the board")
    src.add_argument("--device", metavar="N", help="a live camera: grab views with a key press")
    p.add_argument("--out", required=True, metavar="CALIB.yaml", help=out)
    p.add_argument("--board", default=DEFAULT_BOARD, metavar="SPEC", help=board)
    p.add_argument("--save-views", metavar="DIR", help="live: also save the grabbed views here")
    p.add_argument("--force", action="store_true", help="keep a result over the error threshold")
    p = sub.add_parser("table", help="fit camera -> table from markers at known positions")
    p.add_argument("--image", required=True, metavar="IMAGE",
                   help="a camera image of the markers on the table")
    p.add_argument("--marker", action="append", default=[], metavar="ID=X,Y",
                   help="a marker's id and the table position of its centre (metres)")
    p.add_argument("--out", required=True, metavar="CALIB.yaml", help=out)
    p.add_argument("--dictionary", default="DICT_4X4_50", metavar="NAME",
                   help="OpenCV dictionary of the markers (default %(default)s)")
    p.add_argument("--calibration", metavar="CALIB.yaml", help="take the lens from this file")
    p.add_argument("--force", action="store_true", help="keep a result over the error threshold")
    p = sub.add_parser("pattern", help="draw the image the projector shows for its calibration")
    p.add_argument("--out", required=True, metavar="PATTERN.png", help="the pattern image")
    p.add_argument("--size", required=True, metavar="W,H", help="its size, projector pixels")
    p = sub.add_parser("projector", help="fit table -> projector from camera images of the "
                                         "projected pattern (or live with --live)")
    p.add_argument("--pattern", metavar="PATTERN.png", help="the pattern the projector showed "
                                                            "(from calibrate pattern)")
    p.add_argument("--image", action="append", default=[], metavar="IMAGE",
                   help="a camera image of the projected pattern (repeatable)")
    p.add_argument("--calibration", required=True, metavar="CALIB.yaml",
                   help="the calibration with the camera -> table fit")
    p.add_argument("--out", required=True, metavar="CALIB.yaml", help=out)
    p.add_argument("--table", metavar="W,H", help="table size, metres: pattern corners beyond the "
                                                  "table's edge are not used (default: all used)")
    p.add_argument("--live", action="store_true", help="show the pattern fullscreen and grab "
                                                       "camera frames until the fit is stable")
    p.add_argument("--device", default="0", metavar="N", help="live: the camera index (default 0)")
    p.add_argument("--display", default="1", metavar="N", help="live: the projector display "
                                                                    "(default 1)")
    p.add_argument("--size", metavar="W,H", help="live: projector pixels (default: the "
                                                        "display's size)")
    p.add_argument("--force", action="store_true", help="keep a result over the error threshold")
    p = sub.add_parser("check", help="project a cross under every puck and measure how far "
                                     "each lands from its puck (mm)")
    p.add_argument("--config", default="config.yaml", metavar="FILE",
                   help="the installation's config (default %(default)s)")
    p.add_argument("--tolerance", default=None, metavar="MM",
                   help="pass when every cross lands this close (default 2 mm)")
    for name, step in sub.choices.items():   # errors name the step, as its usage errors do
        step.set_defaults(_prog=f"tabletop calibrate {name}")


class CalibrateError(InputError):
    """Bad ``calibrate`` input; one line."""


def main(args: argparse.Namespace) -> int:
    if args.step in ("camera", "table", "projector"):
        # the file a step will write into is checked before the work (a live lens solve takes
        # minutes of views): a folder, or an existing file that is not a calibration, is
        # refused now rather than after it
        from tabletop.commands import folder_takes_files, output_file
        output_file(args.out, "--out", CalibrateError, example="calibration.yaml")
        # (and where it cannot be written, nor the live views saved: said before the views)
        folder_takes_files(Path(args.out).absolute().parent, "--out", args.out, CalibrateError)
        if getattr(args, "save_views", None):
            folder_takes_files(Path(args.save_views), "--save-views", args.save_views,
                               CalibrateError)
        from calibration.files import CalibrationError
        try:
            load_existing(args.out)
        except CalibrationError as exc:   # (what is wrong in it, and that --out is the file)
            raise CalibrateError(f"--out {args.out}: the file is there and is no calibration "
                                 f"this step can add to ({exc}); give another file name, or "
                                 "the installation's calibration file") from None
    return {"board": board_main, "camera": camera_main, "table": table_main,
            "pattern": pattern_main, "projector": projector_main,
            "check": check_main}[args.step](args)


# ----------------------------------------------------------------------------------- helpers
def parse_pair(text: str, option: str, unit: str, integer: bool = False) -> tuple[Any, Any]:
    """``A,B`` of ``option`` as two positive numbers (integers when asked)."""
    parts = text.split(",")
    if len(parts) != 2:
        raise CalibrateError(f"{option} {text!r}: expected two numbers A,B ({unit})")
    a, b = (positive_number(p, f"{option} {text!r}:", unit, CalibrateError) for p in parts)
    if integer:
        if a != int(a) or b != int(b):
            raise CalibrateError(f"{option} {text!r}: expected whole numbers of {unit}")
        return int(a), int(b)
    return a, b


MIN_PROJECTOR_PX, MAX_PROJECTOR_PX = 160, 8192   # the pattern's least; view.size's most


def parse_projector_size(text: str) -> tuple[int, int]:
    """``--size W,H`` in projector pixels, each from MIN_PROJECTOR_PX to MAX_PROJECTOR_PX (the
    largest ``view.size``): a larger one could never be shown, and drawing it ran out of
    memory instead of naming the option."""
    size = parse_pair(text, "--size", "projector pixels", integer=True)
    if min(size) < MIN_PROJECTOR_PX or max(size) > MAX_PROJECTOR_PX:
        raise CalibrateError(f"--size {text}: from {MIN_PROJECTOR_PX} to {MAX_PROJECTOR_PX} "
                             "pixels each way")
    return size


def parse_marker(text: str) -> tuple[int, float, float]:
    """``ID=X,Y`` -> (id, x m, y m); one clear line when malformed."""
    usage = f"--marker {text!r}: expected ID=X,Y (marker id, table metres), e.g. 3=0.1,0.7"
    try:
        mid, xy = text.split("=")
        x, y = (float(v) for v in xy.split(","))
        marker_id = int(mid)
    except ValueError:
        raise CalibrateError(usage) from None
    if marker_id < 0 or not (math.isfinite(x) and math.isfinite(y)):
        raise CalibrateError(usage)
    return marker_id, x, y


def write_png(path: str | Path, option: str, image: np.ndarray, dpi: float | None = None) -> None:
    """``image`` written atomically to ``path`` (the ``option``'s file, which must end in .png:
    a .jpg would hold PNG bytes, and JPEG's blur would move the corners), with ``dpi`` in the
    file's pHYs chunk so that printing at 100% scale prints at that resolution (without it a
    print dialog assumes 72 or 96 dpi and the board comes out 3-4 times too large)."""
    import struct
    import zlib

    import cv2
    from tabletop.commands import png_output
    from tabletop.files import atomic_write_bytes
    png_output(path, option, CalibrateError)
    ok, data = cv2.imencode(".png", image)
    png = data.tobytes()
    if dpi is not None:   # pHYs: pixels per metre on x and y, unit 1 (metre), after IHDR
        body = b"pHYs" + struct.pack(">IIB", round(dpi / 0.0254), round(dpi / 0.0254), 1)
        chunk = struct.pack(">I", 9) + body + struct.pack(">I", zlib.crc32(body))
        end = 8 + 8 + 13 + 4                      # signature, IHDR length + type, data, CRC
        png = png[:end] + chunk + png[end:]
    atomic_write_bytes(path, png)


def read_image(path: str | Path) -> np.ndarray:
    """An image file as 8-bit grey; one line when missing or unreadable."""
    import cv2
    p = Path(path)
    if p.is_dir():
        raise CalibrateError(f"{p}: is a folder, expected an image file")
    if not p.is_file():
        raise CalibrateError(f"{p}: image not found")
    img = cv2.imread(str(p), cv2.IMREAD_GRAYSCALE)
    if img is None:
        raise CalibrateError(f"{p}: not an image OpenCV can read")
    return img


def image_files(folder: str) -> list[Path]:
    """Every PNG/JPEG in ``folder``, in name order; one line when there is none."""
    p = Path(folder)
    if p.exists() and not p.is_dir():
        raise CalibrateError(f"{p}: is a file, expected a folder of images")
    if not p.is_dir():
        raise CalibrateError(f"{p}: no such folder")
    files = sorted(f for f in p.iterdir() if f.suffix.lower() in IMAGE_SUFFIXES)
    if not files:
        raise CalibrateError(f"{p}: the folder holds no PNG or JPEG images")
    return files


def load_existing(path: str | Path) -> Any:
    """The calibration in ``path`` (lens-only files accepted), or None when there is none."""
    from calibration.files import load_calibration
    return load_calibration(path, require_table=False) if Path(path).exists() else None


def save(out: str, **entries: Any) -> None:
    """Write ``entries`` into the calibration file ``out``, keeping its other entries and the
    previous file as ``out.bak``."""
    from calibration.files import Calibration, save_with_backup
    old = load_existing(out)
    errors = dict(old.reprojection_error) if old is not None else {}
    errors.update(entries.pop("errors", {}))
    base = {} if old is None else dict(
        camera_to_table=old.camera_to_table, table_to_projector=old.table_to_projector,
        camera_matrix=old.camera_matrix, distortion=old.distortion, image_size=old.image_size,
        projector_size=old.projector_size)
    base.update(entries)
    base.setdefault("camera_to_table", None)
    cal = Calibration(reprojection_error=errors,
                      date=_dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
                      **base)
    backup = save_with_backup(out, cal)
    print(f"saved {out}" + (f" (previous file kept as {backup})" if backup else ""))


def same_size(calibration: Any, image: np.ndarray, name: Any) -> None:
    """Refuse an image whose size differs from the one the lens was calibrated at."""
    size = None if calibration is None else calibration.image_size
    h, w = image.shape[:2]
    if size is not None and calibration.camera_matrix is not None and tuple(size) != (w, h):
        raise CalibrateError(f"{name}: {w}x{h} pixels, but the lens was calibrated at "
                             f"{size[0]}x{size[1]}; use the camera at that resolution")


def refuse_or_force(over: bool, message: str, force: bool) -> None:
    """Refuse a result over its threshold (one line) unless ``force``."""
    if over and not force:
        raise CalibrateError(f"{message}; refused (--force keeps it anyway)")
    if over:
        print(f"warning: {message}; kept because of --force")


# ------------------------------------------------------------------------------------- steps
def board_main(args: argparse.Namespace) -> int:
    from calibration.charuco import board_image, parse_board
    spec = parse_board(args.board)
    dpi = positive_number(args.dpi, "--dpi", "dots per inch", CalibrateError)
    img, (w_mm, h_mm) = board_image(spec, dpi)
    write_png(args.out, "--out", img, dpi)
    print(f"wrote {args.out}: {spec.cols}x{spec.rows} squares of {spec.square_m * 1e3:g} mm, "
          f"markers {spec.marker_m * 1e3:g} mm ({spec.dictionary}); print at {dpi:g} dpi, "
          f"100% scale: {w_mm:.1f} x {h_mm:.1f} mm. Measure a printed square: it must be "
          f"{spec.square_m * 1e3:g} mm")
    return 0


def camera_main(args: argparse.Namespace) -> int:
    import cv2
    from calibration.charuco import MIN_CORNERS, MIN_VIEWS, detect_board, make_board, parse_board
    spec = parse_board(args.board)
    board = make_board(spec)
    detector = cv2.aruco.CharucoDetector(board)
    if args.device is not None:
        from tabletop.procam import capture_views
        images = capture_views(args.device, detector, args.save_views)
    else:
        images = [(f.name, read_image(f)) for f in image_files(args.images)]
    views, names, size = [], [], None
    for name, img in images:
        h, w = img.shape[:2]
        if size is not None and size != (w, h):
            print(f"skipped {name}: {w}x{h}, the other views are {size[0]}x{size[1]}")
            continue
        corners, ids = detect_board(detector, img)
        if len(ids) < MIN_CORNERS:
            print(f"skipped {name}: {len(ids)} board corners found, {MIN_CORNERS} needed")
            continue
        size = (w, h)
        views.append((corners, ids))
        names.append(name)
    if len(views) < MIN_VIEWS:
        raise CalibrateError(f"{len(views)} usable views of the board ({spec.text()}); at "
                             f"least {MIN_VIEWS} are needed, from all over the image")
    from calibration.charuco import MAX_RMS_PX, REGION_VIEWS, coverage_gaps, solve_lens
    solve = solve_lens(board, views, size)
    for name, e in zip(names, solve.view_rms_px):
        print(f"  {name}: {e:.3f} px")
    K = solve.camera_matrix
    print(f"RMS reprojection error {solve.rms_px:.3f} px over {len(views)} views"
          + (f" ({solve.outliers} stray corners left out)" if solve.outliers else "")
          + f"; focal {K[0, 0]:.1f}, {K[1, 1]:.1f} px; principal point {K[0, 2]:.1f}, "
          f"{K[1, 2]:.1f} px")
    refuse_or_force(solve.rms_px > MAX_RMS_PX, f"RMS reprojection error {solve.rms_px:.3f} px "
                    f"is over {MAX_RMS_PX} px", args.force)
    gaps = coverage_gaps([c for c, _ in views], size)
    where = ", ".join(f"{name} ({n} view{'' if n == 1 else 's'})" for name, n in gaps)
    refuse_or_force(bool(gaps), f"fewer than {REGION_VIEWS} views put board corners in the "
                    f"image's {where}: hold the board there too, where the lens bends most",
                    args.force)
    save(args.out, camera_matrix=K, distortion=solve.distortion, image_size=size,
         errors={"intrinsics_px": solve.rms_px})
    return 0


def table_main(args: argparse.Namespace) -> int:
    import numpy as np

    from calibration.fits import MAX_TABLE_MM, diagonal_centres, fit_handedness, fit_table
    from calibration.transforms import FitError, undistort_pixels
    from tracking.markers import DetectorSettings, detect_markers, make_detector, refine_corners
    wanted = [parse_marker(m) for m in args.marker]
    if len(wanted) < 4:
        raise CalibrateError(f"{len(wanted)} --marker given; at least 4 markers at known table "
                             "positions are needed (--marker ID=X,Y)")
    ids_given = [m[0] for m in wanted]
    twice = sorted({i for i in ids_given if ids_given.count(i) > 1})
    if twice:
        raise CalibrateError(f"--marker: marker id {twice[0]} is given twice; give each marker "
                             "on the table once, at its own position")
    lens = load_existing(args.calibration or args.out)
    if args.calibration and lens is None:
        raise CalibrateError(f"{args.calibration}: calibration file not found")
    grey = read_image(args.image)
    same_size(lens, grey, args.image)
    try:
        detector = make_detector(DetectorSettings(dictionary=args.dictionary))
    except ValueError as exc:
        raise CalibrateError(f"--dictionary: {exc}") from None
    from tabletop.config_checks import dictionary_size
    n = dictionary_size(args.dictionary) or 0
    for m in ids_given:   # was "not found", sending the installer to look for it on the table
        if m >= n:
            raise CalibrateError(f"--marker {m}=...: marker id {m} is not in {args.dictionary} "
                                 f"(ids 0 to {n - 1}); use the ids printed on the markers")
    ids, corners = detect_markers(grey, detector)
    corners = refine_corners(grey, corners)
    seen = {int(i): c for i, c in zip(ids, corners)}
    missing = [m for m in ids_given if m not in seen]
    if missing:
        raise CalibrateError(f"{args.image}: marker(s) {', '.join(map(str, missing))} of "
                             f"{args.dictionary} not found (found: "
                             f"{', '.join(map(str, sorted(seen))) or 'none'})")
    K = None if lens is None else lens.camera_matrix
    dist = None if lens is None else lens.distortion
    if K is None:
        print("note: no lens calibration; pixels are used as they are (run `tabletop "
              "calibrate camera` first for a lens with visible distortion)")
    quads = np.array([seen[m] for m in ids_given])
    ideal = diagonal_centres(undistort_pixels(quads.reshape(-1, 2), K, dist).reshape(-1, 4, 2))
    table = np.array([[x, y] for _, x, y in wanted])
    try:
        fit = fit_table(ideal, table)
    except FitError as exc:
        raise CalibrateError(f"--marker: {exc}") from None
    for (mid, x, y), r in zip(wanted, fit.residual_mm):
        print(f"  marker {mid} at {x:.3f}, {y:.3f} m: {r:.2f} mm")
    folded, mirrored = fit_handedness(fit.H, undistort_pixels(quads.reshape(-1, 2), K, dist))
    if folded:
        raise CalibrateError("--marker: these positions fold the table over itself (two markers' "
                             "positions swapped?); check each id against where it lies")
    print(f"table fit: residual {fit.rms_mm:.2f} mm RMS, {fit.worst_mm:.2f} mm worst, "
          f"{len(wanted)} markers")
    refuse_or_force(fit.rms_mm > MAX_TABLE_MM, f"table residual {fit.rms_mm:.2f} mm RMS is "
                    f"over {MAX_TABLE_MM} mm (a marker at a wrong position?)", args.force)
    refuse_or_force(mirrored, "--marker: these positions are mirrored (the table is x right, "
                    "y up seen from above; every angle would be reversed)", args.force)
    entries: dict[str, Any] = dict(camera_to_table=fit.H, errors={
        "camera_to_table_m": fit.rms_mm / 1e3})
    if K is not None:
        entries.update(camera_matrix=K, distortion=dist)
    entries.setdefault("image_size", (grey.shape[1], grey.shape[0]))
    save(args.out, **entries)
    return 0


def pattern_main(args: argparse.Namespace) -> int:
    from calibration.charuco import pattern_image, pattern_spec
    size = parse_projector_size(args.size)
    write_png(args.out, "--out", pattern_image(size))
    spec, _ = pattern_spec(size)
    print(f"wrote {args.out}: {size[0]}x{size[1]} projector pixels, a {spec.cols}x{spec.rows} "
          f"ChArUco pattern; show it fullscreen, unscaled, on the projector")
    return 0


def projector_main(args: argparse.Namespace) -> int:
    import numpy as np

    from calibration.fits import MAX_PROJECTOR_MM
    from tabletop.procam import fit_projector_images, live_projector
    cal = load_existing(args.calibration)
    if cal is None:
        raise CalibrateError(f"{args.calibration}: calibration file not found")
    if cal.camera_to_table is None:
        raise CalibrateError(f"{args.calibration}: camera_to_table: null; run `tabletop "
                             "calibrate table` first")
    table = parse_pair(args.table, "--table", "metres") if args.table else None
    if args.live:
        size = parse_projector_size(args.size) if args.size else None
        display = args.display.strip()
        if not (display.isascii() and display.isdigit()):
            raise CalibrateError(f"--display {args.display!r}: expected a display number "
                                 "(0, 1, ...)")
        fit, size = live_projector(args.device, int(display), size, cal, table)
    else:
        if not args.pattern or not args.image:
            raise CalibrateError("--pattern PATTERN.png and at least one --image IMAGE are "
                                 "needed (or --live)")
        pattern = read_image(args.pattern)
        images = [(p, read_image(p)) for p in args.image]
        for name, img in images:
            same_size(cal, img, name)
        fit = fit_projector_images(pattern, args.pattern, images, cal, table)
        size = (pattern.shape[1], pattern.shape[0])
    print(f"projector fit: residual {fit.rms_mm:.2f} mm RMS "
          f"({np.sqrt(np.mean(fit.residual ** 2)):.2f} "
          f"projector px), {fit.worst_mm:.2f} mm worst, {len(fit.residual)} pattern corners")
    refuse_or_force(fit.rms_mm > MAX_PROJECTOR_MM, f"projector residual {fit.rms_mm:.2f} mm "
                    f"RMS is over {MAX_PROJECTOR_MM} mm", args.force)
    save(args.out, camera_to_table=cal.camera_to_table, camera_matrix=cal.camera_matrix,
         distortion=cal.distortion, image_size=cal.image_size, table_to_projector=fit.H,
         projector_size=size,
         errors={"table_to_projector_px": float(np.sqrt(np.mean(fit.residual ** 2)))})
    return 0


def check_main(args: argparse.Namespace) -> int:
    from calibration.fits import CHECK_MM
    from tabletop.procam import check_from_config, check_lines
    tol = (CHECK_MM if args.tolerance is None
           else positive_number(args.tolerance, "--tolerance", "millimetres", CalibrateError))
    result = check_from_config(args.config)
    lines, passed = check_lines(result, tol)
    print("\n".join(lines))
    return 0 if passed else 1
