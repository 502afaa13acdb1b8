"""The wall-parameter checks and their messages, one vocabulary for the whole suite.

Every validator of a wall parameter (``macro.MacroWall``, ``macro.sweep``,
``comparison.domain.wall.WallSpec`` and its ``from_paper``, the scene files and the
command line) raises :class:`ValueError` with one of these messages, naming the
parameter as the caller spells it (``block_length``, ``t``, ``rows[1]`` for the
entry of storey 2, ...). ``micro`` may not import this module (``macro`` and
``micro`` stay independent); it spells the same templates out, and a parity test
(``tests/comparison/test_wall_vocabulary.py``) holds the two together.

Physical bounds (:func:`wall_bounds`, and :func:`macro.paper.paper_walls` for
the paper's parameters) keep every wall inside the range where both models are
exact enough in double precision, so that no input reaches a solver that it
cannot take:

* every dimensional number (lengths, unit weight) lies in
  (:data:`MIN_MAGNITUDE`, :data:`MAX_MAGNITUDE`]: any consistent system of
  units (mm to km, N to MN) stays far inside, and the products of up to five
  such numbers that a moment needs stay within 1e±150, far from the limits of
  a double (1e±308), so nothing overflows or underflows to zero;
* lengths in block heights are at most :data:`MAX_RATIO` (and a thickness or a
  block length at least ``1/MAX_RATIO``): the macro search runs over crack
  slopes up to ``v/b``, which a double resolves to ``(v/b) 2e-16`` relative
  (2e-10 at the bound; at ``l/b = 1e16`` the crack angle is 90° to the last
  bit and Eq. (10) turns to NaN or negative values), and the micro LP's
  coefficients (lever arms in block heights) stay within the range its solvers
  scale;
* a wall is at least one block long (``length >= block_length``): the paper's
  parts A-D assume a half-block column over the hinge and rows beyond it (for
  ``L < v`` the weight of part B comes out negative), and running bond needs a
  whole block in every course;
* a floor load is at most :data:`MAX_RATIO` times the weight of one row of its
  storey per unit length;
* the friction coefficient lies in (:data:`MIN_FRICTION`, :data:`MAX_FRICTION`]:
  dry joints have 0.3-1; below 1e-3 the friction terms of the LP fall to the
  solvers' coefficient tolerances relative to the lever arms, and above 10
  they dwarf the weights they are compared with.
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
IN_RANGE = "{name} must be in ({lo}, {hi}], got {value!r}"
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
#: A number in the closed interval ``[lo, hi]``.
IN_CLOSED_RANGE = "{name} must be in [{lo}, {hi}], got {value!r}"
#: A number above a physical bound (:data:`MAX_RATIO`); a reason follows after a colon.
AT_MOST = "{name} must be at most {hi}, got {value!r}"
#: A number below a physical bound (a wall at least one block long); a reason follows after a colon.
AT_LEAST = "{name} must be at least {lo}, got {value!r}"
#: A wall whose search or model would not fit in the memory available.
TOO_LARGE = "{name}: {what} needs an estimated {need:.3g} GB of memory, but only {have:.3g} GB are available"

#: Dimensional numbers (lengths, unit weight) lie in (MIN_MAGNITUDE, MAX_MAGNITUDE] (module docstring).
MIN_MAGNITUDE = 1e-30
MAX_MAGNITUDE = 1e30
#: Largest length in block heights, and largest floor load in row weights (module docstring).
MAX_RATIO = 1e6
#: The friction coefficient lies in (MIN_FRICTION, MAX_FRICTION] (module docstring).
MIN_FRICTION = 1e-3
MAX_FRICTION = 10.0
#: Relative slack of the bounds ``block_length <= length <= MAX_RATIO block heights`` (``o/t`` against
#: ``1/m`` and against ``MAX_RATIO`` in floating point: ``o/t`` at ``t = o/1e6`` comes out a unit in the last
#: place above or below 1e6).
LENGTH_SLACK = 1e-12
#: Work estimated below this many bytes is not checked against the memory available (saves reading it).
ALWAYS_FITS = 1 << 26


class TooLarge(ValueError):
    """A wall whose estimated memory exceeds what is available (bad input, message :data:`TOO_LARGE`)."""


T = TypeVar("T")


def exact(bound: float) -> str:
    """A bound as a message prints it: shortest (``1e+06``, ``4``) where that is its value, else with every
    digit it has (166666.66666666666, not 166667, which reads as the very value it refuses)."""
    x = float(bound)
    short = f"{x:g}"
    return short if float(short) == x else repr(x)

def _real(value: object) -> float | None:
    """``value`` as a float, or ``None`` when it is not a number (bools and strings are not numbers here)."""
    if isinstance(value, bool):
        return None
    if isinstance(value, numbers.Real):
        try:
            return float(value)
        except OverflowError:  # an int beyond the doubles (10**400): infinite, for the checks to refuse
            return -math.inf if str(value).lstrip().startswith("-") else math.inf
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


def in_range(name: str, value: object, lo: float, hi: float, why: str = "") -> float:
    """``value`` as a float in ``(lo, hi]``; when ``lo >= 0`` it must first be positive.

    Args:
        name: the parameter.
        value: its value.
        lo, hi: the bounds.
        why: the reason for the bounds, appended to the message after a colon.

    Raises:
        ValueError: :data:`POSITIVE` for a non-number or a value <= 0 when
            ``lo >= 0``, else :data:`IN_RANGE`.
    """
    x = positive(name, value) if lo >= 0.0 else _real(value)
    if x is None or not math.isfinite(x) or not lo < x <= hi:
        raise ValueError(IN_RANGE.format(name=name, lo=exact(lo), hi=exact(hi), value=value)
                         + (f": {why}" if why else ""))
    return x


def magnitude(name: str, value: object) -> float:
    """``value`` as a positive dimensional number in (:data:`MIN_MAGNITUDE`, :data:`MAX_MAGNITUDE`].

    Raises:
        ValueError: :data:`POSITIVE` or :data:`IN_RANGE`, naming ``name``.
    """
    return in_range(name, value, MIN_MAGNITUDE, MAX_MAGNITUDE, "dimensional values are limited to this range")


def friction(name: str, value: object) -> float:
    """``value`` as a friction coefficient in (:data:`MIN_FRICTION`, :data:`MAX_FRICTION`].

    Raises:
        ValueError: :data:`POSITIVE` or :data:`IN_RANGE`, naming ``name``.
    """
    return in_range(name, value, MIN_FRICTION, MAX_FRICTION, "dry-joint friction coefficients lie near 0.3-1")


def choice(name: str, value: T, choices: Sequence[T]) -> T:
    """``value`` when it is one of ``choices``.

    Raises:
        ValueError: :data:`CHOICE`, naming ``name``.
    """
    try:
        known = any(isinstance(value, type(c)) and value == c for c in choices)
    except (TypeError, ValueError):  # an array compares element by element
        known = False
    if not known:
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


def _within(name: str, x: float, lo: float, hi: float) -> None:
    """A length already checked as a positive number, within ``(lo, hi]`` block heights (:data:`IN_RANGE`)."""
    if not lo < x <= hi:
        raise ValueError(IN_RANGE.format(name=name, lo=exact(lo), hi=exact(hi), value=x)
                         + f": at most {MAX_RATIO:g} block heights")


#: The keyword arguments of :func:`wall_bounds` (attributes of every wall type).
WALL_FIELDS = ("length", "block_length", "block_height", "rows", "thickness", "overload", "unit_weight")


def wall_bounds(
    *,
    length: float,
    block_length: float,
    block_height: float,
    rows: Sequence[int],
    thickness: Sequence[float],
    overload: Sequence[float],
    unit_weight: float,
) -> None:
    """The physical bounds of a dimensional wall whose every entry is already checked (module docstring).

    Raises:
        ValueError: naming the first parameter out of bounds, with :data:`IN_RANGE`,
            :data:`AT_MOST` or :data:`AT_LEAST` and the reason after a colon.
    """
    b = block_height
    _within("block_length", block_length, b / MAX_RATIO, b * MAX_RATIO)
    if length < block_length * (1.0 - LENGTH_SLACK):
        raise ValueError(
            AT_LEAST.format(name="length", lo=exact(block_length), value=length)
            + ": a running-bond wall is at least one block long"
        )
    if length > b * MAX_RATIO * (1.0 + LENGTH_SLACK):
        raise ValueError(
            AT_MOST.format(name="length", hi=exact(b * MAX_RATIO), value=length)
            + f": at most {MAX_RATIO:g} block heights"
        )
    if sum(rows) > MAX_RATIO:
        raise ValueError(AT_MOST.format(name="rows", hi=exact(MAX_RATIO), value=sum(rows)) + ": rows in all")
    for i, (t, q) in enumerate(zip(thickness, overload, strict=True)):
        _within(f"thickness[{i}]", t, b / MAX_RATIO, b * MAX_RATIO)
        row_weight = unit_weight * b * t
        if q > MAX_RATIO * row_weight:
            raise ValueError(
                AT_MOST.format(name=f"overload[{i}]", hi=exact(MAX_RATIO * row_weight), value=q)
                + f": at most {MAX_RATIO:g} times the weight of one row per unit length"
            )


def available_memory_bytes() -> int | None:
    """Memory the process may still use: ``MemAvailable`` of ``/proc/meminfo`` (Linux), else ``None``.

    ``micro.geometry`` has its own copy (``macro`` and ``micro`` share no code).
    """
    try:
        with open("/proc/meminfo", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    return None


def fits_in_memory(name: str, what: str, need: int, budget: int | None = None) -> None:
    """Refuse work whose estimated memory ``need`` (bytes) exceeds ``budget`` (default: what is available).

    Raises:
        TooLarge: :data:`TOO_LARGE`, naming ``name``.
    """
    if need <= ALWAYS_FITS and budget is None:
        return
    have = available_memory_bytes() if budget is None else budget
    if have is not None and need > have:
        gb = need / 1e9 if need < 1e300 else math.inf  # an int beyond the doubles cannot be divided as one
        raise TooLarge(TOO_LARGE.format(name=name, what=what, need=gb, have=have / 1e9))
