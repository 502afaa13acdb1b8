"""The stability study on a few walls: typed runs, the summary and the files."""

from __future__ import annotations

import csv
from pathlib import Path

from comparison.stability import Setting, StudyRun, WallCase, grid_walls, run_study, summarise, write_reports


def test_grid_walls_are_buildable_and_labelled() -> None:
    walls = grid_walls()
    assert len(walls) == 120  # 104 whole-half-block walls + 16 with cut end blocks (micro builds any length)
    assert WallCase(1.0, 1 / 3, 12, 0.75, 1).label == "t1 m1/3 r12 f0.75 s1"


def test_small_study(tmp_path: Path) -> None:
    walls = [WallCase(1.0, 1.0, 6, 0.75, 1), WallCase(2.0, 0.5, 6, 0.6, 2)]
    runs = run_study(walls, (Setting("a", 0.6),), processes=1)
    assert len(runs) == 2 and all(isinstance(r, StudyRun) for r in runs)
    for r in runs:
        assert r.result is not None
        # LPs of every direction solved: at least the governing direction's
        assert r.total_iterations >= r.result.iterations >= 1
        assert r.last_load_factor <= r.lambda_assoc * (1 + 1e-7)
    s = summarise(runs)
    assert s["settings"] == ["a/0.6"] and s["per"]["a/0.6"]["n"] == 2
    paths = write_reports(runs, tmp_path, seconds=1.0, processes=1)
    rows = list(csv.DictReader(paths["csv"].open()))
    assert [row["wall"] for row in rows] == [w.label for w in walls]
    assert int(rows[0]["total_iterations"]) == runs[0].total_iterations
    assert "a/0.6" in paths["md"].read_text() and paths["png"].stat().st_size > 0
