"""The quick report, cell by cell, against pinned values.

``golden_quick.json`` holds, for every number the quick report shows (timings
excepted), its value and tolerance, keyed ``table / row / column``. A change
that moves a number fails here naming the cell. Regenerate the file only for a
change meant to move numbers, and say why in the commit:
``XCHECK_REGEN_GOLDEN=1 pytest tests/comparison/test_report_golden.py``.
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path
from typing import Any

import pytest

GOLDEN = Path(__file__).with_name("golden_quick.json")


def _number(v: Any) -> float | None:
    if isinstance(v, bool):
        return None
    if isinstance(v, (int, float)):
        return float(v)
    if isinstance(v, str):
        try:
            return float(v)
        except ValueError:
            return None
    return None


def _tolerance(table: str, column: str, value: float) -> float | None:
    """Tolerance of one cell; None for cells that are not pinned (timings)."""
    if "seconds" in column or column.endswith(" s"):
        return None
    if column.startswith("Δ %"):
        return 0.051  # one printed decimal
    if table == "failure_modes":
        return 1.0 if "angle" in column or "α" in column else max(1.0, 0.02 * abs(value))
    if "nonassoc" in column or "nonassoc" in table:
        return 1e-4 * max(1.0, abs(value))
    return 2e-6 * max(1.0, abs(value))


def _cells(report: dict[str, Any]) -> dict[str, float | str]:
    cells: dict[str, float | str] = {}
    for table, rows in report["tables"].items():
        for row in rows:
            for column, value in row.items():
                if column == "row":
                    continue
                key = f"{table} / {row['row']} / {column}"
                x = _number(value)
                cells[key] = value if x is None and value is not None else ("nan" if x is None or math.isnan(x) else x)
    return cells


@pytest.fixture(scope="module")
def quick_report(quick_report_dir: Path) -> dict[str, Any]:
    return json.loads((quick_report_dir / "report.json").read_text())


def test_quick_report_matches_golden_cells(quick_report: dict[str, Any]) -> None:
    cells = _cells(quick_report)
    if os.environ.get("XCHECK_REGEN_GOLDEN"):
        pinned = {}
        for key, v in cells.items():
            table, _, column = key.split(" / ", 1)[0], None, key.rsplit(" / ", 1)[1]
            if isinstance(v, float):
                tol = _tolerance(table, column, v)
                if tol is not None:
                    pinned[key] = [v, tol]
            else:
                pinned[key] = [v, None]
        lines = [f"  {json.dumps(k, ensure_ascii=False)}: {json.dumps(v)}" for k, v in sorted(pinned.items())]
        GOLDEN.write_text("{\n" + ",\n".join(lines) + "\n}\n")
        pytest.skip("golden cells regenerated")
    golden = json.loads(GOLDEN.read_text())
    problems = []
    for key, (value, tol) in golden.items():
        if key not in cells:
            problems.append(f"{key}: missing from the report")
            continue
        got = cells[key]
        if tol is None:
            if got != value:
                problems.append(f"{key}: {got!r} != pinned {value!r}")
        elif not isinstance(got, float) or not abs(got - value) <= tol:
            problems.append(f"{key}: {got!r} vs pinned {value!r} ± {tol:g}")
    assert not problems, "cells moved:\n" + "\n".join(problems[:40])


def test_quick_report_files(quick_report: dict[str, Any], tmp_path: Path) -> None:
    for table in (
        "table5",
        "table7",
        "table8",
        "table9",
        "all_cases",
        "failure_modes",
        "sensitivity",
        "speed_accuracy",
    ):
        assert quick_report["tables"][table], table
    assert quick_report["meta"]["quick"] is True
