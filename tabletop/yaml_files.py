"""YAML input files: parsed with unique keys, a bad file refused with one line naming the file,
line and column (configs, calibrations, behaviour folders)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import yaml

from tabletop.files import FileFormatError, UnreadableText, read_text
from tabletop.frames import InputError


class UniqueKeyLoader(yaml.SafeLoader):
    """YAML's safe loader refusing a key given twice in one mapping (YAML says keys are
    unique; PyYAML would silently keep the last)."""


def _unique_mapping(loader: UniqueKeyLoader, node: yaml.MappingNode, deep: bool = False) -> Any:
    seen: set[Any] = set()
    for key_node, _ in node.value:
        if key_node.tag == "tag:yaml.org,2002:merge":
            continue
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


def parse_yaml(text: str, file: str | Path, error: type[InputError] = FileFormatError,
               problem: str = "YAML syntax error") -> Any:
    """Parse YAML text; a syntax error or a duplicate key raises ``error`` naming the file,
    line and column."""
    try:
        return yaml.load(text, Loader=UniqueKeyLoader)
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        where = f"line {mark.line + 1}, column {mark.column + 1}" if mark else "unknown place"
        raise error(f"{file}: {problem} at {where}: {exc.problem}") from None
    except yaml.YAMLError as exc:  # e.g. a reader error: a character YAML does not allow
        raise error(f"{file}: {problem}: {' '.join(str(exc).split())}") from None
    except (ValueError, RecursionError) as exc:  # e.g. an integer of thousands of digits
        raise error(f"{file}: {problem}: {type(exc).__name__}: {exc}") from None


def read_yaml(path: str | Path, error: type[InputError] = FileFormatError,
              missing: str = "not found", problem: str = "YAML syntax error") -> Any:
    """Read and parse a YAML file; a missing, unreadable or malformed file raises ``error``
    (``missing`` is the message for a file that does not exist)."""
    p = Path(path)
    try:
        text = read_text(p)
    except FileNotFoundError:
        raise error(f"{p}: {missing}") from None
    except IsADirectoryError:
        raise error(f"{p}: is a folder; expected a YAML file") from None
    except (OSError, UnreadableText) as exc:
        raise error(f"{p}: cannot read: {exc}") from None
    return parse_yaml(text, p, error, problem)
