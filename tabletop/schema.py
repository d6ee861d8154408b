"""A small schema language for config.yaml: typed fields with defaults, ranges and choices.

Each spec validates a parsed YAML value and returns the value with defaults filled in, or raises
:class:`ConfigError` naming the file, the key path (``engines[0].main.puck``) and what would be
right. Validation is strict: unknown keys, wrong types and out-of-range values are refused.
Mappings and lists go on past a refused key or item, so one refusal names every mistake found:
the first as its own message, then ``(and N more: PATH: WHAT; ...)`` (:class:`Mistakes`).
"""

from __future__ import annotations

import copy
import difflib
import math
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Mapping, Sequence

from tabletop.errors import InputError


class ConfigError(InputError):
    """A config value is wrong; the message names the file and the key path. ``at``: the key
    path and what is wrong without the file (``view.fps: unknown key ...``), '' when unknown."""

    def __init__(self, message: str, at: str = "") -> None:
        super().__init__(message)
        self.at = at


#: The mistakes after the first that a refusal says in full (:class:`Mistakes`).
MISTAKES_SHOWN = 3


class Mistakes(ConfigError):
    """The mistakes found under one key, each already in :attr:`Context.errors` (so a mapping
    or list holding that key does not count them twice): the first one's message, then
    ``(and N more: PATH: WHAT; ...)``, at most :data:`MISTAKES_SHOWN` of them said (one cause,
    a config copied away from its files, made 27 refusals of missing files: a line of 4,000
    characters), the rest counted; :attr:`found` keeps them all."""

    def __init__(self, found: Sequence[ConfigError], file: str) -> None:
        first, *more = found
        rest = [e.at or str(e).removeprefix(f"{file}: ") for e in more[:MISTAKES_SHOWN]]
        if len(more) > MISTAKES_SHOWN:
            rest.append(f"{len(more) - MISTAKES_SHOWN} more not shown")
        tail = f" (and {len(more)} more: {'; '.join(rest)})" if rest else ""
        super().__init__(f"{first}{tail}", first.at)
        self.found = list(found)


class _Required:
    def __repr__(self) -> str:
        return "REQUIRED"


REQUIRED: Any = _Required()


@dataclass(frozen=True)
class FileRef:
    """A file or folder a config value refers to: its key path (``engines[0].behavior``), the
    value as written, where it resolved, and whether a recording should carry its content."""

    key: str
    value: str
    resolved: Path
    embed: bool


@dataclass(frozen=True)
class Context:
    """Where the value came from: the config file (for messages) and its folder (for paths).

    ``refs`` collects every file the config refers to, so a recording can carry them.
    ``start_without``: a file an engine's action names (a MOP template or clip) is not read at
    validation: a kiosk's start, or the replay of one, whose build starts a character without
    the actions it cannot read (see :func:`tabletop.plugins.mop.build`)."""

    file: str
    base: Path
    refs: list[FileRef] = field(default_factory=list, compare=False)
    start_without: bool = False
    errors: list[ConfigError] = field(default_factory=list, compare=False)
    # what the specs read of files while validating, by (kind, path): a file named by several
    # keys is read once
    read: dict[tuple, Any] = field(default_factory=dict, compare=False)

    def error(self, path: str, message: str) -> ConfigError:
        at = f"{path or '<top>'}: {message}"
        return ConfigError(f"{self.file}: {at}", at)

    def note(self, exc: ConfigError) -> None:
        """Keep ``exc`` among :attr:`errors` (a :class:`Mistakes`' are kept already)."""
        if not isinstance(exc, Mistakes):
            self.errors.append(exc)

    def attempt(self, spec: Spec, value: Any, path: str) -> Any:
        """``spec.validate(value, path, self)``; None after keeping its refusal."""
        try:
            return spec.validate(value, path, self)
        except ConfigError as exc:
            self.note(exc)
            return None

    def settle(self, since: int) -> None:
        """Raise :class:`Mistakes` when errors were kept after the first ``since``."""
        if len(self.errors) > since:
            raise Mistakes(self.errors[since:], self.file)

    def refer(self, key: str, value: str, resolved: Path, embed: bool = True) -> None:
        """Note that the value at ``key`` names the file or folder ``resolved``."""
        self.refs.append(FileRef(key, value, Path(resolved), embed))


SHOWN_CHARS = 60   # a value quoted in a message: a whole file read as one string stays out


def shown(value: Any, limit: int = SHOWN_CHARS) -> str:
    """``repr(value)`` for a one-line message, cut to about ``limit`` characters."""
    text = repr(value)
    return text if len(text) <= limit else f"{text[:limit]}... ({len(text)} characters)"


def _type_name(value: Any) -> str:
    return {bool: "a boolean", int: "an integer", float: "a number", str: "a string",
            list: "a list", dict: "a mapping"}.get(type(value), type(value).__name__)


class Spec:
    """Base of all specs; ``default`` is REQUIRED when the key must be present."""

    default: Any = REQUIRED
    doc: str = ""

    def validate(self, value: Any, path: str, ctx: Context) -> Any:
        raise NotImplementedError

    def describe(self) -> str:
        raise NotImplementedError

    def wrong_type(self, value: Any, path: str, ctx: Context, hint: str = "") -> ConfigError:
        """The error for a value of the wrong type at ``path``: what was expected, what came."""
        got = "nothing (an empty value, or null)" if value is None else \
            f"{_type_name(value)} {shown(value)}"
        return ctx.error(path, f"expected {self.describe()}, got {got}{hint}")

    def mapping(self, value: Any, path: str, ctx: Context) -> dict:
        """``value`` as a mapping (nothing, null, is an empty one); else :meth:`wrong_type`."""
        if value is None:
            return {}
        if not isinstance(value, dict):
            raise self.wrong_type(value, path, ctx)
        return value


# "1e9", "1.0e9", "1e+9": YAML 1.1 (PyYAML) reads them as strings ("1.0e+9" is a number)
YAML_TEXT_NUMBER = re.compile(r"[-+]?([0-9]+\.?[0-9]*|\.[0-9]+)[eE][-+]?[0-9]+")


class Number(Spec):
    """An int or float (``integer=True``: int only) within [lo, hi]; ``unit`` ("seconds") is
    said in its refusals (a :class:`Record` key ending ``_s``, ``_m``, ... names it), and a
    value over ``hi`` that is in range read as thousandths is asked about as milliseconds or
    millimetres."""

    def __init__(self, default: Any = REQUIRED, lo: float | None = None, hi: float | None = None,
                 integer: bool = False, doc: str = "", unit: str = "") -> None:
        self.default, self.lo, self.hi, self.integer, self.doc = default, lo, hi, integer, doc
        self.unit = unit

    def describe(self) -> str:
        kind = "an integer" if self.integer else "a number"
        kind += f" of {self.unit}" if self.unit and not self.integer else ""
        kind += f" number of {self.unit}" if self.unit and self.integer else ""
        if self.lo is not None and self.hi is not None:
            return f"{kind} in [{self.lo}, {self.hi}]"
        if self.lo is not None:
            return f"{kind} >= {self.lo}"
        if self.hi is not None:
            return f"{kind} <= {self.hi}"
        return kind

    def validate(self, value: Any, path: str, ctx: Context) -> Any:
        ok_types = (int,) if self.integer else (int, float)
        if isinstance(value, bool) or not isinstance(value, ok_types):
            raise self.wrong_type(value, path, ctx, yaml_number_hint(value))
        if not self.integer:
            try:
                value = float(value)
            except OverflowError:
                raise ctx.error(path, f"expected {self.describe()}, got {shown(value)} "
                                      "(too large)") from None
        if isinstance(value, float) and not math.isfinite(value):  # NaN, inf
            raise ctx.error(path, f"expected {self.describe()}, got {shown(value)}")
        if (self.lo is not None and value < self.lo) or (self.hi is not None and value > self.hi):
            why = self.thousandths_hint(value)
            raise ctx.error(path, f"expected {self.describe()}, got {shown(value)} "
                                  f"(out of range{why})")
        return value

    def thousandths_hint(self, value: float) -> str:
        """For a value over ``hi`` that a thousandth of is in range, in seconds or metres:
        '; milliseconds given?' (or millimetres); else ''."""
        smaller = thousandths(self.unit, self.lo, self.hi, value)
        return f"; {smaller} given?" if smaller else ""


def thousandths(unit: str, lo: float | None, hi: float | None, *values: float) -> str:
    """The smaller unit ("milliseconds", "millimetres") that ``values`` of ``unit`` (seconds,
    metres) were likely given in: one over ``hi`` and every one's thousandth in [lo, hi];
    else ""."""
    smaller = THOUSANDTHS.get(unit, "")
    if not smaller or hi is None or not any(v > hi for v in values):
        return ""
    return smaller if all((lo is None or v / 1000 >= lo) and v / 1000 <= hi
                          for v in values) else ""


# the unit a key's name ends with (``stall_s``), said when its value is refused
UNIT_SUFFIXES = {"_s": "seconds", "_m": "metres", "_px": "pixels", "_hz": "Hz",
                 "_deg": "degrees", "_rad": "radians", "_mb": "megabytes"}
# a value a thousand times too large in these units was likely given in the smaller one
THOUSANDTHS = {"seconds": "milliseconds", "metres": "millimetres"}


def with_unit(spec: Spec, unit: str) -> Spec:
    """``spec`` with ``unit`` on its numbers (in a list, a range or optional) that name none;
    ``spec`` itself when there is nothing to name."""
    if not unit:
        return spec
    if isinstance(spec, Number) and not spec.unit:
        spec = copy.copy(spec)
        spec.unit = unit
    elif isinstance(spec, (Optional_, ListOf)):
        part = "inner" if isinstance(spec, Optional_) else "item"
        inner = getattr(spec, part)
        named = with_unit(inner, unit)
        if named is not inner:
            spec = copy.copy(spec)
            setattr(spec, part, named)
    return spec


def unit_of(key: str) -> str:
    """The unit ``key``'s name ends with (``stall_s``: seconds), or ''."""
    return next((u for end, u in UNIT_SUFFIXES.items() if key.endswith(end)), "")


def yaml_number_hint(value: Any) -> str:
    """For a string YAML read from a number with an exponent (``1e9``), how to write it so
    that YAML reads a number; else ''."""
    if not (isinstance(value, str) and YAML_TEXT_NUMBER.fullmatch(value.strip())):
        return ""
    m, e = value.strip().lower().split("e")
    m, e = m if "." in m else f"{m}.0", e if e[0] in "+-" else f"+{e}"
    return (" (YAML reads a number with an exponent as text unless it has a point and a signed "
            f"exponent: write {m}e{e})")


class Bool(Spec):
    def __init__(self, default: Any = REQUIRED, doc: str = "") -> None:
        self.default, self.doc = default, doc

    def describe(self) -> str:
        return "true or false"

    def validate(self, value: Any, path: str, ctx: Context) -> Any:
        if not isinstance(value, bool):
            raise self.wrong_type(value, path, ctx)
        return value


class Str(Spec):
    """A string, optionally one of ``choices``."""

    def __init__(self, default: Any = REQUIRED, choices: Sequence[str] | None = None,
                 doc: str = "") -> None:
        self.default, self.choices, self.doc = default, tuple(choices) if choices else None, doc

    def describe(self) -> str:
        return f"one of {', '.join(self.choices)}" if self.choices else "a string"

    def validate(self, value: Any, path: str, ctx: Context) -> Any:
        if not isinstance(value, str):
            raise self.wrong_type(value, path, ctx)
        if self.choices and value not in self.choices:
            raise ctx.error(path, f"expected {self.describe()}, got {shown(value)}")
        return value


class FilePath(Spec):
    """A path relative to the config file's folder; ``must_exist`` checks it at load time.

    ``kind`` is "file", "dir" or "any". Returns an absolute :class:`Path`. ``embed`` (default:
    ``must_exist``): a session recording carries the content, so it replays anywhere (an output
    folder such as the recorder's is not embedded). ``built_without``: under the context's
    ``start_without`` (a kiosk's start) the path is not checked: the build reads it and starts
    without what it cannot read, a file deleted or replaced by a folder as well as one corrupt.
    """

    def __init__(self, default: Any = REQUIRED, must_exist: bool = True, kind: str = "any",
                 doc: str = "", embed: bool | None = None, built_without: bool = False) -> None:
        self.default, self.must_exist, self.kind, self.doc = default, must_exist, kind, doc
        self.embed = must_exist if embed is None else embed
        self.built_without = built_without

    def describe(self) -> str:
        return {"file": "a path to a file", "dir": "a path to a folder"}.get(self.kind, "a path")

    def validate(self, value: Any, path: str, ctx: Context) -> Any:
        if not isinstance(value, str) or not value:
            raise self.wrong_type(value, path, ctx)
        p = Path(value).expanduser()
        if not p.is_absolute():
            p = ctx.base / p
        if self.must_exist and not (self.built_without and ctx.start_without):
            if not p.exists():
                raise ctx.error(path, f"{shown(value)} does not exist (looked for {p})")
            if self.kind == "file" and not p.is_file():
                raise ctx.error(path, f"{shown(value)} is not a file")
            if self.kind == "dir" and not p.is_dir():
                raise ctx.error(path, f"{shown(value)} is not a folder")
        ctx.refer(path, value, p, self.embed)
        return p


class Optional_(Spec):
    """``None`` or a value of ``inner``; defaults to None."""

    def __init__(self, inner: Spec, default: Any = None, doc: str = "") -> None:
        self.inner, self.default, self.doc = inner, default, doc or inner.doc

    def describe(self) -> str:
        return f"{self.inner.describe()} or null"

    def validate(self, value: Any, path: str, ctx: Context) -> Any:
        return None if value is None else self.inner.validate(value, path, ctx)


class ListOf(Spec):
    """A list of items of one spec, with a length range."""

    def __init__(self, item: Spec, default: Any = REQUIRED, min_len: int = 0,
                 max_len: int | None = None, doc: str = "") -> None:
        self.item, self.default, self.min_len, self.max_len, self.doc = (
            item, default, min_len, max_len, doc)

    def describe(self) -> str:
        lo, hi = self.min_len, self.max_len
        n = ("" if hi is None and lo == 0 else f"at least {lo}" if hi is None
             else f"{lo}" if lo == hi else f"{lo} to {hi}")
        items = f" ({n} item{'' if n.endswith(' 1') or n == '1' else 's'})" if n else ""
        return f"a list{items} of {self.item.describe()}"

    def validate(self, value: Any, path: str, ctx: Context) -> Any:
        if not isinstance(value, list):
            raise self.wrong_type(value, path, ctx)
        if len(value) < self.min_len or (self.max_len is not None and len(value) > self.max_len):
            got = f"{len(value)} item{'' if len(value) == 1 else 's'}"
            raise ctx.error(path, f"expected {self.describe()}, got {got}")
        since = len(ctx.errors)
        out = [ctx.attempt(self.item, v, f"{path}[{i}]") for i, v in enumerate(value)]
        ctx.settle(since)
        return out


class Range(ListOf):
    """``[least, most]``: two numbers of ``item``, the first not above the second (and, with
    ``contains``, that value between them)."""

    def __init__(self, item: Spec, default: Any = REQUIRED, contains: float | None = None,
                 doc: str = "") -> None:
        super().__init__(item, default, 2, 2, doc)
        self.contains = contains

    def describe(self) -> str:
        held = "" if self.contains is None else f" holding {self.contains:g}"
        return f"[least, most]{held}, each {self.item.describe()}"

    def validate(self, value: Any, path: str, ctx: Context) -> Any:
        lo, hi = super().validate(value, path, ctx)
        c = self.contains
        if lo > hi or (c is not None and not lo <= c <= hi):
            raise ctx.error(path, f"expected {self.describe()}, got [{lo:g}, {hi:g}]")
        return [lo, hi]


class MapOf(Spec):
    """A mapping from free-form string keys to values of one spec (e.g. character -> sprite)."""

    def __init__(self, value: Spec, default: Any = REQUIRED, doc: str = "") -> None:
        self.value, self.default, self.doc = value, default, doc

    def describe(self) -> str:
        return f"a mapping of names to {self.value.describe()}"

    def validate(self, value: Any, path: str, ctx: Context) -> Any:
        value = self.mapping(value, path, ctx)
        since = len(ctx.errors)
        out = {str(k): ctx.attempt(self.value, v, _join(path, str(k))) for k, v in value.items()}
        ctx.settle(since)
        return out


class Record(Spec):
    """A mapping with known keys; unknown keys are refused, missing ones take their defaults."""

    def __init__(self, fields: Mapping[str, Spec], default: Any = None, doc: str = "",
                 check: Callable[[dict, str, Context], None] | None = None) -> None:
        self.fields = {k: with_unit(f, unit_of(k)) for k, f in fields.items()}
        self.doc, self.check = doc, check
        # A record whose fields all have defaults may be omitted entirely.
        self.default = default if default is not None else (
            {} if all(f.default is not REQUIRED for f in self.fields.values()) else REQUIRED)

    def describe(self) -> str:
        return f"a mapping with keys {', '.join(self.fields)}"

    def validate(self, value: Any, path: str, ctx: Context) -> Any:
        value = self.mapping(value, path, ctx)
        out: dict[str, Any] = {}
        since = len(ctx.errors)
        for key in value:
            if key not in self.fields:
                known = ", ".join(sorted(self.fields)) or "none"
                close = difflib.get_close_matches(str(key), sorted(self.fields), n=1)
                hint = f"; did you mean {close[0]!r}?" if close else ""
                ctx.note(ctx.error(_join(path, str(key)),
                                   f"unknown key (known keys here: {known}){hint}"))
        for key, spec in self.fields.items():
            sub = _join(path, key)
            if key in value:
                out[key] = ctx.attempt(spec, value[key], sub)
            elif spec.default is REQUIRED:
                ctx.note(ctx.error(sub, f"missing; expected {spec.describe()}"))
            else:
                d = spec.default
                # A default path is relative to the config's folder, like a written one.
                out[key] = ctx.attempt(spec, d, sub) if isinstance(spec, (Record, FilePath)) else d
        ctx.settle(since)   # the check below reads every key valid
        if self.check is not None:
            self.check(out, path, ctx)
        return out


def _join(path: str, key: str) -> str:
    return f"{path}.{key}" if path else key
