"""Fuzzing ``xcheck macro`` and ``xcheck micro`` arguments: an answer, or one line and exit 2; never a traceback."""

from __future__ import annotations

import contextlib
import io
import json
from typing import Any

from fuzz_strategies import FUZZ, finite_success, mark, number_text, one_line_error
from hypothesis import given
from hypothesis import strategies as st

from comparison.cli import main

pytestmark = mark

small_int_text = st.one_of(st.integers(-3, 8).map(str), st.sampled_from(["2.5", "1e3", "3/1", "x", "", "2000"]))


@st.composite
def macro_argv(draw: st.DrawFn) -> list[str]:
    argv = ["macro"]
    for option, values in (
        ("--rows", st.one_of(st.integers(-5, 10**7).map(str), number_text)),
        ("--t", number_text),
        ("--m", number_text),
        ("--f", number_text),
        ("--p", number_text),
        ("--storeys", small_int_text),
    ):
        if draw(st.integers(0, 9)) > 0:  # most options given
            argv += [option, draw(values)]
    if draw(st.booleans()):
        argv.append("--json")
    if draw(st.integers(0, 19)) == 0:
        argv += draw(st.sampled_from([["--scene", "missing.toml"], ["--bogus"], ["--json", "--json"]]))
    return argv


def _run(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    return code, out.getvalue(), err.getvalue()


def _check(code: int, out: str, err: str, argv: list[str], ok_codes: tuple[int, ...]) -> None:
    assert code in ok_codes, (argv, code, err)
    if code == 2:
        assert one_line_error(err) and out == "", (argv, err)
    elif "--json" in argv:
        d: dict[str, Any] = json.loads(out)
        assert finite_success(str(d["status"]), d["load_factor"]), (argv, d["status"], d["load_factor"])
        if code == 0:
            assert d["load_factor"] is not None and d["load_factor"] > 0, (argv, d)


@FUZZ
@given(argv=macro_argv())
def test_fuzz_macro_arguments(argv: list[str]) -> None:
    code, out, err = _run(argv)
    _check(code, out, err, argv, (0, 2))


@st.composite
def micro_argv(draw: st.DrawFn) -> list[str]:
    """Small walls (at most 12 rows, 4 blocks per course) with extreme numbers elsewhere."""
    rows = draw(st.one_of(st.integers(1, 12).map(str), st.sampled_from(["0", "-1", "2.5", "x", "1e9"])))
    argv = ["micro", "--rows", rows]
    argv += ["--t", draw(st.one_of(st.sampled_from(["0.5", "1", "2", "1/3"]), st.sampled_from(EXTREME)))]
    argv += ["--m", draw(st.one_of(st.sampled_from(["1/3", "1/2", "1", "0.25"]), st.sampled_from(EXTREME)))]
    argv += ["--f", draw(st.one_of(st.sampled_from(["0.6", "0.75", "0.4"]), number_text))]
    if draw(st.booleans()):
        argv += ["--p", draw(st.one_of(st.sampled_from(["0", "1", "4"]), number_text))]
    argv += ["--solver", draw(st.sampled_from(["highs-ipm", "clarabel", "highs-simplex", "cvxpy", "gurobi"]))]
    if draw(st.booleans()):
        argv += ["--first-course", draw(st.sampled_from(["full", "half", "middle"]))]
    if draw(st.booleans()):
        argv += ["--time-limit", draw(st.one_of(st.sampled_from(["-1", "0", "nan", "inf", "60"]), number_text))]
    return [*argv, "--json"]


#: Values of t and m that the bounds refuse or that keep the wall small (never a wall of many blocks).
EXTREME = ["0", "-1", "1e300", "1e-300", "nan", "inf", "-inf", "5e-324", "1e-7", "1e7", "x", "1/0"]


@FUZZ
@given(argv=micro_argv())
def test_fuzz_micro_arguments(argv: list[str]) -> None:
    code, out, err = _run(argv)
    _check(code, out, err, argv, (0, 1, 2))
