"""Table 9's walls with coarser bonds: the non-associative value where 150 rows are out of reach.

Sets 15-17 (five storeys, 150 rows, 7,575 blocks) have no non-associative
load factor: the iterated LP does not settle on them within the runner's caps
(``docs/report.md`` links the measurements). Reads the committed sweep table
``sweeps/table9_bond.csv`` of the report's tables directory
(:mod:`comparison.report.committed`; written
by ``xcheck sweep examples/sweeps/table9_bond.toml --out reports/sweeps``;
the report does not recompute it): the same walls (t = 1, m = 1/3, f = 0.75,
p = 0, 1, 8) built with fewer rows of proportionally larger units, with the
macro, associative and non-associative load factors of each. The section
tabulates them and how far the non-associative value lies below the
associative one, from the coarsest bond to the finest. Every non-associative collapse state is
statically admissible for the associative LP, so the associative value bounds
the non-associative one from above at any number of rows; the table shows how
close the two come as the bond gets finer.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

from comparison.report.tables import plain
from comparison.sweep.table import number, read_table

#: Table 9's set for each overloading ratio p of the sweep.
SETS = {0.0: "Set 15", 1.0: "Set 16", 8.0: "Set 17"}
#: Micro statuses whose load factor counts.
REFERENCE_STATUS = {"micro-nonassoc": "converged", "micro-assoc": "optimal"}


def wall_values(path: Path) -> dict[tuple[str, ...], dict[str, Any]]:
    """Per wall of a sweep table, keyed ``(t, m, rows, storeys, f, p)`` as the table writes them: the
    macro load factor (``"macro"``), the micro ones that count as references (``"micro-assoc"``,
    ``"micro-nonassoc"``; NaN otherwise), the blocks of those (``"blocks"``), and how the iterated LP
    ended (``"nonassoc_status"``, ``"nonassoc_lps"``; ``""`` and 0 without it). Micro rows: the bond
    with a full first course."""
    walls: dict[tuple[str, ...], dict[str, Any]] = {}
    for row in read_table(path):
        key = (row["t"], row["m"], row["rows"], row["storeys"], row["f"], row["p"])
        w = walls.setdefault(key, {"macro": math.nan, "micro-assoc": math.nan, "micro-nonassoc": math.nan,
                                   "blocks": 0, "nonassoc_status": "", "nonassoc_lps": 0})
        kind = row["kind"]
        if kind == "macro" and row["status"] == "optimal":
            w["macro"] = number(row["load_factor"])
        elif REFERENCE_STATUS.get(kind) == row["status"] and row["first_course"] == "full":
            w[kind] = number(row["load_factor"])
            w["blocks"] = max(w["blocks"], int(row["blocks"] or 0))
        if kind == "micro-nonassoc" and row["first_course"] == "full":
            w["nonassoc_status"], w["nonassoc_lps"] = str(row["status"]), int(row["iterations"] or 0)
    return walls


@dataclass(frozen=True)
class BondRow:
    """One wall of the sweep.

    Attributes:
        p: overloading ratio (which of Sets 15-17).
        rows: rows in all (the paper's walls have 150).
        blocks: blocks of the micro wall (0 when none was built).
        macro: the macro load factor (NaN when it failed).
        assoc: the associative load factor (NaN when not run or failed).
        nonassoc: the converged non-associative load factor (NaN otherwise).
        nonassoc_status: the iterated LP's status (``""`` when absent).
        lps: its LPs (0 when absent).
    """

    p: float
    rows: int
    blocks: int
    macro: float
    assoc: float
    nonassoc: float
    nonassoc_status: str
    lps: int

    @property
    def label(self) -> str:
        """``"Set 15"`` (or ``"p = 2"`` for a p outside Table 9)."""
        return SETS.get(self.p, f"p = {self.p:g}")

    @property
    def below_assoc(self) -> float:
        """``(nonassoc - assoc) / assoc`` (NaN without both)."""
        return (self.nonassoc - self.assoc) / self.assoc if math.isfinite(self.nonassoc + self.assoc) else math.nan

    @property
    def macro_error(self) -> float:
        """``(macro - nonassoc) / nonassoc`` (NaN without both)."""
        return (self.macro - self.nonassoc) / self.nonassoc if math.isfinite(self.macro + self.nonassoc) else math.nan


def load(path: Path) -> list[BondRow]:
    """The walls of the sweep table (:func:`wall_values`), by p then rows."""
    rows = [BondRow(float(p), int(o), w["blocks"], w["macro"], w["micro-assoc"], w["micro-nonassoc"],
                    w["nonassoc_status"], w["nonassoc_lps"])
            for (_t, _m, o, _n, _f, p), w in wall_values(path).items()]
    return sorted(rows, key=lambda r: (r.p, r.rows))


def _lam(x: float, status: str = "") -> str:
    return f"{x:.4f}" if math.isfinite(x) else (status or "–").replace("_", " ")


def _pct(x: float, digits: int = 1) -> str:
    return f"{100 * x:+.{digits}f}" if math.isfinite(x) else "–"


def findings(rows: Sequence[BondRow]) -> list[str]:
    """One bullet per set: the non-associative value against the associative one, coarsest to finest
    bond, and the rows on which the iterated LP did not settle."""
    out = []
    for p, label in SETS.items():
        done = [r for r in rows if r.p == p and math.isfinite(r.below_assoc)]
        failed = [r for r in rows if r.p == p and r.nonassoc_status and r.nonassoc_status != "converged"]
        parts = []
        if done:
            gaps = ", ".join(f"{_pct(r.below_assoc, 2)} % at {r.rows} rows" for r in done)
            best, worst = min(r.macro_error for r in done), max(r.macro_error for r in done)
            parts.append(f"the non-associative λ differs from the associative one by {gaps}; the macro λ lies "
                         f"{_pct(best)} % to {_pct(worst)} % above the non-associative one")
        for status in dict.fromkeys(r.nonassoc_status for r in failed):
            at = ", ".join(f"{r.rows}" for r in failed if r.nonassoc_status == status)
            parts.append(f"the iterated LP did not settle at {at} rows (`{status}`)")
        if parts:
            out.append(f"* **{label}** (p = {p:g}): " + "; ".join(parts) + ".")
    return out


def section(path: Path | None, missing: str = "") -> tuple[str, list[dict[str, Any]]]:
    """The report's markdown section and its rows (for ``report.json``); says so when the table is missing
    (``None``: :func:`~comparison.report.committed.committed_table` warned; ``missing``: the sentence naming
    the path looked for, :func:`~comparison.report.committed.missing`)."""
    title = "## Table 9's walls with coarser bonds"
    if path is None or not path.exists():
        return f"{title}\n\n{missing or 'The committed sweep table is missing.'}\n", []
    rows = load(path)
    lines = [
        title,
        "",
        "Sets 15-17 (o = 150, 7,575 blocks) have no non-associative value: the iterated LP does not settle on "
        "them within the runner's caps (Table 9 above; "
        "[the report's page](../docs/report.md), which links the measurements). "
        "Their associative λ is an upper "
        "bound of every non-associative collapse load (a non-associative collapse state is statically admissible "
        "for the associative LP), so the macro model's excess over it is a lower bound of its excess over the "
        "non-associative λ. The same walls (five storeys, t = 1, m = 1/3, f = 0.75) built with fewer rows of "
        "proportionally larger units show how close the two micro values come as the bond gets finer. From the "
        "committed sweep `reports/sweeps/table9_bond.csv` (`xcheck sweep examples/sweeps/table9_bond.toml --out "
        "reports/sweeps`; the report reads it and does not recompute it). These are other walls than the paper's, "
        "and each has its own macro λ.",
        "",
        *findings(rows),
        "",
        "| Set | p | rows | blocks | λ macro | micro-assoc | micro-nonassoc | Δ % non-assoc vs assoc "
        "| Δ % macro vs non-assoc | LPs |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(f"| {r.label} | {r.p:g} | {r.rows} | {r.blocks} | {_lam(r.macro)} | {_lam(r.assoc)} "
                     f"| {_lam(r.nonassoc, r.nonassoc_status)} | {_pct(r.below_assoc, 2)} | {_pct(r.macro_error)} "
                     f"| {r.lps or '–'} |")
    return "\n".join(lines) + "\n", [_record(r) for r in rows]


def _record(r: BondRow) -> dict[str, Any]:
    """``r`` for ``report.json``: strict JSON, NaN as ``null`` (:func:`~comparison.report.tables.plain`)."""
    extra = {"set": r.label, "below_assoc": r.below_assoc, "macro_error": r.macro_error}
    return {k: plain(v) for k, v in {**asdict(r), **extra}.items()}
