"""The quick report regenerated from scratch is the same report, but for its run times.

Results may not depend on the clock or the machine: every file of the report
but :data:`comparison.report.timings.TIMING_FILES` must come out byte for
byte the same when it is computed again (no cache), and the result files hold
no seconds.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from comparison.report import build_report
from comparison.report.timings import TIMING_FILES

REPORTS = Path(__file__).resolve().parents[3] / "reports"


@pytest.mark.processes  # the quick report computed a second time (~45 s): the processes tier, not the fast suite
def test_the_quick_report_reproduces_but_for_timings(quick_report_dir: Path, tmp_path: Path) -> None:
    again = tmp_path / "again"
    build_report(again, quick=True, cache_dir=None, tables_dir=REPORTS)
    names = sorted(p.name for p in quick_report_dir.iterdir())
    assert names == sorted(p.name for p in again.iterdir())
    differ = [
        n for n in names if n not in TIMING_FILES and (quick_report_dir / n).read_bytes() != (again / n).read_bytes()
    ]
    assert not differ, f"files that changed between two runs: {differ}"


def test_the_result_files_hold_no_run_times(quick_report_dir: Path) -> None:
    report = json.loads((quick_report_dir / "report.json").read_text())
    assert set(report["meta"]) == {"quick", "methods"}
    for name, rows in report["tables"].items():
        for column in rows[0]:
            assert "second" not in column and not column.endswith(" s"), (name, column)
    assert "timings.md" in (quick_report_dir / "REPORT.md").read_text()
    run = json.loads((quick_report_dir / "timings.json").read_text())["run"]
    assert {"seconds", "computed", "cached", "python", "machine"} <= set(run)


def test_the_nonassociative_cost_adds_up_the_timings(quick_report_dir: Path) -> None:
    """``timings.json``'s ``nonassociative_cost``: its sums are those of the timing rows of each method (the
    library's non-associative method, the associative LP by the default back end), its ratio their quotient,
    and the per-wall median lies between the smallest and the largest ratio."""
    data = json.loads((quick_report_dir / "timings.json").read_text())
    cost = {row["over"]: row for row in data["nonassociative_cost"]}
    rows = data["timings"]
    sum_n = sum(r["total s"] for r in rows if r["method"].startswith("micro-nonassoc (scheme a"))
    sum_a = sum(r["total s"] for r in rows if r["method"].startswith("micro-assoc (normal-ipm"))
    whole = cost["the report"]
    assert whole["non-associative s"] == pytest.approx(sum_n) and whole["associative s"] == pytest.approx(sum_a)
    assert whole["ratio"] == pytest.approx(sum_n / sum_a)
    both = cost["the walls with both"]
    rounding = 1 + 1e-6  # the tables keep 7 significant digits
    assert both["non-associative s"] <= sum_n * rounding and both["associative s"] <= sum_a * rounding
    largest = next(v for k, v in cost.items() if k.startswith("per wall with both: largest"))
    median = cost["per wall with both: median"]["ratio"]
    assert 0 < median <= cost["per wall with both: 90th percentile"]["ratio"] <= largest["ratio"]
    assert "non-associative method's seconds against" in (quick_report_dir / "timings.md").read_text()
