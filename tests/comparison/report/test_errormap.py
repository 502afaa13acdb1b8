"""The error-map section: pairing macro and micro per wall, the counts, the figure, the committed table."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from comparison.report import errormap
from comparison.report.committed import ERRORMAP
from comparison.sweep.table import write_table

REPORTS = Path(__file__).resolve().parents[3] / "reports"


def _row(kind: str, lam: float, status: str, **wall: float) -> dict[str, object]:
    base = {"t": 1.0, "m": 0.5, "rows": 12, "storeys": 1, "f": 0.6, "p": 0.0, **wall}
    micro = kind != "macro"
    fields = {"kind": kind, "load_factor": lam, "status": status}
    return {**base, **fields, "first_course": "full" if micro else None, "blocks": 100 if micro else None}


def test_each_wall_pairs_the_macro_value_with_the_best_micro_reference(tmp_path: Path) -> None:
    rows = [
        # wall 1: converged non-associative -> the reference (macro 12 % above)
        _row("macro", 0.56, "optimal"),
        _row("micro-assoc", 0.52, "optimal"),
        _row("micro-nonassoc", 0.5, "converged"),
        {**_row("micro-nonassoc", 0.3, "converged"), "first_course": "half"},  # another bond: not the map's
        # wall 2: the iterated LP cycled -> the associative reference (macro below: safe)
        _row("macro", 0.40, "optimal", rows=24),
        _row("micro-assoc", 0.50, "optimal", rows=24),
        _row("micro-nonassoc", math.nan, "cycling", rows=24),
        # wall 3: both slide at f -> agree
        _row("macro", 0.6, "optimal", rows=36),
        _row("micro-assoc", 0.6 * (1 - 1e-9), "optimal", rows=36),
        # wall 4: no micro result
        _row("macro", 0.5, "optimal", rows=48),
        _row("micro-assoc", math.nan, "not_run", rows=48),
    ]
    table = write_table(rows, tmp_path / "map.csv")
    cells = {c.rows: c for c in errormap.load(table)}
    assert cells[12].reference_kind == "non-assoc" and cells[12].error == pytest.approx(0.12)
    assert cells[24].reference_kind == "assoc" and cells[24].error == pytest.approx(-0.2)
    assert cells[48].reference_kind == "" and math.isnan(cells[48].error)
    s = errormap.summary(list(cells.values()))
    assert {k: s["all"][k] for k in ("walls", "unsafe", "agree", "above_10pct")} == {
        "walls": 3,
        "unsafe": 1,
        "agree": 1,
        "above_10pct": 1,
    }
    assert s["no_reference"] == 1 and s["all"]["max"] == pytest.approx(0.12)
    assert [c.rows for c in errormap.worst(list(cells.values()))] == [12, 36, 24]
    text, numbers = errormap.write(tmp_path, table)
    assert (tmp_path / "errormap.png").stat().st_size > 0 and "![Error map](errormap.png)" in text
    assert "**1 of 3 walls**" in text and numbers["summary"]["all"]["walls"] == 3


def test_the_committed_error_map_table_is_complete() -> None:
    cells = errormap.load(REPORTS / ERRORMAP)
    assert len(cells) == 250 and all(math.isfinite(c.macro) for c in cells)
    with_micro = [c for c in cells if c.reference_kind]
    assert len(with_micro) >= 150 and all(0 < c.reference < 1 for c in with_micro)
    # the Table 5 reference wall: macro 0.5825 (the paper's 0.58) above the micro reference
    ref = next(c for c in cells if (c.t, c.m, c.rows, c.storeys) == (1.0, pytest.approx(1 / 3), 60, 3))
    assert ref.macro == pytest.approx(0.5825, abs=1e-4) and ref.error > 0.2
    # a non-associative collapse state is statically admissible for the associative LP
    # (176 walls have both; the largest excess, 3.5e-8, is the LPs' accuracy)
    both = [c for c in cells if math.isfinite(c.nonassoc) and math.isfinite(c.assoc)]
    assert len(both) == 176 and all(c.nonassoc <= c.assoc * (1 + 1e-6) for c in both)


def test_an_empty_part_of_the_summary_is_valid_json(tmp_path: Path) -> None:
    """Every wall with a converged non-associative reference: the part
    against the associative LP is empty, and its median and worst are null,
    not NaN (which strict JSON readers refuse)."""
    import json

    rows = [_row("macro", 0.56, "optimal"), _row("micro-assoc", 0.52, "optimal"),
            _row("micro-nonassoc", 0.5, "converged")]
    s = errormap.summary(errormap.load(write_table(rows, tmp_path / "map.csv")))
    assert s["assoc"] == {"walls": 0, "unsafe": 0, "agree": 0, "above_10pct": 0, "median": None, "max": None}
    assert json.loads(json.dumps(s, allow_nan=False)) == s
