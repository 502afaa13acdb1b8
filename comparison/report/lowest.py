"""Table 7 with the iterated LP, the lowest certified state and the global search, from the committed study.

Reads the committed study table ``lowest.csv`` of the report's tables directory
(:mod:`comparison.report.committed`; written by ``xcheck stability --lowest --out
reports``; the report does not recompute it: the descent and the global
search take minutes) and renders the rows of Table 7's walls beside Orduña's
load factors (:func:`comparison.stability.lowest_render.table7_lines`).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from comparison.stability.lowest_render import table7_lines
from comparison.sweep.table import number, read_table

#: Its columns that hold numbers.
NUMERIC = (
    "orduna", "lambda_iterated", "lambda_lowest", "global_best", "global_bound", "global_gap",
    "iterated_seconds", "lowest_seconds", "global_seconds", "lambda_macro",
)


def load(path: Path) -> list[dict[str, Any]]:
    """The study's rows, numeric columns as floats (NaN when empty)."""
    rows: list[dict[str, Any]] = read_table(path)
    for r in rows:
        r.update({k: number(r.get(k, "")) for k in NUMERIC})  # a table written before a column was added
    return rows


def section(path: Path | None) -> str:
    """The report's markdown section (says so when the table is missing; ``None``:
    :func:`~comparison.report.committed.committed_table` warned)."""
    if path is None or not path.exists():
        return "## Table 7: the lowest collapse load\n\nThe study table `reports/lowest.csv` is missing.\n"
    lines = table7_lines(load(path))
    return "\n".join([
        *lines[:2],
        "The iterated LP's fixed point (`load_factor`) is one collapse state among many; the descent's lowest "
        "certified state (`lowest_load_factor`, verified exact) is the value a safety assessment should quote; "
        "the global search gives a proven lower bound of every collapse load, and where its status is `optimal` "
        "its best value is the global minimum. From `reports/lowest.csv` "
        "(`xcheck stability --lowest`; full study in `reports/lowest.md`).",
        "",
        *lines[2:],
    ]) + "\n"
