"""Checks of the micro wall's parameters: numbers, counts, per-storey lists and the physical bounds.

The same bounds and messages as the macro model's checks (written again here:
``micro`` never imports ``macro``), used by :func:`micro.geometry.build_wall`.
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Sequence

import numpy as np


def _number(name: str, value: object, *, positive: bool = True) -> float:
    """``value`` as a finite float, positive (or, with ``positive=False``, zero
    or positive); else a ``ValueError`` in the shared wording."""
    kind = "a positive number" if positive else "zero or a positive number"
    x = math.nan
    if isinstance(value, (int, float, np.integer, np.floating, str)) and not isinstance(value, bool):
        with contextlib.suppress(ValueError, OverflowError):  # 10**400: not finite, refused below
            x = float(value)
    if not math.isfinite(x) or (x <= 0.0 if positive else x < 0.0):
        raise ValueError(f"{name} must be {kind}, got {value!r}")
    return x


def _positive_int(name: str, value: object) -> int:
    """``value`` as a positive int (an integral float is accepted)."""
    if isinstance(value, (int, np.integer, float)) and not isinstance(value, bool):
        x = math.nan
        with contextlib.suppress(OverflowError):  # 10**400: refused below (the bounds would refuse it too)
            x = float(value)
        if math.isfinite(x) and x == int(x) and x > 0:
            return int(x)
    raise ValueError(f"{name} must be a positive integer, got {value!r}")


def _per_storey(name: str, values: object, n: int | None, *, positive: bool) -> tuple[float, ...]:
    if isinstance(values, (str, bytes)) or not hasattr(values, "__len__"):
        raise ValueError(f"{name} must be a tuple with one value per storey (storey 1 = top), got {values!r}")
    vals: tuple[object, ...] = tuple(values)  # type: ignore[arg-type]
    if n is not None and len(vals) != n:
        raise ValueError(f"{name} must have one value per storey: got {len(vals)} values for {n} storeys")
    return tuple(_number(f"{name}[{i}]", v, positive=positive) for i, v in enumerate(vals))


#: Physical bounds, the values of ``macro.checks`` (``micro`` may not import
#: ``macro``; a parity test holds them together). Dimensional values lie in
#: (MIN_MAGNITUDE, MAX_MAGNITUDE]; lengths are at most MAX_RATIO block heights
#: (a thickness and a block length at least 1/MAX_RATIO of one); a floor load
#: is at most MAX_RATIO row weights; the friction coefficient lies in
#: (MIN_FRICTION, MAX_FRICTION]. Inside them every LP coefficient (lever arms
#: in block heights, loads in block weights) stays within the range the solvers
#: scale, and nothing overflows when the loads are built; beyond them HiGHS
#: refused the model (``--p 1e300``).
MIN_MAGNITUDE, MAX_MAGNITUDE = 1e-30, 1e30
MAX_RATIO = 1e6
#: Relative slack of ``length <= MAX_RATIO`` block heights (``o/t`` at ``t = o/1e6`` is a unit in the last
#: place above 1e6 for some ``o``), as ``macro.checks.LENGTH_SLACK``.
LENGTH_SLACK = 1e-12
MIN_FRICTION, MAX_FRICTION = 1e-3, 10.0


def _within(name: str, x: float, lo: float, hi: float, why: str) -> None:
    if not lo < x <= hi:
        raise ValueError(f"{name} must be in ({_exact(lo)}, {_exact(hi)}], got {x!r}: {why}")


def _exact(bound: float) -> str:
    """A bound printed shortest where that is its value, else with every digit (as ``macro.checks.exact``:
    ``micro`` does not import ``macro``)."""
    short = f"{bound:g}"
    return short if float(short) == bound else repr(float(bound))


def physical_bounds(
    length: float,
    block_length: float,
    block_height: float,
    unit_weight: float,
    friction: float,
    rows: Sequence[int],
    thickness: Sequence[float],
    overload: Sequence[float],
) -> None:
    """The physical bounds above, on values already checked one by one.

    Raises:
        ValueError: naming the first parameter out of bounds, worded as ``macro.checks`` words it.
    """
    for name, x in (
        ("length", length),
        ("block_length", block_length),
        ("block_height", block_height),
        ("unit_weight", unit_weight),
    ):
        _within(name, x, MIN_MAGNITUDE, MAX_MAGNITUDE, "dimensional values are limited to this range")
    _within("friction", friction, MIN_FRICTION, MAX_FRICTION, "dry-joint friction coefficients lie near 0.3-1")
    b, R = block_height, MAX_RATIO
    _within("block_length", block_length, b / R, b * R, f"at most {R:g} block heights")
    if length > b * R * (1.0 + LENGTH_SLACK):
        raise ValueError(f"length must be at most {b * R:g}, got {length!r}: at most {R:g} block heights")
    if sum(rows) > R:
        raise ValueError(f"rows must be at most {R:g}, got {sum(rows)!r}: rows in all")
    for i, (t, q) in enumerate(zip(thickness, overload, strict=True)):
        _within(f"thickness[{i}]", t, b / R, b * R, f"at most {R:g} block heights")
        if q > R * unit_weight * b * t:
            raise ValueError(
                f"overload[{i}] must be at most {R * unit_weight * b * t:g}, got {q!r}: "
                f"at most {R:g} times the weight of one row per unit length"
            )
