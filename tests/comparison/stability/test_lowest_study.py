"""The lowest-state study on a few walls: typed runs, the three values, the files and the report section."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import pytest

from comparison.report import lowest as report_lowest
from comparison.stability import WallCase
from comparison.stability.lowest import GLOBAL_MATCH, LowestCase, LowestRun, run_cases, safe_side, study_cases
from comparison.stability.lowest_render import write_lowest


def test_study_cases() -> None:
    cases = study_cases(quick=True)
    table7 = [c for c in cases if c.group == "table7"]
    assert [c.name for c in table7] == ["Set 11", "Set 12", "Set 13", "Set 14"]
    assert all(c.nodes > 0 and math.isfinite(c.published) for c in table7)
    assert all(c.group == "tiny" and c.nodes > 0 for c in cases if c not in table7)


def test_small_study(tmp_path: Path) -> None:
    cases = [
        LowestCase("tiny", WallCase(0.5, 1 / 3, 2, 0.6, 1), nodes=5_000),  # 4 blocks: the search closes
        LowestCase("table7", WallCase(1.0, 1.0, 6, 0.75, 1), published=0.5, label="Set X"),  # no search
    ]
    runs = run_cases(cases, processes=1)
    assert all(isinstance(r, LowestRun) and r.status == "converged" for r in runs)
    for r in runs:  # the descent never climbs above the iterated LP
        assert r.lowest <= r.iterated * (1 + 1e-9)
    closed, other = runs
    assert closed.closed and closed.global_gap <= 1e-6
    assert closed.global_min <= closed.lowest * (1 + GLOBAL_MATCH)
    assert closed.global_bound <= closed.global_min * (1 + 1e-9)
    assert not other.global_status and math.isnan(other.global_min)
    assert math.isnan(closed.macro) and 0 < other.macro < other.lowest  # the macro model runs on Table 7's walls
    paths = write_lowest(runs, tmp_path, seconds=1.0, processes=1)
    rows = list(csv.DictReader(paths["csv"].open()))
    assert [row["wall"] for row in rows] == ["t0.5 m1/3 r2 f0.6 s1", "Set X"]
    assert float(rows[0]["lambda_lowest"]) == closed.lowest
    text = paths["md"].read_text()
    assert "| Set X | 0.50 |" in text and "closed on 1 of the 1 walls" in text
    assert f"{other.macro:.4f}: unproven |" in text  # no search on Set X: no bound
    assert rows[1]["macro_safe"] == "unproven" and float(rows[1]["lambda_macro"]) == other.macro
    assert paths["png"].stat().st_size > 0
    section = report_lowest.section(paths["csv"])
    assert "| Set X | 0.50 |" in section and "t0.5" not in section
    assert "missing" in report_lowest.section(tmp_path / "none.csv")


@pytest.mark.parametrize(
    "macro, best, bound, verdict",
    [(0.6, 0.7, 0.65, "yes"), (0.6, 0.7, 0.6, "yes"), (0.65, 0.7, 0.0, "unproven"), (0.65, 0.65, 0.0, "unproven"),
     (0.49, 0.48, 0.0, "no"), (0.49, 0.48, math.nan, "no"), (0.6, math.nan, math.nan, "unproven"),
     (math.nan, 0.7, 0.6, "")],
)
def test_macro_safe_side(macro: float, best: float, bound: float, verdict: str) -> None:
    assert safe_side(macro, best, bound) == verdict


def test_report_section_reads_a_table_without_the_macro_columns(tmp_path: Path) -> None:
    """A table written before the macro columns existed still renders (the macro cell says so)."""
    header = ("group,wall,orduna,lambda_iterated,lambda_lowest,global_best,global_bound,global_gap,global_status,"
              "lowest_moves,iterated_seconds,lowest_seconds,global_seconds")
    path = tmp_path / "lowest.csv"
    path.write_text(header + "\ntable7,Set 12,0.68,0.7086,0.6911,0.6911,0.0,1.0,node_limit,1,0.04,0.06,3.4\n")
    assert "| Set 12 | 0.68 |" in report_lowest.section(path) and "| –: – |" in report_lowest.section(path)


@pytest.mark.processes
def test_worker_processes_give_the_runs_of_one_process() -> None:
    """The study's worker processes are the suite's LocalExecutor (Ctrl-C and orphans: test_signals.py)."""
    cases = [
        LowestCase("tiny", WallCase(0.5, 1 / 3, 2, 0.6, 1), nodes=5_000),
        LowestCase("table7", WallCase(1.0, 1.0, 6, 0.75, 1), published=0.5, label="Set X"),
    ]

    def values(runs: list[LowestRun]) -> list[tuple[object, ...]]:
        return [(r.case.name, r.status, r.iterated, r.lowest, r.global_status) for r in runs]

    assert values(run_cases(cases, processes=2)) == values(run_cases(cases, processes=1))
