"""The quick report, cell by cell, against pinned values.

``golden_quick.json`` holds, for every number the quick report shows (run times excepted), its value and
the tolerance of its quantity (:func:`golden.tolerance`), keyed ``table / row / column``. A change that moves
a number fails here naming the cell. The file is rewritten by a script, never by this test, and only for a
change meant to move numbers (say why in the commit): ``python tests/comparison/report/golden.py``.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import golden
import pytest


@pytest.fixture(scope="module")
def report_json(quick_report_dir: Path) -> dict[str, Any]:
    return json.loads((quick_report_dir / "report.json").read_text())


def test_quick_report_matches_golden_cells(report_json: dict[str, Any]) -> None:
    problems = golden.moved(report_json, json.loads(golden.GOLDEN.read_text()))
    assert not problems, "cells moved:\n" + "\n".join(problems[:40])


def test_every_pinned_tolerance_is_its_quantitys() -> None:
    """The file's tolerances are those the named rules give (a hand-widened cell would hide a move), and
    every number of the quick report but its run times is pinned."""
    pinned = json.loads(golden.GOLDEN.read_text())
    for key, (value, tol) in pinned.items():
        table, column = key.split(" / ", 1)[0], key.rsplit(" / ", 1)[1]
        if tol is not None:
            assert tol == golden.tolerance(table, column, value), key
    assert golden.dumps(pinned) == golden.GOLDEN.read_text()  # the script's format: a rewrite shows as a diff


def test_the_golden_cells_cover_the_quick_report(report_json: dict[str, Any]) -> None:
    assert set(golden.pinned(report_json)) == set(json.loads(golden.GOLDEN.read_text()))


@pytest.mark.parametrize(
    ("table", "column", "value", "tol"),
    [
        ("table7", "Δ % vs Orduña (micro-nonassoc)", 4.2, golden.PERCENT_TOLERANCE),
        ("failure_modes", "α (deg)", 40.0, golden.ANGLE_TOLERANCE),
        ("failure_modes", "sliding", 200.0, 4.0),
        ("all_cases", "micro-nonassoc iterated LP λ", 0.7, golden.NONASSOC_RELATIVE),
        ("all_cases", "macro λ", 0.65, golden.LP_RELATIVE),
        ("all_cases", "blocks", 102.0, 102 * golden.LP_RELATIVE),
        ("timings", "seconds", 3.0, None),
    ],
)
def test_tolerance_by_quantity(table: str, column: str, value: float, tol: float | None) -> None:
    got = golden.tolerance(table, column, value)
    assert got is None if tol is None else got == pytest.approx(tol)


def test_quick_report_files(report_json: dict[str, Any]) -> None:
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
        assert report_json["tables"][table], table
    assert report_json["meta"]["quick"] is True
