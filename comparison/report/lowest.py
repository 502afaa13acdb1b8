"""Table 7 with the iterated LP, the lowest certified state and the global search, from the committed study.

Reads the committed study table ``lowest.csv`` of the report's tables directory
(:mod:`comparison.report.committed`; written by ``xcheck stability --lowest --out
reports``; the report does not recompute it: the descent and the global
search take minutes), renders the rows of Table 7's walls beside Orduña's
load factors (:func:`comparison.stability.lowest_render.table7_lines`) and
draws the study's figure from the same table (:func:`comparison.stability.lowest_render.chart`).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from comparison.stability.lowest_render import GROUPS, chart, table7_lines
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


def figure(rows: list[dict[str, Any]], path: Path) -> Path:
    """Draw ``lowest.png`` from the study's rows: the iterated LP's excess over the global minimum (where the
    search closed) and over the lowest certified state, per group."""
    over_global = [number(r["iterated_over_global"]) for r in rows if r["global_status"] == "optimal"]
    over_lowest = {g: [number(r["iterated_over_lowest"]) for r in rows if r["group"] == g] for g in GROUPS}
    return chart(over_global, over_lowest, path)


def section(path: Path | None, out: Path | None = None, number_: int | None = None, missing: str = "") -> str:
    """The report's markdown section (says so when the table is missing).

    Args:
        path: the study's table (``None``: :func:`~comparison.report.committed.committed_table` warned).
        out: where to draw ``lowest.png`` (``None``: no figure).
        number_: the figure's number in the report.
        missing: the sentence said in place of a missing table, naming the path looked for
            (:func:`~comparison.report.committed.missing`).
    """
    if path is None or not path.exists():
        return f"## Table 7: the lowest collapse load\n\n{missing or 'The committed study table is missing.'}\n"
    rows = load(path)
    lines = table7_lines(rows)
    fig: list[str] = []
    if out is not None:
        name = figure(rows, out / "lowest.png").name
        label = f"Figure {number_}" if number_ is not None else "Figure"
        closed = sum(1 for r in rows if r["global_status"] == "optimal")
        groups = "; ".join(f"{GROUPS[g]}: {sum(1 for r in rows if r['group'] == g)}" for g in GROUPS)
        fig = [
            "",
            f"![{label}]({name})",
            "",
            f"**{label}.** The iterated LP's load factor against the lowest known collapse load, over every wall "
            f"of the study ({groups}), in bins of 1 %. Left: its excess over the global minimum on the {closed} "
            "walls where the global search closed. Right: its excess "
            "over the lowest certified state, stacked by group: a lower bound of its excess over the global "
            "minimum. Data: `lowest.csv`.",
        ]
    return "\n".join([
        *lines[:2],
        "The iterated LP's fixed point (`iterated_load_factor`) is one collapse state among many; the descent's lowest "
        "certified state (`lowest_load_factor`, verified exact) is the value a safety assessment should quote; "
        "the global search gives a proven lower bound of every collapse load, and where its status is `optimal` "
        "its best value is the global minimum. From `reports/lowest.csv` "
        "(`xcheck stability --lowest`; full study in `reports/lowest.md`).",
        "",
        *lines[2:],
        *fig,
    ]) + "\n"
