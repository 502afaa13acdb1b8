"""Numbers on the command line: the suite's one rule (comparison/utilities/numbers.py) on every option that takes a
number, and every count that reaches a solver held to a stated bound (HiGHS' 32-bit integers).

Each refusal is one line naming the option and exit 2, before any solve (no traceback from the library's
own check, which would say ``lowest_budget`` rather than ``--lowest``).
"""

from __future__ import annotations

import pytest

from comparison.cli import main
from comparison.cli.options import SOLVER_COUNT_MAX
from micro.backends.base import MAX_INTEGER

WALL = ["--rows", "6", "--t", "1", "--m", "1", "--f", "0.6"]
NONASSOC = ["micro", *WALL, "--friction", "nonassociative"]


def one_line_error(capsys: pytest.CaptureFixture[str], argv: list[str], *words: str) -> None:
    code = main(argv)
    out, err = capsys.readouterr()
    assert (code, out) == (2, ""), (code, out, err)
    assert err.startswith("xcheck: error: ") and err.count("\n") == 1, err
    for word in words:
        assert word in err, (word, err)


def test_the_bound_is_the_librarys() -> None:
    assert SOLVER_COUNT_MAX == MAX_INTEGER == 2_147_483_647


@pytest.mark.parametrize(("extra", "option"), [
    (["--lowest", "99999999999999999999"], "--lowest"),
    (["--lowest", "2147483648"], "--lowest"),
    (["--max-iterations", "99999999999999999999"], "--max-iterations"),
    (["--max-iterations", "2147483648"], "--max-iterations"),
    (["--global", "--node-limit", "2147483648"], "--node-limit"),
    (["--global", "--node-limit", "1e400"], "--node-limit"),
    (["--tuning", "retry_iterations=2147483648"], "--tuning retry_iterations"),
    (["--tuning", "max_simplex_iterations=1e20"], "--tuning max_simplex_iterations"),
])
def test_a_count_beyond_the_solvers_integers_is_one_line_naming_the_option(
    capsys: pytest.CaptureFixture[str], extra: list[str], option: str
) -> None:
    one_line_error(capsys, [*NONASSOC, *extra], option, "2,147,483,647")


@pytest.mark.parametrize("text", ["+3", "1_0", " 5", "5 ", "\u0663", "\uff15"])
@pytest.mark.parametrize("option", ["--lowest", "--max-iterations", "--time-limit"])
def test_a_number_outside_the_rule_is_refused_by_every_option(
    capsys: pytest.CaptureFixture[str], option: str, text: str
) -> None:
    one_line_error(capsys, [*NONASSOC, option, text], option, repr(text))


@pytest.mark.parametrize("text", ["1_0", "+1", " 1", "\u0661", "1\u00a0"])
@pytest.mark.parametrize("option", ["--t", "--m", "--f", "--p", "--rows", "--storeys"])
def test_a_wall_parameter_outside_the_rule_is_refused(
    capsys: pytest.CaptureFixture[str], option: str, text: str
) -> None:
    argv = ["macro", "--rows", "6", "--t", "1", "--m", "1", "--f", "0.6", "--storeys", "1", "--p", "0"]
    argv[argv.index(option) + 1] = text
    one_line_error(capsys, argv, option.lstrip("-"), repr(text))


def test_leading_zeros_are_read_as_the_number_they_write(capsys: pytest.CaptureFixture[str]) -> None:
    # "06" rows is 6 rows; "00" for --lowest is zero LPs, refused as zero (not as a malformed number)
    assert main(["macro", "--rows", "06", "--t", "01", "--m", "1", "--f", "0.60", "-q"]) == 0
    assert capsys.readouterr().out == main_value(capsys, ["macro", *WALL, "-q"])
    one_line_error(capsys, [*NONASSOC, "--lowest", "00"], "--lowest", "'00'")


def main_value(capsys: pytest.CaptureFixture[str], argv: list[str]) -> str:
    assert main(argv) == 0
    return capsys.readouterr().out


def test_compare_bounds_its_node_limit_alike(capsys: pytest.CaptureFixture[str]) -> None:
    one_line_error(capsys, ["compare", *WALL, "--global", "--node-limit", "2147483648"], "--node-limit",
                   "2,147,483,647")
