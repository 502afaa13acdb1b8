"""Numbers written as text: exact, and read in bounded time (comparison/numbers.py)."""

from __future__ import annotations

import time
from fractions import Fraction

import pytest

from comparison.numbers import MAX_EXPONENT, OutOfRange, exact


@pytest.mark.parametrize(
    ("text", "value"),
    [("1/3", Fraction(1, 3)), (" 0.75 ", Fraction(3, 4)), ("1e3", Fraction(1000)), ("-2.5E-1", Fraction(-1, 4)),
     ("1_000", Fraction(1000)), (f"1e{MAX_EXPONENT}", Fraction(10**MAX_EXPONENT)),
     (f"1e-{MAX_EXPONENT}", Fraction(1, 10**MAX_EXPONENT)), ("5e0_1", Fraction(5 * 10**1))],
)
def test_what_fraction_reads_is_read_alike(text: str, value: Fraction) -> None:
    assert exact("t", text) == value


@pytest.mark.parametrize(
    "text", ["1e999999999", "-1e999999999", "1e-999999999", f"1e{MAX_EXPONENT + 1}", "0e99999", "1e" + "9" * 5000,
             "2.5E+0000000000000000000000000000000000001001"],
)
def test_an_exponent_beyond_the_bound_is_refused_at_once_naming_the_parameter(text: str) -> None:
    t0 = time.process_time()
    with pytest.raises(OutOfRange, match=r"^rows is out of range"):
        exact("rows", text)
    assert time.process_time() - t0 < 0.5  # before: Fraction built 10**999999999 (minutes)


def test_leading_zeros_of_an_exponent_within_the_bound_are_read() -> None:
    assert exact("t", "1e0000000000000000000000003") == 1000


@pytest.mark.parametrize("text", ["x", "", "1/0", "1e", "1/3/4", "nan", "inf", "0x10"])
def test_anything_else_is_a_value_error_naming_the_parameter(text: str) -> None:
    with pytest.raises(ValueError, match=r"^f must be a number or a fraction such as 1/3") as info:
        exact("f", text)
    assert not isinstance(info.value, OutOfRange)
