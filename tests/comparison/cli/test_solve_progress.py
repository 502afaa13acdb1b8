"""The progress lines of one ``xcheck compare``: each model's line, the non-associative LPs paced by a clock."""

from __future__ import annotations

import io
import math

from comparison.cli.solve_progress import LINE_SECONDS, SolveProgress
from micro.nonassociative import LPProgress


def _lp(k: int, lam: float = math.nan) -> LPProgress:
    return LPProgress("+x", "vertex", k, lam, math.nan, "simplex-warm", 0.0)


def test_lines_are_paced_and_say_the_lps_lambda_and_the_time_so_far() -> None:
    now = [100.0]
    out = io.StringIO()
    p = SolveProgress(7230, out, clock=lambda: now[0])
    p("macro model: lambda = 0.252134 (rocking), 0.1 s")
    p(_lp(0, 0.2773))
    for k in range(1, 5):  # within LINE_SECONDS: no line
        now[0] += 1.0
        p(_lp(k, 0.26 - k * 1e-3))
    now[0] += LINE_SECONDS
    p(_lp(5))  # an LP without a lambda keeps the last one
    lines = out.getvalue().splitlines()
    assert lines[0] == "  macro model: lambda = 0.252134 (rocking), 0.1 s"
    assert len(lines) == 3
    assert lines[1] == "  non-associative: 1 LP, lambda = 0.277300 (+x, vertex), 0 s so far"
    assert lines[2] == "  non-associative: 6 LPs, lambda = 0.256000 (+x, vertex), 14 s so far"


def test_no_line_names_an_expected_time() -> None:
    """The blocks do not predict the time (a square-block wall of 7,230 blocks takes a minute, a fan of 7,575
    more than ten): no line guesses it."""
    for blocks in (78, 7230):
        out = io.StringIO()
        SolveProgress(blocks, out, clock=lambda: 0.0)(_lp(0, 0.55))
        assert "expected" not in out.getvalue() and "about" not in out.getvalue()
