"""The quick report, built once for the tests that read it."""

from __future__ import annotations

from pathlib import Path

import pytest

from comparison.report import build_report

#: The committed report, whose tables (sweeps/errormap.csv, ...) the report's sections read.
REPORTS = Path(__file__).resolve().parents[3] / "reports"


@pytest.fixture(scope="session")
def quick_report_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A quick report computed from scratch (no cache)."""
    out = tmp_path_factory.mktemp("quick-report")
    build_report(out, quick=True, cache_dir=None, tables_dir=REPORTS)
    return out
