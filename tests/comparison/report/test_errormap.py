"""The error-map section: the sweep's validation page drawn from the committed table, as a section of the report."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from comparison.report import errormap
from comparison.report.committed import ERRORMAP
from comparison.sweep.page import render
from comparison.sweep.table import read_table, write_table

REPORTS = Path(__file__).resolve().parents[3] / "reports"


def _row(kind: str, lam: float, status: str, **wall: float) -> dict[str, object]:
    base = {"t": 1.0, "m": 0.5, "rows": 12, "storeys": 1, "f": 0.6, "p": 0.0, **wall}
    micro = kind != "macro"
    fields = {"kind": kind, "method": kind, "load_factor": lam, "status": status}
    return {**base, **fields, "first_course": "full" if micro else None, "blocks": 100 if micro else None}


def test_the_section_is_the_sweep_page_numbered_on_from_the_report(tmp_path: Path) -> None:
    """One code path: the section is :func:`comparison.sweep.page.render` of the table, one heading level
    down, its figures numbered from the report's next number."""
    rows = [_row("macro", 0.56, "optimal"), _row("micro-assoc", 0.52, "optimal"),
            _row("micro-nonassoc", 0.5, "converged"),
            _row("macro", 0.40, "optimal", rows=24), _row("micro-assoc", 0.50, "optimal", rows=24),
            _row("micro-nonassoc", math.nan, "cycling", rows=24)]
    table = write_table(rows, tmp_path / "map.csv")
    text, numbers = errormap.write(tmp_path / "report", table, number=7)
    page = render(read_table(table), tmp_path / "page", title=errormap.TITLE, intro="x", prefix="errormap",
                  source=errormap.SOURCE, level=2, first_figure=7)
    assert text.split("\n", 3)[3] == page.text.split("\n", 3)[3]  # all but the intro
    assert text.startswith(f"## {errormap.TITLE}\n") and "\n### Summary\n" in text
    assert "![Figure 7](errormap-map.png)" in text and "**Figure 7.** " in text
    assert numbers["figures"] == ["errormap-map.png", "errormap-scatter.png", "errormap-histogram.png"]  # no seconds
    assert all((tmp_path / "report" / name).stat().st_size > 0 for name in numbers["figures"])
    # the report keeps the macro model's summary under its old keys (the README's figures read them)
    assert numbers["summary"]["all"]["walls"] == 2 and numbers["summary"]["all"]["unsafe"] == 1
    assert numbers["summary"]["no_reference"] == 0 and numbers["statuses"]["micro-nonassoc"] == {
        "converged": 1, "cycling": 1}
    assert json.loads(json.dumps(numbers, allow_nan=False)) == numbers


def test_the_committed_error_map_table_is_complete() -> None:
    walls = errormap.load(REPORTS / ERRORMAP)
    assert len(walls) == 250 and all(math.isfinite(w.macro["macro"]) for w in walls)
    with_micro = [w for w in walls if w.reference_kind]
    assert len(with_micro) >= 150 and all(0 < w.reference < 1 for w in with_micro)
    # the Table 5 reference wall: macro 0.5825 (the paper's 0.58) above the micro reference
    ref = next(w for w in walls if (w.t, w.m, w.rows, w.storeys) == (1.0, pytest.approx(1 / 3), 60, 3))
    assert ref.macro["macro"] == pytest.approx(0.5825, abs=1e-4) and ref.error("macro") > 0.2
    # a non-associative collapse state is statically admissible for the associative LP
    # (200 walls have both; the largest excess, 3.5e-8, is the LPs' accuracy)
    both = [w for w in walls if math.isfinite(w.nonassoc) and math.isfinite(w.assoc)]
    assert len(both) == 200 and all(w.nonassoc <= w.assoc * (1 + 1e-6) for w in both)


def test_the_committed_section_keeps_the_numbers_it_had(tmp_path: Path) -> None:
    """Drawn as the sweep's page, the committed table gives the section's numbers against the micro
    reference (the lowest certified state, the value to quote, on the 176 walls of up to 1,500 blocks and the
    24 larger walls of square blocks whose verdict needs it; the associative LP, a bound, on the other 50
    above the limit): 160 of 250 walls above it, 56 by more than 10 %, 24 agreeing, median +3.3 %, worst
    +25.1 %, every wall with a micro value; by verdict and the proof of the larger margin 54 unsafe by the
    associative bound (the 50 above the block limit among them), 106 by a certified state, 90 not refuted
    (the 24 square-block walls among them), every wall with a verdict; the table per storeys and rows."""
    text, numbers = errormap.write(tmp_path, REPORTS / ERRORMAP, number=23)
    s = numbers["summary"]
    assert {k: s["all"][k] for k in ("walls", "unsafe", "above_10pct", "agree")} == {
        "walls": 250, "unsafe": 160, "above_10pct": 56, "agree": 24}
    assert round(100 * s["all"]["median"], 1) == 3.3 and round(100 * s["all"]["max"], 1) == 25.1
    assert s["no_reference"] == 0 and list(s["by_group"])[:2] == ["N=1, o=12", "N=1, o=24"]
    assert "| N=3, o=60 | 25 | 20 | 12 | 0 | +6.1 % | +25.1 % |" in text
    assert "| macro | 54 | 106 | 90 | 0 |" in text
    assert "`not_run` (above the block limit): 50" in text
