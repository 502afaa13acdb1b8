"""The wall-parameter checks and their messages, one vocabulary for the whole suite.

Every validator of a wall parameter (``macro.MacroWall``, ``macro.sweep``,
``comparison.wall.WallSpec`` and its ``from_paper``, the scene files and the
command line) raises :class:`ValueError` with one of these messages, naming the
parameter as the caller spells it (``block_length``, ``t``, ``rows[1]`` for the
entry of storey 2, ...). ``micro`` may not import this module (``macro`` and
``micro`` stay independent); it spells the same templates out, and a parity test
(``tests/comparison/test_wall_vocabulary.py``) holds the two together.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Callable, Sequence
from typing import TypeVar

#: A number > 0 (finite; not a bool).
POSITIVE = "{name} must be a positive number, got {value!r}"
#: A number >= 0 (finite; not a bool).
NON_NEGATIVE = "{name} must be zero or a positive number, got {value!r}"
#: An integer > 0 (an integer-valued float is accepted; not a bool).
POSITIVE_INT = "{name} must be a positive integer, got {value!r}"
#: A number in the half-open interval ``(lo, hi]``.
IN_RANGE = "{name} must be in ({lo:g}, {hi:g}], got {value!r}"
#: A per-storey tuple of the wrong length.
PER_STOREY = "{name} must have one value per storey: got {count} values for {storeys} storeys"
#: A per-storey parameter that is not a sequence.
SEQUENCE = "{name} must be a tuple with one value per storey (storey 1 = top), got {value!r}"
#: A wall without storeys.
NO_STOREY = "{name}: a wall needs at least one storey"
#: Rows that cannot be split equally over the storeys.
UNEQUAL_STOREYS = "rows: {rows!r} rows cannot be split equally over {storeys!r} storeys"
#: One of a few named choices.
CHOICE = "{name} must be one of {choices}, got {value!r}"

T = TypeVar("T")


def _real(value: object) -> float | None:
    """``value`` as a float, or ``None`` when it is not a number (bools and strings are not numbers here)."""
    if isinstance(value, bool):
        return None
    if isinstance(value, numbers.Real):
        return float(value)
    return None


def positive(name: str, value: object) -> float:
    """``value`` as a finite float > 0.

    Raises:
        ValueError: :data:`POSITIVE`, naming ``name``.
    """
    x = _real(value)
    if x is None or not math.isfinite(x) or x <= 0.0:
        raise ValueError(POSITIVE.format(name=name, value=value))
    return x


def non_negative(name: str, value: object) -> float:
    """``value`` as a finite float >= 0.

    Raises:
        ValueError: :data:`NON_NEGATIVE`, naming ``name``.
    """
    x = _real(value)
    if x is None or not math.isfinite(x) or x < 0.0:
        raise ValueError(NON_NEGATIVE.format(name=name, value=value))
    return x


def positive_int(name: str, value: object) -> int:
    """``value`` as an int > 0 (``12.0`` is accepted as 12).

    Raises:
        ValueError: :data:`POSITIVE_INT`, naming ``name``.
    """
    x = _real(value)
    if x is None or not math.isfinite(x) or not x.is_integer() or x <= 0:
        raise ValueError(POSITIVE_INT.format(name=name, value=value))
    return int(x)


def in_range(name: str, value: object, lo: float, hi: float) -> float:
    """``value`` as a float in ``(lo, hi]``; below ``lo`` it must first be positive when ``lo == 0``.

    Raises:
        ValueError: :data:`POSITIVE` for a non-number or a value <= 0 when
            ``lo == 0``, else :data:`IN_RANGE`.
    """
    x = positive(name, value) if lo == 0.0 else _real(value)
    if x is None or not math.isfinite(x) or not lo < x <= hi:
        raise ValueError(IN_RANGE.format(name=name, lo=lo, hi=hi, value=value))
    return x


def choice(name: str, value: T, choices: Sequence[T]) -> T:
    """``value`` when it is one of ``choices``.

    Raises:
        ValueError: :data:`CHOICE`, naming ``name``.
    """
    if value not in choices:
        raise ValueError(CHOICE.format(name=name, choices=" or ".join(repr(c) for c in choices), value=value))
    return value


def per_storey(name: str, values: object, storeys: int | None, check: Callable[[str, object], T]) -> tuple[T, ...]:
    """A per-storey tuple (storey 1 = top), every entry checked as ``name[i]``.

    Args:
        name: the parameter.
        values: a sequence with one entry per storey.
        storeys: the expected number of storeys (``None``: any, at least one).
        check: the check of one entry (:func:`positive`, :func:`non_negative`
            or :func:`positive_int`).

    Raises:
        ValueError: :data:`SEQUENCE`, :data:`NO_STOREY`, :data:`PER_STOREY` or the entry's message.
    """
    if isinstance(values, (str, bytes)) or not hasattr(values, "__len__") or not hasattr(values, "__iter__"):
        raise ValueError(SEQUENCE.format(name=name, value=values))
    entries = tuple(values)
    if not entries:
        raise ValueError(NO_STOREY.format(name=name))
    if storeys is not None and len(entries) != storeys:
        raise ValueError(PER_STOREY.format(name=name, count=len(entries), storeys=storeys))
    return tuple(check(f"{name}[{i}]", v) for i, v in enumerate(entries))


def rows_per_storey(rows: int, storeys: int) -> int:
    """The rows of each storey when ``rows`` are split equally over ``storeys``.

    Raises:
        ValueError: :data:`UNEQUAL_STOREYS`.
    """
    if rows % storeys:
        raise ValueError(UNEQUAL_STOREYS.format(rows=rows, storeys=storeys))
    return rows // storeys
