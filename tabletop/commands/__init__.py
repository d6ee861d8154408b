"""Subcommands of the tabletop command line, one module each, and their shared argument checks."""

from __future__ import annotations

import math

from tabletop.frames import InputError


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
