"""File formats shared by the commands and plugins: numeric CSV tables and YAML inputs, a bad
file refused with one line naming the file, the line and what is wrong. The safe reads and
atomic writes under them (:mod:`tabletop.file_io`) and a take kept under a free name
(:mod:`tabletop.names`) are re-exported: the engines import this one shared layer.

Reading a CSV either returns a clean float table or raises :class:`FileFormatError` naming the
file, the line and what is wrong; a CSV is written atomically (:func:`write_csv`).
"""

from __future__ import annotations

import csv
import io
import math
import re
from pathlib import Path
from typing import Any, Iterable, Sequence

import numpy as np
import yaml

from tabletop.file_io import (  # noqa: F401  (shared layer)
    MAX_CALIBRATION_BYTES, MAX_CLIP_BYTES, MAX_DEMONSTRATION_BYTES, MAX_DESCRIPTION_BYTES,
    MAX_TEMPLATE_BYTES, MAX_TEXT_BYTES, FileFormatError, UnreadableText, alive,
    atomic_write_bytes, atomic_write_text, atomic_writer, file_on_path, folder_failure,
    fsync_folder, is_stream, json_loads, new_folder, read_regular_bytes, read_text,
    read_text_within, tree_signature, write_synced)
from tabletop.frames import MAX_POSITION_M, InputError
from tabletop.names import NameTaken, keep_under_free_name  # noqa: F401  (shared layer)


class ReadFile(type(Path())):
    """A file's path (equal to it, as any config path) carrying what the config's load read of
    it: ``content`` (read-only) and ``read``, the file's signature taken just before
    (:func:`~tabletop.file_io.tree_signature`; None when not taken), so that a build takes
    the content without opening the file again. Subclasses name what the content is."""

    content: Any
    read: tuple | None

    def __reduce__(self) -> tuple:
        return carrying, (type(self), str(self), self.content, self.read)

    def unchanged(self) -> bool:
        """Is the file on disk still as it was read (its signature: a stat, no open)?"""
        return self.read is not None and tree_signature(self) == self.read


def carrying(cls: type[ReadFile], path: str, content: Any, read: tuple | None) -> ReadFile:
    """A ``cls`` (a :class:`ReadFile`) of ``path`` carrying ``content``, read at ``read``."""
    f = cls(path)
    f.content, f.read = content, read
    return f


class Table(ReadFile):
    """A numeric CSV's path carrying what :func:`read_table` read of it: ``content``, its
    header, rows and the file line of each row (read-only)."""

    content: tuple[list[str], np.ndarray, np.ndarray]


def read_table(path: Path, what: str, required: Sequence[str] = (), min_rows: int = 1,
               max_bytes: int = MAX_TEXT_BYTES, cls: type[Table] = Table) -> Table:
    """A CSV read (:func:`read_csv_lines`, FileFormatError naming the file) into a ``cls``
    carrying its table and the :func:`tree_signature` taken just before the read."""
    read = tree_signature(Path(path))
    header, data, lines = read_csv_lines(path, required, what, min_rows, max_bytes)
    data.setflags(write=False)       # shared by every reader and build of the config read
    lines.setflags(write=False)
    return carrying(cls, str(path), (header, data, lines), read)


def read_shared(read: dict, path: Path, what: str, required: Sequence[str] = (),
                min_rows: int = 1, max_bytes: int = MAX_TEXT_BYTES) -> Table:
    """The table of the CSV ``path`` from ``read`` (a config load's files read, by (kind,
    path): :class:`tabletop.schema.Context`), read once for every reader of the load asking
    with the same ``min_rows`` and ``max_bytes`` (a MOP template that is also a scripted
    gesture: examples/mop.yaml 12 CSV parses per load -> 6). A table lacking the ``required``
    columns is read again, so its refusal names ``what`` and those columns."""
    key = ("csv", Path(path), min_rows, max_bytes)
    table = read.get(key)
    if table is None or not set(required) <= set(table.content[0]):
        table = read_table(path, what, required, min_rows, max_bytes)
        read.setdefault(key, table)
    return table


def format_csv(header: Sequence[str], rows: Iterable[Sequence[float | str]]) -> str:
    """CSV text with ``header``; floats are written with full precision (repr)."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(header)
    for row in rows:
        w.writerow([repr(float(v)) if isinstance(v, (float, np.floating)) else v for v in row])
    return buf.getvalue()


def write_csv(path: str | Path, header: Sequence[str],
              rows: Iterable[Sequence[float | str]]) -> None:
    """Write a CSV table atomically."""
    atomic_write_text(path, format_csv(header, rows))


def read_csv(path: str | Path, required: Sequence[str] = (), what: str = "CSV file",
             min_rows: int = 1, max_bytes: int = MAX_TEXT_BYTES) -> tuple[list[str], np.ndarray]:
    """Read a numeric CSV with a header row; returns (column names, float array rows x columns).
    See :func:`read_csv_lines`."""
    return read_csv_lines(path, required, what, min_rows, max_bytes)[:2]


def read_csv_lines(path: str | Path, required: Sequence[str] = (), what: str = "CSV file",
                   min_rows: int = 1, max_bytes: int = MAX_TEXT_BYTES
                   ) -> tuple[list[str], np.ndarray, np.ndarray]:
    """Read a numeric CSV with a header row; returns (column names, float array rows x columns,
    the file line number of each row).

    Raises FileFormatError for a file over ``max_bytes`` (before it is parsed), a missing or
    unreadable file, an empty file, a header without the
    ``required`` columns, duplicate columns, a row of the wrong length, a non-numeric or
    non-finite value (with its line number), a last row cut short (the file ends without a
    line end: :func:`_check_last_row_whole`) or fewer than ``min_rows`` rows.
    """
    p = Path(path)
    try:
        text = read_text_within(p, max_bytes, what, FileFormatError, "utf-8-sig")
    except FileNotFoundError:
        raise FileFormatError(f"{p}: {what} not found") from None
    except IsADirectoryError:
        raise FileFormatError(f"{p}: is a folder, expected a {what}") from None
    except (OSError, UnreadableText) as exc:
        raise FileFormatError(f"{p}: cannot read {what}: {exc}") from None
    # row by row, not list(csv.reader(...)): one C call holds the GIL for the whole file, and
    # a worker reading a 600 s demonstration that way stalls the frame loop 8-60 ms
    # (bench/reload_tick.py)
    reader = csv.reader(text.splitlines())
    try:
        rows = [r for r in reader]
    except csv.Error as exc:   # a value over csv's 128 kB field limit: no CSV of numbers
        raise FileFormatError(f"{p}: line {reader.line_num}: {exc} (not a {what}?)") from None
    first = next((i for i, r in enumerate(rows) if any(c.strip() for c in r)), None)
    if first is None:
        raise FileFormatError(f"{p}: {what} is empty (expected a header row)")
    header = [c.strip() for c in rows[first]]
    if header[0][:1] in ("{", "["):     # (its commas made a header of the data's pieces)
        raise FileFormatError(f"{p}: line {first + 1}: JSON, not a {what} (a CSV whose first "
                              "row names its columns)")
    if any(not c for c in header):
        raise FileFormatError(f"{p}: line {first + 1}: empty column name in header {header}")
    dup = sorted({c for c in header if header.count(c) > 1})
    if dup:
        raise FileFormatError(f"{p}: line {first + 1}: duplicate column(s) {', '.join(dup)}")
    missing = [c for c in required if c not in header]
    if missing:
        raise FileFormatError(
            f"{p}: line {first + 1}: missing column(s) {', '.join(missing)}; "
            f"expected header {','.join(required)}, got {','.join(header)}")
    data: list[list[float]] = []
    numbers: list[int] = []
    unended = len(rows) - 1 if text[-1:] not in ("\n", "\r") else -1   # (its last line's row)
    width, isfinite = len(header), math.isfinite
    for i in range(first + 1, len(rows)):
        r = rows[i]
        if not "".join(r).strip():      # (as any cell with more than white space)
            continue
        if len(r) != width:
            cut = CUT_SHORT if i == unended else ""
            raise FileFormatError(
                f"{p}: line {i + 1}: {len(r)} value{'s' * (len(r) != 1)}, expected "
                f"{len(header)} ({','.join(header)}){cut}")
        # a row's cells in one pass, each through float() (the loop below, a cell at a time,
        # only to say what a refused row holds): the five shipped demonstrations (2,400-3,200
        # rows) read in 62.5 -> 48.5 ms of CPU in all (least of 15, loaded 2-core machine)
        try:
            vals = list(map(float, r))
        except ValueError:
            vals = None
        if vals is not None and all(map(isfinite, vals)):
            data.append(vals)
            numbers.append(i + 1)
            continue
        cut = CUT_SHORT if i == unended else ""
        for name, cell in zip(header, r):
            try:
                v: float | None = float(cell)
            except ValueError:
                v = None
            if v is None or not math.isfinite(v):
                raise FileFormatError(f"{p}: line {i + 1}: column {name!r}: {cell.strip()!r} is "
                                      f"not a {'number' if v is None else 'finite number'}{cut}")
    if numbers and numbers[-1] == unended + 1:
        _check_last_row_whole(p, numbers[-1], header[-1], [rows[n - 1][-1] for n in numbers])
    if len(data) < min_rows:
        raise FileFormatError(
            f"{p}: {what} has {len(data)} data row(s), needs at least {min_rows}")
    return (header, np.asarray(data, dtype=float).reshape(len(data), len(header)),
            np.asarray(numbers, dtype=int))


CUT_SHORT = " (the file ends there without a line end: cut short while it was written?)"
"""Said of a refused last row that has no line end."""


def _written_digits(cell: str) -> tuple[int, int]:
    """Digits a number was written with: (after its point, in its exponent)."""
    mantissa, _, exponent = cell.strip().lower().partition("e")
    return len(mantissa.partition(".")[2]), sum(c.isdigit() for c in exponent)


def _check_last_row_whole(path: Path, line: int, column: str, cells: list[str]) -> None:
    """Refuse a CSV whose last row, not ended by a line end, was evidently cut short while the
    file was written (a copy interrupted, a recorder stopped): its last value written with
    fewer digits than that column's value in every other row (``-0.000287`` cut to ``-0.``
    still reads as a number). ``line``: the last row's file line; ``cells``: the last
    column's cells, row by row."""
    if len(cells) < 2:
        return
    last = _written_digits(cells[-1])
    fewest = tuple(min(d) for d in zip(*map(_written_digits, cells[:-1])))
    if last[0] < fewest[0] or last[1] < fewest[1]:
        raise FileFormatError(
            f"{path}: line {line}: column {column!r}: {cells[-1].strip()!r} has fewer digits "
            f"than in every other row{CUT_SHORT[:-1]}; if the row is whole, end it with a line "
            "end)")


def check_increasing(t: np.ndarray, path: str | Path, column: str = "t",
                     lines: Sequence[int] | None = None) -> None:
    """Raise FileFormatError unless times ``t`` (s) strictly increase; names the first bad row by
    its file line (``lines``, from :func:`read_csv_lines`) or else by its data row number."""
    bad = np.flatnonzero(np.diff(t) <= 0)
    if bad.size:
        i = int(bad[0]) + 1
        if lines is not None:
            where, before = f"line {int(lines[i])}", f"line {int(lines[i - 1])}"
        else:
            where, before = f"data row {i + 1}", f"row {i}"
        raise FileFormatError(
            f"{path}: {where}: column {column!r} must strictly increase; {float(t[i])!r} is "
            f"not after {float(t[i - 1])!r} ({before})")


def check_positions(data: np.ndarray, header: Sequence[str], columns: Sequence[str],
                    path: str | Path, lines: Sequence[int] | None = None,
                    limit: float = MAX_POSITION_M, unit: str = " m",
                    what: str = "not a table position") -> None:
    """Raise FileFormatError unless every value of ``columns`` is within ``limit`` (by default
    table positions, metres, within ``frames.MAX_POSITION_M``); names the first bad row by its
    file line (``lines``) or else by its data row number."""
    index = [list(header).index(c) for c in columns]
    bad = np.argwhere(np.abs(data[:, index]) > limit)
    if bad.size:
        r, c = (int(v) for v in bad[0])
        where = f"line {int(lines[r])}" if lines is not None else f"data row {r + 1}"
        raise FileFormatError(
            f"{path}: {where}: column {columns[c]!r}: {float(data[r, index[c]])!r}{unit} is "
            f"beyond {limit:g}{unit}, {what}")


# --- YAML inputs: parsed with unique keys, a bad file refused with one line naming the file, line
# and column (configs, calibrations, behaviour folders).

class UniqueKeyLoader(yaml.SafeLoader):
    """YAML's safe loader refusing a key given twice in one mapping (YAML says keys are
    unique; PyYAML would silently keep the last). A key is read as written where YAML 1.1
    would read a boolean (``on:``, ``yes:``, ``off:``): no key of ours is one, and ``{True:
    False}`` in a message hid what was written (values keep YAML 1.1: ``overlay: on``)."""


BOOL_TAG = "tag:yaml.org,2002:bool"


def _unique_mapping(loader: UniqueKeyLoader, node: yaml.MappingNode, deep: bool = False) -> Any:
    seen: set[Any] = set()
    for i, (key_node, value_node) in enumerate(node.value):
        if key_node.tag == "tag:yaml.org,2002:merge":
            continue
        if key_node.tag == BOOL_TAG and isinstance(key_node, yaml.ScalarNode):
            key_node = yaml.ScalarNode("tag:yaml.org,2002:str", key_node.value,
                                       key_node.start_mark, key_node.end_mark)
            node.value[i] = (key_node, value_node)
        key = loader.construct_object(key_node, deep=True)
        try:
            duplicate = key in seen
            seen.add(key)
        except TypeError:  # an unhashable key: the base constructor says so
            break
        if duplicate:
            raise yaml.constructor.ConstructorError(
                "while reading a mapping", node.start_mark,
                f"key {key!r} is given twice (the second is on this line)", key_node.start_mark)
    return yaml.SafeLoader.construct_mapping(loader, node, deep)


UniqueKeyLoader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, _unique_mapping)

# libyaml's parser (C) under the same resolver and constructors: CPU per parse, examples/mop.yaml
# 16.2 -> 2.0 ms, config.yaml 3.2 -> 0.4 ms, a behaviour's behavior.yaml 1.5 -> 0.2 ms. A text it
# refuses is parsed again by the Python parser, whose refusal (line, column, problem) is the
# one said. libyaml accepts what the Python parser refuses in texts holding a tab (in a plain
# scalar or after a key), a "?" (in a flow mapping) or a block scalar's "|" or ">" with a
# comment right after it, and reads a byte-order mark past the start as nothing (the Python
# parser: as text): such texts go to the Python parser alone. So on 24,000 random edits of the
# project's YAML files both give the same value, or the same refusal. The node parser gives
# the interpreter lock up at every scalar (its resolver is Python).
_C_LOADER = (type("UniqueKeyCLoader", (yaml.CSafeLoader,),
                  {"yaml_constructors": UniqueKeyLoader.yaml_constructors})
             if getattr(yaml, "__with_libyaml__", False) else None)
_PYTHON_ONLY = re.compile(r"[\t?\ufeff]|[|>][-+0-9]*#")


def parse_yaml(text: str, file: str | Path, error: type[InputError] = FileFormatError,
               problem: str = "YAML syntax error") -> Any:
    """Parse YAML text; a syntax error or a duplicate key raises ``error`` naming the file,
    line and column."""
    if _C_LOADER is not None and not _PYTHON_ONLY.search(text):
        try:
            return yaml.load(text, Loader=_C_LOADER)
        except Exception:  # noqa: BLE001 (refused: said as the Python parser says it, below)
            pass
    return _parse_yaml_python(text, file, error, problem)


def _parse_yaml_python(text: str, file: str | Path, error: type[InputError] = FileFormatError,
                       problem: str = "YAML syntax error") -> Any:
    """:func:`parse_yaml` by PyYAML's Python parser (its messages)."""
    try:
        return yaml.load(text, Loader=UniqueKeyLoader)
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        where = f"line {mark.line + 1}, column {mark.column + 1}" if mark else "unknown place"
        raise error(f"{file}: {problem} at {where}: {exc.problem}") from None
    except yaml.reader.ReaderError as exc:  # a character YAML does not allow
        at = exc.position if isinstance(exc.position, int) else 0
        line = text.count("\n", 0, at) + 1
        column = at - (text.rfind("\n", 0, at) + 1) + 1
        code = exc.character if isinstance(exc.character, int) else ord(exc.character or " ")
        raise error(f"{file}: {problem} at line {line}, column {column}: character U+{code:04X} "
                    f"is not allowed in YAML (a damaged or binary file?)") from None
    except yaml.YAMLError as exc:
        raise error(f"{file}: {problem}: {' '.join(str(exc).split())}") from None
    except (ValueError, RecursionError) as exc:  # e.g. an integer of thousands of digits
        raise error(f"{file}: {problem}: {type(exc).__name__}: {exc}") from None


def read_yaml(path: str | Path, error: type[InputError] = FileFormatError,
              missing: str = "not found", problem: str = "YAML syntax error",
              max_bytes: int | None = None, kind: str = "YAML file") -> Any:
    """Read and parse a YAML file; a missing, unreadable or malformed file raises ``error``
    (``missing`` is the message for a file that does not exist), and so does one over
    ``max_bytes`` (a ``kind`` of file never that long), before it is parsed: YAML parses
    about 2 MB a second, so a wrong file of 50 MB took half a minute to be refused."""
    p = Path(path)
    try:
        text = read_text(p) if max_bytes is None else read_text_within(p, max_bytes, kind, error)
    except FileNotFoundError:
        raise error(f"{p}: {missing}") from None
    except IsADirectoryError:
        raise error(f"{p}: is a folder; expected a YAML file") from None
    except (OSError, UnreadableText) as exc:
        raise error(f"{p}: cannot read: {exc}") from None
    return parse_yaml(text, p, error, problem)
