"""``tabletop follow``: follow a recorded performance along action templates, row by row.

Each template CSV and the performance CSV share their feature columns (an optional ``t`` column is
not a feature); samples are regularly spaced, and a template whose ``t`` is at another rate
than the performance's is resampled to it (:func:`at_rate`). One output row per performance
row, computed causally as it would be live: ``t,best,progress,variance``, then ``p_NAME`` and
``progress_NAME`` per template, then ``valid`` and ``loglik``. Gestures are spotted in the stream
(one after another, without a rest between them); ``--invariance scale`` follows them at any
size and wherever they begin.
"""

from __future__ import annotations

import argparse
import re
from pathlib import Path
from typing import TYPE_CHECKING, Sequence

from tabletop.commands import number_in_range, output_file
from tabletop.errors import InputError

if TYPE_CHECKING:
    import numpy as np

    from behaviors.mop.follower import ActionFollower

HELP = "follow a performance along action templates (MOP): progress, recognition, validity per row"

_NAME = re.compile(r"^[A-Za-z0-9_.-]+$")
SIGMA = (1e-3, 100.0)   # standardised units, as the mop engine's follower.sigma
WINDOW = (1, 10_000)    # template samples


class FollowArgumentError(InputError):
    """A bad command-line argument of ``tabletop follow``."""


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--template", action="append", required=True, metavar="NAME=FILE.csv",
                   help="an action template: its name and CSV of features (repeat for several)")
    p.add_argument("--input", required=True, type=Path, metavar="PERF.csv",
                   help="the performance: CSV with the templates' feature columns")
    p.add_argument("--out", required=True, type=Path, metavar="PROGRESS.csv",
                   help="output CSV, one row per input row")
    p.add_argument("--sigma", default="0.2", metavar="S",
                   help=f"observation spread relative to the pooled feature scale, {SIGMA[0]:g} "
                        f"to {SIGMA[1]:g} (default 0.2)")
    p.add_argument("--window", default="15", metavar="N",
                   help=f"half-width of the forward window, in template samples, {WINDOW[0]} to "
                        f"{WINDOW[1]} (default 15): the states either side of the followed "
                        "progress that are weighed, so how far it may reach, nothing else (a still "
                        "input is valid at no window)")
    p.add_argument("--invariance", choices=("none", "offset", "scale"), default="none",
                   help="follow a performance relative to where each gesture begins (offset), "
                        "and of any size (scale; puck and touch paths are followed so live); "
                        "default none: as recorded")


def parse_template_args(values: list[str]) -> list[tuple[str, Path]]:
    """``NAME=FILE`` pairs; names are letters, digits, ``_ . -`` and unique."""
    out: list[tuple[str, Path]] = []
    for v in values:
        name, sep, file = v.partition("=")
        name = name.strip()
        if not sep or not name or not file.strip():
            raise FollowArgumentError(f"--template {v!r}: expected NAME=FILE.csv")
        if not _NAME.match(name):
            raise FollowArgumentError(
                f"--template {v!r}: name {name!r} may only hold ASCII letters, digits, '_', '.' "
                "and '-'")
        if any(name == n for n, _ in out):
            raise FollowArgumentError(f"--template {v!r}: template name {name!r} is given twice")
        out.append((name, Path(file.strip())))
    return out


def _features(path: str | Path, header: list[str], data: np.ndarray, what: str,
              lines: Sequence[int] | None = None) -> tuple[list[str], np.ndarray]:
    """(feature names, their columns) of a template or performance CSV; a value beyond
    ``frames.MAX_FEATURE`` is refused naming its line (``lines``) or data row."""
    from tabletop.files import check_positions
    from tabletop.frames import MAX_FEATURE
    cols = [i for i, c in enumerate(header) if c != "t"]
    if not cols:
        raise FollowArgumentError(f"{path}: {what} has no feature columns (only 't')")
    names = [header[i] for i in cols]
    check_positions(data, header, names, path, lines, MAX_FEATURE, "",
                    "more than a feature can be followed with")
    return names, data[:, cols]


#: The still radius (where the input is taken as resting; :mod:`behaviors.mop.invariance`) is
#: measured in a spread floored at this share of the templates' pooled spread per column (features
#: of unknown units: the puck's 1 cm floor against the example gestures' ~5 cm). Without it, with
#: ``--invariance scale``, a template that moved a thousandth of the others shrank the radius to
#: its own spread and left every other template invalid on every row (a circle beside a 1 mm
#: nudge: 0 of 61 rows valid, 43 alone). Each template's own scale (its tolerance) is not floored
#: by the set: flooring it so widened the circle's x tolerance from 4.5 to 13.7 cm beside a line
#: ten times its size.
MIN_SCALE_SHARE = 0.2


def still_scale(templates: dict) -> "np.ndarray":
    """The floor (d,) of the still radius's spread: :data:`MIN_SCALE_SHARE` of the pooled
    spread."""
    from behaviors.mop.features import fit_scale
    return MIN_SCALE_SHARE * fit_scale(list(templates.values()))[1]


def warn_templates(templates: dict, paths: dict) -> None:
    """One stderr line per template the follower cannot use as the designer meant, which was
    followed without a word: one shorter than a take the studio keeps (its few samples match
    any wiggle), and two holding the same samples (the same file under two names: each takes
    half the probability, so neither is valid while it is performed)."""
    import sys

    import numpy as np

    from behaviors.mop.takes import MIN_TAKE_SAMPLES
    said = "tabletop follow: warning:"
    for name, feats in templates.items():
        if len(feats) < MIN_TAKE_SAMPLES:
            print(f"{said} {paths[name]}: template {name!r} has {len(feats)} samples; the "
                  f"studio keeps no take under {MIN_TAKE_SAMPLES} (so short, its start matches "
                  "any motion)", file=sys.stderr)
    names = list(templates)
    for i, a in enumerate(names):
        twin = next((b for b in names[:i] if templates[b].shape == templates[a].shape
                     and np.array_equal(templates[b], templates[a])), None)
        if twin is not None:
            print(f"{said} templates {twin!r} ({paths[twin]}) and {a!r} ({paths[a]}) hold the "
                  "same samples: the follower cannot tell them apart, and neither is valid "
                  "while it is performed", file=sys.stderr)


def warn_alike(templates: dict[str, np.ndarray], paths: dict[str, Path],
               follower: ActionFollower) -> None:
    """One stderr line per pair of different templates whose paths lie within the path
    misfit's acceptance of each other (:mod:`behaviors.mop.alike`): the same gesture recorded
    twice, which was followed without a word, each taking part of the probability."""
    import sys

    import numpy as np

    from behaviors.mop.alike import alike
    limit = follower.shape_accept
    for a, b, ab, ba in alike(templates, follower.bank, follower.sigma, limit,
                              follower.invariance):
        if templates[a].shape == templates[b].shape and np.array_equal(templates[a],
                                                                       templates[b]):
            continue                    # said as the same samples
        print(f"tabletop follow: warning: templates {a!r} ({paths[a]}) and {b!r} "
              f"({paths[b]}) are alike: performed as recorded, each lies on the other's path "
              f"({ab:.2f} and {ba:.2f} sigma from it; a path is accepted within {limit:g}): "
              "the follower can hardly tell them apart", file=sys.stderr)


MAX_RESAMPLED = 1_000_000   # samples a template may be resampled to
UNITS_APART = 300.0   # rates this many times apart are no two rates: milliseconds for seconds
# (a performance's t in ms resampled a 2 s template at 30 Hz to 2 samples, followed as such)


def at_rate(templates: dict, times: dict, paths: dict, rate_hz: float) -> None:
    """Resample in place each template whose column 't' is not on the performance's rate
    (``rate_hz``, from its median step), as the installation resamples every template to its
    ``rate_hz``: the follower takes one template sample per performance row, so a template
    recorded at 120 Hz followed a 30 Hz performance of the same gesture as a fourfold slow one
    (8 of 60 rows valid, progress 0.006 at the end; resampled: as at 30 Hz, 54 of 60). The
    templates resampled are said in one stderr line."""
    import sys

    import numpy as np

    from behaviors.mop.follower import TemplateError
    from tabletop.plugins.mop_files import MAX_TEMPLATE_S, resample
    step = 1.0 / rate_hz
    said = []
    for name, t in times.items():
        steps = np.diff(t)
        if np.all(np.abs(steps - step) <= 0.01 * step):
            continue
        if t[-1] - t[0] > MAX_TEMPLATE_S:
            raise TemplateError(f"{paths[name]}: template {name!r} spans {t[-1] - t[0]:g} s "
                                f"(column 't'); at most {MAX_TEMPLATE_S:g} s can be followed")
        if (t[-1] - t[0]) * rate_hz > MAX_RESAMPLED:   # (a performance's t in hours: GBs)
            raise TemplateError(f"{paths[name]}: template {name!r} would be "
                                f"{(t[-1] - t[0]) * rate_hz:.3g} samples at the performance's "
                                f"{rate_hz:.3g} Hz (at most {MAX_RESAMPLED:,}); are both "
                                "columns 't' in seconds?")
        own = 1.0 / float(np.median(steps))
        if not 1.0 / UNITS_APART <= own / rate_hz <= UNITS_APART:  # not a rate: other units
            raise TemplateError(f"{paths[name]}: template {name!r} samples are {1.0 / own:.3g} s "
                                f"apart (median), the performance's {step:.3g} s; are both "
                                "columns 't' in seconds (milliseconds given for one?)")
        regular = np.all(np.abs(steps - 1.0 / own) <= 0.01 / own)
        said.append(f"{name!r} ({paths[name]}, " + (f"{own:.3g} Hz)" if regular else
                    f"irregular: {steps.min():.3g} to {steps.max():.3g} s apart)"))
        templates[name] = resample(t, templates[name], rate_hz)
    if said:
        print(f"tabletop follow: note: template{'s' * (len(said) > 1)} {', '.join(said)} "
              f"resampled to the performance's {rate_hz:.3g} Hz, as the installation resamples "
              "its templates to its rate_hz", file=sys.stderr)


def main(args: argparse.Namespace) -> int:
    import numpy as np

    from behaviors.mop.follower import ActionFollower, TemplateError
    from tabletop.files import MAX_TEMPLATE_BYTES, check_increasing, read_csv_lines, write_csv

    sigma = number_in_range(args.sigma, "--sigma", "standardised units", *SIGMA,
                            FollowArgumentError)
    window = number_in_range(args.window, "--window", "template samples", *WINDOW,
                             FollowArgumentError, integer=True)
    pairs = parse_template_args(args.template)
    output_file(args.out, "--out", FollowArgumentError,
                inputs=[args.input] + [path for _, path in pairs], example="progress.csv")
    templates: dict[str, np.ndarray] = {}
    times: dict[str, np.ndarray] = {}       # a template's column 't', where it has one
    columns: list[str] | None = None
    first: Path | None = None
    for name, path in pairs:
        # (no row is said as one row is: "has 0 sample(s), needs at least 2" just below)
        header, data, tlines = read_csv_lines(path, what=f"template {name!r} CSV file",
                                              min_rows=0, max_bytes=MAX_TEMPLATE_BYTES)
        names, feats = _features(path, header, data, f"template {name!r}", tlines)
        if "t" in header:   # (the engine refuses such a template; it was followed here)
            check_increasing(data[:, header.index("t")], path, lines=tlines)
        if feats.shape[0] < 2:
            raise TemplateError(
                f"{path}: template {name!r} has {feats.shape[0]} sample(s), needs at least 2")
        if columns is None:
            columns, first = names, path
        elif sorted(names) != sorted(columns):
            raise TemplateError(
                f"{path}: template {name!r} has feature columns {','.join(names)} but {first} has "
                f"{','.join(columns)}; every template needs the same feature columns")
        order = [names.index(c) for c in columns]
        templates[name] = feats[:, order]
        if "t" in header:
            times[name] = data[:, header.index("t")]
    assert columns is not None
    header, data, lines = read_csv_lines(args.input, what="performance CSV file", min_rows=1)
    names, feats = _features(args.input, header, data, "performance", lines)
    if sorted(names) != sorted(columns):
        missing = [c for c in columns if c not in names]
        extra = [c for c in names if c not in columns]
        detail = "; ".join(s for s in (f"missing {','.join(missing)}" if missing else "",
                                       f"unexpected {','.join(extra)}" if extra else "") if s)
        raise TemplateError(
            f"{args.input}: performance feature columns {','.join(names)} do not match the "
            f"templates' {','.join(columns)} ({detail})")
    perf = feats[:, [names.index(c) for c in columns]]
    if "t" in header:
        t = data[:, header.index("t")]
        check_increasing(t, args.input, lines=lines)
        if len(t) >= 2:
            at_rate(templates, times, dict(pairs), 1.0 / float(np.median(np.diff(t))))
    else:
        t = np.arange(perf.shape[0], dtype=float)

    warn_templates(templates, dict(pairs))
    follower = ActionFollower(templates, sigma=sigma, window=window,
                              invariance=args.invariance,
                              still_scale=still_scale(templates))
    warn_alike(templates, dict(pairs), follower)
    out_header = ["t", "best", "progress", "variance"]
    for name in templates:
        out_header += [f"p_{name}", f"progress_{name}"]
    out_header += ["valid", "loglik"]
    rows = []
    for ti, x in zip(t, perf):
        s = follower.step(x)
        row: list[float | str | int] = [float(ti), s.best, s.progress, s.variance]
        for name in templates:
            row += [s.probabilities[name], s.progress_by[name]]
        row += [int(s.valid), s.loglik]
        rows.append(row)
    write_csv(args.out, out_header, rows)
    return 0
