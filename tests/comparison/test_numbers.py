"""Numbers written as text: one rule (ASCII digits, a leading '-' at most), exact, and read in bounded time
(comparison/utilities/numbers.py)."""

from __future__ import annotations

import math
import time
from fractions import Fraction
from pathlib import Path

import pytest

from comparison.pytest_plugin.walls import walls_from_file
from comparison.sweep import GridError, parse_grid
from comparison.utilities.numbers import MAX_EXPONENT, OutOfRange, exact, shortest


@pytest.mark.parametrize(
    ("text", "value"),
    [("1/3", Fraction(1, 3)), ("0.75", Fraction(3, 4)), ("1e3", Fraction(1000)), ("-2.5E-1", Fraction(-1, 4)),
     ("1e+16", Fraction(10**16)), (".5", Fraction(1, 2)), ("5.", Fraction(5)), ("007", Fraction(7)),
     ("00", Fraction(0)), ("-1/3", Fraction(-1, 3)), (f"1e{MAX_EXPONENT}", Fraction(10**MAX_EXPONENT)),
     (f"1e-{MAX_EXPONENT}", Fraction(1, 10**MAX_EXPONENT))],
)
def test_a_number_under_the_rule_is_read_exactly(text: str, value: Fraction) -> None:
    assert exact("t", text) == value


@pytest.mark.parametrize(
    "text",
    ["1_0", "1_000", "5e0_1", "+3", "+0.5", " 5", "5 ", " 0.75 ", "1 / 3", "\t1", "\u0663", "1\u0660", "\uff11",
     "1/-3", "1.5/2", "--1", "1e", ".", "-"],
)
def test_underscores_signs_spaces_and_other_digits_are_refused(text: str) -> None:
    # Fraction and float read all of these ("1_0" as 10, Arabic-Indic "\u0663" as 3, " 5" as 5)
    with pytest.raises(ValueError, match=r"^lowest must be a number or a fraction such as 1/3 \(ASCII digits"):
        exact("lowest", text)


@pytest.mark.parametrize(
    "text", ["1e999999999", "-1e999999999", "1e-999999999", f"1e{MAX_EXPONENT + 1}", "0e99999", "1e" + "9" * 5000,
             "2.5E+0000000000000000000000000000000000001001", "1" * 5000],
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


@pytest.mark.parametrize("text", ["1_0", "+1", " 1", "\u0661"])
def test_grid_and_walls_files_read_numbers_written_as_text_by_the_same_rule(tmp_path: Path, text: str) -> None:
    grid = f'[axes]\nt = ["{text}"]\nm = 1\nrows = 6\nf = 0.6\n[[method]]\nkind = "macro"\n'
    with pytest.raises(GridError, match=r"\(line 2\): axes\.t: t must be a number or a fraction such as 1/3"):
        parse_grid(grid, source="g.toml")
    walls = tmp_path / "w.toml"
    walls.write_text(f'[[wall]]\nname = "a"\nt = 1\nm = "{text}"\nrows = 6\nf = 0.6\n', encoding="utf-8")
    with pytest.raises(ValueError, match=r"wall\[0\] \(a\): m must be a number or a fraction"):
        walls_from_file(walls)


@pytest.mark.parametrize(("x", "printed"), [
    (0.1 / 0.3, 1 / 3), (2.16 / (18 * 6 * 0.1), 0.2), (6.0 / 6.0, 1.0), (0.7, 0.7), (0.0, 0.0),
    (math.pi, math.pi), (1 / 3 + 1e-9, 1 / 3 + 1e-9), (1e-300, 1e-300), (math.inf, math.inf),
])
def test_a_ratio_of_decimals_prints_as_written(x: float, printed: float) -> None:
    assert shortest(x) == printed
    assert math.fabs(shortest(x) - x) <= 4 * math.ulp(x) if math.isfinite(x) else shortest(x) == x


def test_power_law_recovers_an_exact_power_and_skips_what_it_cannot_fit() -> None:
    from comparison.utilities.numbers import power_law

    sizes = [10.0, 100.0, 1000.0, 5000.0]
    law = power_law([*sizes, 0.0, math.nan], [0.003 * x**1.5 for x in sizes] + [1.0, 1.0])
    assert law is not None and law[0] == pytest.approx(1.5, rel=1e-12) and law[1] == pytest.approx(0.003, rel=1e-9)
    assert power_law([100.0, 100.0], [1.0, 2.0]) is None  # one size: no slope
    assert power_law([], []) is None
