"""Numbers written as text (``"1/3"``, ``"0.75"``, ``"1e3"``): read exactly and in bounded time.

``fractions.Fraction`` reads ``"1e999999999"`` by building the integer
``10**999999999``: ``xcheck micro --t 1e999999999`` (and ``--rows``,
``--workers``, a grid entry ``t = ["1e999999999"]``) was still parsing after
minutes. :func:`exact` refuses a decimal exponent beyond
:data:`MAX_EXPONENT` before ``Fraction`` sees it; everything else reads as
``Fraction`` reads it (a fraction ``1/3``, a decimal, an exponent, ``_``
between digits).

:func:`received_number` reads the other way in: the value a user's model returned (to the pytest
plugin, or as a sweep's column), a real number or a one-line ``TypeError`` naming where it came from.
"""

from __future__ import annotations

import math
import numbers
import re
from fractions import Fraction

#: The largest decimal exponent read (either sign): far beyond the doubles
#: (1e308, 5e-324), and ``10**1000`` is built in microseconds.
MAX_EXPONENT = 1000
#: The exponent of a decimal at the end of the text (Fraction's syntax: digits with single ``_`` between).
_EXPONENT = re.compile(r"[eE]([-+]?)(\d+(?:_\d+)*)\s*\Z")


class OutOfRange(ValueError):
    """A number whose decimal exponent is beyond :data:`MAX_EXPONENT`."""


def exact(name: str, text: str) -> Fraction:
    """``text`` as an exact fraction.

    Raises:
        OutOfRange: a decimal exponent beyond :data:`MAX_EXPONENT`, naming ``name``.
        ValueError: not a number or a fraction (``ZeroDivisionError`` for ``"1/0"`` included),
            naming ``name``.
    """
    text = str(text)
    match = _EXPONENT.search(text)
    if match is not None:
        digits = match.group(2).replace("_", "").lstrip("0")
        if len(digits) > len(str(MAX_EXPONENT)) or int(digits or "0") > MAX_EXPONENT:
            raise OutOfRange(f"{name} is out of range (a decimal exponent beyond +-{MAX_EXPONENT}), got {text!r}")
    try:
        return Fraction(text.strip())
    except (ValueError, ZeroDivisionError):
        raise ValueError(f"{name} must be a number or a fraction such as 1/3, got {text!r}") from None


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
