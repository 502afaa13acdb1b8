"""Numbers written as text (``"1/3"``, ``"0.75"``, ``"1e3"``): one rule, read exactly and in bounded time.

The rule, for every number the suite reads as text (the command line's options,
the quoted numbers of grid and walls files such as ``m = "1/3"``, the values of
``--tuning``): :data:`NUMBER_RULE`. A number is ASCII digits with an optional
leading ``-``, an optional decimal point and an optional decimal exponent
(``e``/``E``, its own sign ``-`` or ``+``, as Python prints ``1e+16``), or a
fraction of two such integers (``1/3``). Leading zeros are allowed (``007`` is 7,
``00`` is 0, which an option that needs a positive count then refuses as zero).
Refused: a leading ``+``, spaces anywhere, ``_`` between digits (``1_0`` is not
10: Python's ``Fraction`` and ``float`` read it so, and a typo became a wall ten
times larger), digits of other scripts (``float`` reads ``"٣"`` as 3),
``inf``/``nan``, hexadecimal. TOML's own numbers (``rows = 12``) are read by
TOML, as its specification defines them, before any of this.

``fractions.Fraction`` reads ``"1e999999999"`` by building the integer
``10**999999999``: ``xcheck micro --t 1e999999999`` was still parsing after
minutes. :func:`exact` refuses a decimal exponent beyond
:data:`MAX_EXPONENT` before ``Fraction`` sees it.

:func:`received_number` reads the other way in: the value a user's model returned (to the pytest
plugin, or as a sweep's column), a real number or a one-line ``TypeError`` naming where it came from.
"""

from __future__ import annotations

import math
import numbers
import re
from collections.abc import Sequence
from fractions import Fraction

#: The largest decimal exponent read (either sign): far beyond the doubles
#: (1e308, 5e-324), and ``10**1000`` is built in microseconds.
MAX_EXPONENT = 1000
#: The rule of a number written as text, as the messages word it (module docstring).
NUMBER_RULE = "ASCII digits, a leading '-' at most; no '+', spaces or '_'"
#: A decimal (``-2.5e-1``, ``.5``, ``5.``) or a fraction of integers (``1/3``), ASCII only.
_NUMBER = re.compile(r"-?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE](?P<exp>[-+]?[0-9]+))?|-?[0-9]+/[0-9]+")


class OutOfRange(ValueError):
    """A number whose decimal exponent is beyond :data:`MAX_EXPONENT`, or of more digits than Python
    converts to an integer (``sys.get_int_max_str_digits()``)."""


def exact(name: str, text: str) -> Fraction:
    """``text`` as an exact fraction, when it follows :data:`NUMBER_RULE` (module docstring).

    Raises:
        OutOfRange: a decimal exponent beyond :data:`MAX_EXPONENT`, naming ``name``.
        ValueError: not a number or a fraction under the rule (``"1/0"`` included), naming ``name``.
    """
    text = str(text)
    match = _NUMBER.fullmatch(text)
    if match is None:
        raise ValueError(f"{name} must be a number or a fraction such as 1/3 ({NUMBER_RULE}), got {text!r}")
    if match.group("exp") is not None:
        digits = match.group("exp").lstrip("-+").lstrip("0")
        if len(digits) > len(str(MAX_EXPONENT)) or int(digits or "0") > MAX_EXPONENT:
            raise OutOfRange(f"{name} is out of range (a decimal exponent beyond +-{MAX_EXPONENT}), got {text!r}")
    try:
        return Fraction(text)
    except ZeroDivisionError:  # 1/0
        raise ValueError(f"{name} must be a number or a fraction such as 1/3, got {text!r}") from None
    except ValueError:  # more digits than Python converts (sys.get_int_max_str_digits(), 4,300)
        raise OutOfRange(f"{name} is out of range (too many digits), got {text[:20]!r}...") from None


#: The largest denominator :func:`shortest` looks for, and how near (in units in the last place) the value
#: must lie to the fraction: the noise of one or two divisions of numbers written in decimals.
SIMPLE_DENOMINATOR = 10**6
NOISE_ULPS = 4


def shortest(x: float) -> float:
    """``x``, or the double nearest a fraction of denominator at most :data:`SIMPLE_DENOMINATOR` when ``x`` lies
    within :data:`NOISE_ULPS` of it: a ratio of numbers written in decimals printed as written
    (``0.1 / 0.3`` is ``0.33333333333333337``; the wall's ``m`` is 1/3, ``0.3333333333333333``). For output
    only: what is computed keeps its own value."""
    if not math.isfinite(x) or x == 0.0:
        return x
    near = float(Fraction(x).limit_denominator(SIMPLE_DENOMINATOR))
    return near if math.fabs(near - x) <= NOISE_ULPS * math.ulp(x) else x


def received_number(where: str, value: object) -> float:
    """``value`` as a float when it is a real number (a Python or NumPy integer or float; NaN allowed).

    A model that returns ``None``, a string or an array is a bug of the test, named here rather than
    turned into a number (``"0.5"``) or a bare ``TypeError``.

    Args:
        where: the case, the method and the call, e.g. ``"Set 12 / my model: xcheck_table.add"``.
        value: what the model gave.

    Raises:
        TypeError: ``"{where} needs a number, got '0.5' (str)"``.
    """
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{where} needs a number, got {value!r} ({type(value).__name__})")
    try:
        return float(value)
    except OverflowError:  # an int beyond the doubles (10**400): infinite, outside every reference
        return -math.inf if str(value).lstrip().startswith("-") else math.inf


def power_law(sizes: Sequence[float], values: Sequence[float]) -> tuple[float, float] | None:
    """``(k, c)`` of ``value ~ c size**k``, the least-squares line in log-log, over the pairs whose both numbers
    are positive and finite; ``None`` with fewer than two distinct sizes among them. The one fit of run time
    against blocks (the report's scaling table, the sweep page's time figure)."""
    import numpy as np

    pairs = [(x, y) for x, y in zip(sizes, values, strict=True)
             if math.isfinite(x) and math.isfinite(y) and x > 0 and y > 0]
    if len({x for x, _ in pairs}) < 2:
        return None
    k, log_c = np.polyfit(np.log([x for x, _ in pairs]), np.log([y for _, y in pairs]), 1)
    return float(k), float(math.exp(log_c))
