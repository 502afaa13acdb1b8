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
