"""The micro model in every bond the suite builds: Table 7's bond variants, and how robust the
macro-vs-micro finding is (the rows sequence of the base wall and Table 7's walls in each bond)."""

from __future__ import annotations

import math
from typing import Any

from comparison.domain.cases import cases_in_table
from comparison.report.computed import Results
from comparison.report.plan import bond_variants
from comparison.report.tables import Table, delta, lam_cell, pct, published

#: Column names of the bonds of :data:`~comparison.report.plan.BONDS`.
BOND_NAMES = ("full first, frictional heads", "half first", "frictionless heads", "half first, frictionless heads")


def bond_variants_table(res: Results) -> Table:
    """The micro model on Table 7's walls in every bond: the associative LP, the lowest certified
    non-associative state and the iterated LP's own value."""
    t = Table(
        "bond_variants",
        "Micro model variants on Table 7's walls: bond phase and head-joint friction",
        ["Set", "method", "Orduña micro", *BOND_NAMES],
        keys=2,
    )
    for c in cases_in_table("7"):
        for m in res.plan.methods:
            recs = [res.record(c.spec(), v) for v in bond_variants(m)]
            t.add(c.label, m.column, published(c, "orduna_micro"), *[lam_cell(r) for r in recs])
            if m.kind == "micro-nonassoc":
                t.add(c.label, "micro-nonassoc iterated LP", published(c, "orduna_micro"),
                      *[r.iterated_load_factor if math.isfinite(r.iterated_load_factor) else lam_cell(r)
                        for r in recs])
    return t


def robustness_table(res: Results) -> Table | None:
    """The macro model against the lowest certified micro state in every bond the suite builds, on the
    rows sequence of the base wall and on Table 7's walls: which conclusions hold under every bond."""
    specs = [(f"base wall, o = {sum(st.rows for st in s.storeys)}", s) for s in res.plan.rows_specs()]
    specs += [(c.label, c.spec()) for c in cases_in_table("7")]
    if not specs:
        return None
    hdr = ["wall", "blocks", "macro λ"]
    for name in BOND_NAMES:
        hdr += [f"micro λ, {name}", f"Δ % macro, {name}"]
    hdr += ["macro above micro in"]
    t = Table("robustness", "How robust the finding is: macro against the lowest certified micro state in every "
              "bond", hdr)
    for label, spec in specs:
        lam = res.macro[spec].load_factor
        recs = [res.record(spec, v) for v in bond_variants(res.plan.reference)]
        blocks = next((r.micro.blocks for r in recs if r.micro is not None), None)
        row: list[Any] = [label, blocks, lam]
        above = 0
        for r in recs:
            row += [lam_cell(r), pct(lam, r.load_factor)]
            d = delta(lam, r.load_factor)
            above += d is not None and d > 0
        known = sum(1 for r in recs if math.isfinite(r.load_factor))
        row.append(f"{above} of {known}")
        t.add(*row)
    t.note = robustness_note(t)
    return t


def robustness_note(t: Table) -> str:
    """Which walls of the robustness table have the macro λ above the micro one under every bond, under
    none, or under some only."""
    every: list[str] = []
    none: list[str] = []
    some: list[str] = []
    for row in t.rows:
        above, known = (int(x) for x in row[-1].split(" of "))
        (every if above == known > 0 else none if above == 0 else some).append(str(row[0]))
    parts = [f"under every bond on {', '.join(every)}" if every else "",
             f"under no bond on {', '.join(none)} (not refuted there)" if none else "",
             f"under some bonds only on {', '.join(some)} (the verdict depends on the bond)" if some else ""]
    return ("The macro λ lies above the lowest certified micro state " + "; ".join(p for p in parts if p) + ". "
            "Bonds: the bottom course starting with a full or a half block, head joints with or without friction. "
            "Base wall: the sensitivity sweeps' (o rows in all).")
