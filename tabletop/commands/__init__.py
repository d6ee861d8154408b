"""Subcommands of the tabletop command line, one module each, and their shared argument checks."""

from __future__ import annotations

import errno
import math
from pathlib import Path
from typing import Iterable, Sequence

from tabletop.errors import InputError


def positive_number(text: str, option: str, unit: str,
                    error: type[InputError] = InputError) -> float:
    """``text`` of command-line ``option`` as a positive finite number of ``unit``; anything
    else raises ``error`` naming the option and the value."""
    try:
        value = float(text)
    except ValueError:
        raise error(f"{option} {text!r} is not a number ({unit})") from None
    if not math.isfinite(value) or value <= 0:
        raise error(f"{option} {text!r} must be a positive number of {unit}")
    return value


def number_pair(text: str, option: str, what: str,
                error: type[InputError] = InputError) -> tuple[float, float]:
    """``A,B`` of command-line ``option`` as two floats (inf and nan pass: the caller checks the
    range); anything else raises ``error``: "OPTION 'TEXT' must be WHAT"."""
    parts = text.split(",")
    try:
        if len(parts) != 2:
            raise ValueError
        return float(parts[0]), float(parts[1])
    except ValueError:
        raise error(f"{option} {text!r} must be {what}") from None


def number_in_range(text: str | float, option: str, unit: str, lo: float, hi: float,
                    error: type[InputError] = InputError, integer: bool = False) -> float:
    """``text`` of command-line ``option`` as a finite number of ``unit`` in [lo, hi] (a whole
    number with ``integer``); anything else raises ``error`` naming the option, the value and
    the range."""
    kind = "a whole number" if integer else "a number"
    try:
        value = float(text)
    except (TypeError, ValueError):
        raise error(f"{option} {text!r} is not {kind} ({unit})") from None
    if not math.isfinite(value) or not lo <= value <= hi or (integer and value != int(value)):
        raise error(f"{option} {text!r} must be {kind} of {unit} from {lo:g} to {hi:g}"
                    + thousandths_hint(unit, lo, hi, value))
    return int(value) if integer else value


def thousandths_hint(unit: str, lo: float, hi: float, *values: float) -> str:
    """' (millimetres given?)' (or milliseconds) for ``values`` of metres (or seconds) a
    thousand times too large, as config.yaml's values are asked (:func:`schema.thousandths`);
    else ''."""
    from tabletop.schema import thousandths
    smaller = thousandths(unit, lo, hi, *values)
    return f" ({smaller} given?)" if smaller else ""


def output_file(path: str | Path, option: str, error: type[InputError] = InputError,
                inputs: Iterable[str | Path | None] = (), example: str = "out.jsonl") -> Path:
    """``path`` of an output ``option`` (a Path), refused at once when it names a folder (the
    message suggests the file ``example`` in it) or the same file as one of ``inputs`` (the
    command's input paths, None where not given), which the output would overwrite. An empty
    ``path`` is refused as empty (Path('') is the current folder)."""
    if str(path) == "":
        raise error(f"{option}: the path is empty; give a file name such as {example}")
    p = Path(path)
    if p.is_dir():
        raise error(f"{option} {p}: is a folder; give a file name such as {p / example}")
    target = _resolved(p)
    if target is None:
        raise error(f"{option} {p}: cannot be written: too many levels of symbolic links")
    for source in inputs:   # (an input that does not resolve is refused by its own reader)
        if source is not None and _resolved(Path(source)) == target:
            raise error(f"{option} {p}: is the input file {source}; writing there would "
                        "overwrite it, give another file name")
    return p


def _resolved(p: Path) -> Path | None:
    """``p.resolve()``, or None for a symbolic link loop (Python before 3.13 raises
    RuntimeError there, which the command line reported as an internal error)."""
    try:
        return p.resolve()
    except RuntimeError:
        return None
    except OSError as exc:   # a loop; anything else is told by the write or read itself
        return None if exc.errno == errno.ELOOP else p.absolute()


def folder_takes_files(folder: Path, option: str, shown: str | Path,
                       error: type[InputError] = InputError) -> None:
    """Refuse (``error``) command-line ``option`` (its value ``shown``) when ``folder`` cannot
    be made or takes no file (read-only, not this account's, a file on its path): for a
    command that writes there only after long work (a live calibration's minutes of views).
    The folder is made, as the writer would."""
    import os
    import tempfile

    from tabletop.file_io import folder_failure
    try:
        folder.mkdir(parents=True, exist_ok=True)
        fd, probe = tempfile.mkstemp(dir=folder, prefix=".tabletop-probe-")
        os.close(fd)
        os.unlink(probe)
    except OSError as exc:
        raise error(f"{option} {shown}: nothing can be written there: "
                    f"{folder_failure(folder, exc)}") from None


def png_output(path: str | Path, option: str, error: type[InputError] = InputError,
               inputs: Iterable[str | Path | None] = (), example: str = "out.png") -> Path:
    """:func:`output_file` for an image written as PNG: a name not ending in .png (``x.jpg``
    would hold PNG bytes under a JPEG name) is refused, suggesting the .png one."""
    p = output_file(path, option, error, inputs=inputs, example=example)
    if p.suffix.lower() != ".png":
        raise error(f"{option} {p}: the image is written as PNG; give a file name ending in "
                    f".png, e.g. {p.with_suffix('.png').name}")
    return p


def sparse_hint(times: Sequence[float], what: str) -> str:
    """The words saying ``times`` (s) are over a second apart (median), so likely milliseconds,
    ``what`` first; "" when they are not. A warning says them, and so does a refusal of a span
    too long for its rate (a 60 s main path in milliseconds was refused as "spans 59975 s"
    without saying why it might)."""
    import numpy as np
    apart = float(np.median(np.diff(np.asarray(times, float)))) if len(times) > 1 else 0.0
    return f"{what} are {apart:g} s apart (median); times are seconds (milliseconds given?)" \
        if apart > 1.0 else ""


def warn_sparse_times(times: Sequence[float], command: str, source: str | Path,
                      what: str) -> None:
    """One stderr line when ``times`` (s) are over a second apart (median): milliseconds given
    for seconds, which made a 20 s main path 798,668 generated rows (``behave``) and a 20 s
    touch recording 600,000 physics steps (``pose``) without a word. ``what``: the samples'
    name in the line ("the input frames")."""
    import sys
    hint = sparse_hint(times, what)
    if hint:
        print(f"tabletop {command}: warning: {source}: {hint}", file=sys.stderr)
