"""The report's tables, built from its results (nothing is computed here)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from comparison.domain.cases import SET4_HINGE_LOAD_FACTORS, PaperCase, cases_in_table
from comparison.domain.wall_mechanism import LocalRecord
from comparison.report.computed import Results
from comparison.report.plan import table9_alternative
from comparison.runner import NONASSOC_RETRY_LPS, Record
from comparison.utilities.outputs import csv_text, write_text
from micro.columns import json_number
from micro.records import NonAssociativeRecord


@dataclass
class Table:
    """A report table: markdown for the reader, records for CSV/JSON."""

    name: str
    title: str
    header: list[str]
    rows: list[list[Any]] = field(default_factory=list)
    note: str = ""
    keys: int = 1  # leading columns that name a row

    def row_id(self, row: Sequence[Any]) -> str:
        """The name of a row: its leading ``keys`` cells."""
        return " / ".join(str(c) for c in row[: self.keys])

    def add(self, *cells: Any) -> None:
        """Append a row."""
        self.rows.append(list(cells))

    def markdown(self) -> str:
        """The table in markdown, with its title and note."""
        out = [
            f"### {self.title}",
            "",
            "| " + " | ".join(self.header) + " |",
            "|" + "|".join("---" for _ in self.header) + "|",
        ]
        out += ["| " + " | ".join(_fmt(c) for c in r) + " |" for r in self.rows]
        if self.note:
            out += ["", self.note]
        return "\n".join(out)

    def write_csv(self, path: Path) -> None:
        """The header and the rows as CSV (non-finite numbers empty), whole or not at all."""
        write_text(path, csv_text([self.header, *([plain(c) for c in r] for r in self.rows)]))

    def records(self) -> list[dict[str, Any]]:
        """One dictionary per row, keyed by the header (non-finite numbers as ``None``)."""
        return [{"row": self.row_id(r)} | {h: plain(c) for h, c in zip(self.header, r, strict=True)} for r in self.rows]


def _fmt(c: Any) -> str:
    if c is None:
        return "–"
    if isinstance(c, float):
        if not math.isfinite(c):
            return "n/a"
        return f"{c:.4f}" if abs(c) < 10 else f"{c:.2f}"
    return str(c)


#: Significant digits of the numbers of the report's CSV tables and ``report.json``: the digits every
#: method guarantees. The least accurate is the associative interior point (duality-gap tolerance 1e-8
#: relative): between three OpenBLAS kernels its λ moved by up to 1.2e-8 relative (Set 15: 0.5072551119
#: to 0.5072551182; Ref not at all), and a value printed with all its digits differed from one machine
#: to the next. At seven digits the three kernels print the same values on Sets 15-17; a difference of
#: 1e-8 still moves a printed value where it straddles a rounding boundary, one value in twenty to fifty on
#: the 7,575-block walls.
DIGITS = 7


def plain(c: Any) -> Any:
    """A cell for CSV/JSON: non-finite numbers as ``None``, a float to :data:`DIGITS` significant digits."""
    if isinstance(c, float):
        return json_number(float(f"{c:.{DIGITS}g}"))
    return c


def lam_cell(rec: Record) -> Any:
    """The cell showing a record's load factor: the number, the band of a
    sequence that cycled or reached its cap, or the status of a method that
    gave no number."""
    if math.isfinite(rec.load_factor):
        return rec.load_factor
    nonassoc = rec.nonassoc
    band = None if nonassoc is None else nonassoc.lambda_band
    if rec.status in ("cycling", "max_iterations") and band is not None and all(math.isfinite(v) for v in band):
        return f"{band[0]:.4f}-{band[1]:.4f} ({rec.status})"
    return {"not_applicable": "n/a", "not_run": "not run"}.get(rec.status, rec.status)


def selection_cell(na: NonAssociativeRecord) -> str:
    """``"vertex"``, or ``"<selection> after vertex (<how the vertex sequence stopped>)"``;
    where the sequences ran on a model of bodies followed by ``", reduced wall (<bodies> bodies)"`` (the
    reduced wall: the lowest lifted state's model) or ``", fused wall (<bodies> bodies)"`` (the fused wall
    with the continuation), and,
    where the wall's own sequences ran first (``fused_retry``), ``" after the wall's (<how they ended>)"``."""
    cell = na.selection
    if na.selection != "vertex" and na.vertex_stop_reason:
        cell = f"{na.selection} after vertex ({na.vertex_stop_reason})"
    if na.fused_bodies:
        cell += f", {'reduced' if na.reduced else 'fused'} wall ({na.fused_bodies:,} bodies)"
    if na.unfused_stop_reason:
        cell += f" after the wall's ({na.unfused_stop_reason})"
    return cell


def iterated_cell(rec: Record | None) -> str | None:
    """The non-associative iterated LP's own load factor (4 decimals), with the band of its mechanism's
    collapse states (``"0.7144 (0.7017-0.7176)"``); ``None`` without a converged iterated LP."""
    na = None if rec is None else rec.nonassoc
    if na is None or not math.isfinite(na.iterated_load_factor):
        return None
    states = band_cell(na.mechanism_band)
    return f"{na.iterated_load_factor:.4f}" + ("" if states is None else f" ({states})")


def band_cell(band: tuple[float, float] | None) -> str | None:
    """``"lo-hi"`` of a mechanism band (4 decimals), or ``None``."""
    return None if band is None else f"{band[0]:.4f}-{band[1]:.4f}"


def delta(ours: float | None, ref: float | None) -> float | None:
    """Percentage difference of ``ours`` against ``ref``, rounded to the one decimal the tables show."""
    if ours is None or ref is None or not math.isfinite(ours) or not math.isfinite(ref) or ref == 0:
        return None
    return round(100.0 * (ours - ref) / ref, 1)


def pct(ours: float | None, ref: float | None) -> str | None:
    """Signed percentage difference of ``ours`` against ``ref`` (one decimal)."""
    d = delta(ours, ref)
    return None if d is None else f"{d:+.1f}"


def published(case: PaperCase, model: str, quantity: str = "lambda") -> float:
    """A value the paper publishes for ``case`` (the tables ask only for values it has)."""
    value = case.value(model, quantity)
    if value is None:
        raise KeyError(f"{case.label}: no published {model} {quantity}")
    return value.value


# ---------------------------------------------------------------- the paper's tables


def table5(res: Results) -> Table:
    """Table 5: the sensitivity analysis, macro model against the paper."""
    t = Table(
        "table5",
        "Table 5: sensitivity analysis, macro model (three storeys; reference t = 1, m = 1/3, o = 60, p = 0, f = 0.6)",
        [
            "Set",
            "parameters",
            "λ paper",
            "λ ours (Eq. 10)",
            "Δ %",
            "α_c paper",
            "α_c ours",
            "α_c/α_b paper",
            "α_c/α_b ours",
            "hinge paper",
            "hinge ours",
            "λ = min(λ_r, f)",
            "mechanism",
        ],
    )
    for c in cases_in_table("5"):
        r = res.macro[c.spec()]
        lam = published(c, "proposed")
        t.add(
            c.label, f"t={c.t:g} m={c.m:.3g} o={c.rows} p={c.p:g} f={c.f:g}", lam, r.rocking_load_factor,
            pct(r.rocking_load_factor, lam), published(c, "proposed", "alpha_c_deg"), r.alpha_c_deg,
            published(c, "proposed", "alpha_ratio"), r.alpha_ratio, int(published(c, "proposed", "hinge_storey")),
            r.hinge_storey, r.load_factor, r.mechanism,
        )  # fmt: skip
    set4 = next(res.macro[c.spec()] for c in cases_in_table("5") if c.case == "4")
    t.note = (
        f"Set 4, λ with the hinge at storeys 1, 2, 3: paper {', '.join(f'{x:.3f}' for x in SET4_HINGE_LOAD_FACTORS)}; "
        f"ours {', '.join(f'{h.rocking_load_factor:.4f}' for h in set4.hinges)}.\n\n" + _table5_micro(res)
    )
    return t


def _table5_micro(res: Results) -> str:
    """The rigid-block values of Table 5's walls, the value to quote first: one sentence under the table."""
    parts = []
    for c in cases_in_table("5"):
        rec = res.nonassoc_record(c.spec())
        if rec is None:
            continue
        if math.isfinite(rec.load_factor):
            iterated = rec.iterated_load_factor
            beside = f" (iterated LP {iterated:.4f})" if math.isfinite(iterated) else ""
            parts.append(f"{c.label} {rec.load_factor:.4f}{beside}")
        else:
            parts.append(f"{c.label} {rec.status or 'no value'}")
    if not parts:
        return ""
    return (f"The micro model on these walls, {res.plan.reference.column} λ: " + "; ".join(parts)
            + " (against the macro λ: All cases below).")


def table7(res: Results) -> Table:
    """Table 7: the micro-block model against the macro-block model, with ours beside both."""
    methods, ref = res.plan.methods, res.plan.reference
    hdr = ["Set", "Orduña micro", "paper macro", "Δ % paper", "macro ours", "Δ % ours vs Orduña"]
    for m in methods:
        hdr += [f"{m.column} ours", f"Δ % vs Orduña ({m.kind})"]
    hdr += [f"Δ % macro vs {ref.column}", "micro-nonassoc iterated LP (its mechanism's states)"]
    t = Table("table7", "Table 7: micro-block against macro-block model (one storey, o = 12, f = 0.75)", hdr)
    for c in cases_in_table("7"):
        micro_pub, paper = published(c, "orduna_micro"), published(c, "proposed")
        lam = res.macro[c.spec()].load_factor
        row: list[Any] = [c.label, micro_pub, paper, pct(paper, micro_pub), lam, pct(lam, micro_pub)]
        ours = None
        for m in methods:
            rec = res.record(c.spec(), m)
            ours = rec.load_factor
            row += [lam_cell(rec), pct(ours, micro_pub)]
        row += [pct(lam, ours), iterated_cell(res.nonassoc_record(c.spec()))]
        t.add(*row)
    return t


def table8(res: Results) -> Table:
    """Table 8: other macro-block models (published) against Orduña's micro model and ours."""
    ref = res.plan.reference
    t = Table(
        "table8",
        f"Table 8: other macro-block models (published) against Orduña's micro model and our {ref.column}",
        [
            "Set",
            "Orduña micro",
            f"ours {ref.column}",
            "Orduña macro",
            "Δ %",
            "De Buhan & de Felice",
            "Δ %",
            "Speranza",
            "Δ %",
            "Δ % Speranza vs ours",
        ],
    )
    for c in cases_in_table("8"):
        micro_pub = published(c, "orduna_micro")
        rec = res.record(c.spec(), ref)
        cells: list[Any] = [c.label, micro_pub, lam_cell(rec)]
        for model in ("orduna_macro", "debuhan_defelice", "speranza"):
            v = published(c, model)
            cells += [v, pct(v, micro_pub)]
        cells.append(pct(published(c, "speranza"), rec.load_factor))
        t.add(*cells)
    return t


def table9(res: Results) -> Table:
    """Table 9: the five-storey walls, macro (and, in the full report, micro)."""
    quick, methods = res.plan.quick, res.plan.methods
    hdr = ["Set", "p", "λ paper", "λ ours (m = 1/3)", "Δ %", "λ ours, m = 1/2", "Speranza", "Δ % ours vs Speranza"]
    if not quick:
        hdr += [f"{m.column} ours" for m in methods] + ["Δ % macro vs micro (non-assoc., else assoc.)"]
    t = Table("table9", "Table 9: five-storey walls (t = 1, m = 1/3, o = 150, f = 0.75)", hdr)
    for c in cases_in_table("9"):
        lam = res.macro[c.spec()].load_factor
        paper, sp = published(c, "proposed"), published(c, "speranza")
        alt = res.macro[table9_alternative(c)].load_factor
        row: list[Any] = [c.label, f"{c.p:g}", paper, lam, pct(lam, paper), alt, sp, pct(lam, sp)]
        if not quick:
            row += [lam_cell(res.record(c.spec(), m)) for m in methods]
            row += [pct(lam, res.best_micro(c.spec()).load_factor)]
        t.add(*row)
    return t


# ---------------------------------------------------------------- beyond the paper


def all_cases(res: Results) -> Table:
    """Every case the micro model runs on: macro against micro."""
    hdr = ["Case", "storeys", "t", "m", "o", "p", "f", "macro λ", "macro mechanism"]
    hdr += [f"{m.column} λ" for m in res.plan.methods]
    hdr += ["micro-nonassoc iterated LP λ", "Δ % macro vs micro (non-assoc., else assoc.)", "blocks"]
    t = Table("all_cases", "All cases: macro against micro (micro values the paper does not have)", hdr)
    for c in res.plan.cases:
        r = res.macro[c.spec()]
        row: list[Any] = [
            c.label,
            c.storeys,
            f"{c.t:g}",
            f"{c.m:.4g}",
            c.rows,
            f"{c.p:g}",
            f"{c.f:g}",
            r.load_factor,
            r.mechanism,
        ]
        blocks = None
        for m in res.plan.methods:
            rec = res.record(c.spec(), m)
            micro = rec.micro
            row.append(lam_cell(rec))
            blocks = blocks if micro is None else micro.blocks
        ref = res.nonassoc_record(c.spec())
        row += [None if ref is None else ref.iterated_load_factor,
                pct(r.load_factor, res.best_micro(c.spec()).load_factor), blocks]
        t.add(*row)
    cut = ("A length that is not a whole number of half blocks (Set 8: L = 20, l = 3) is closed as a mason closes "
           "it: a closer at the end of a course, or a long last unit where the remainder would be narrower than a "
           "closer (docs/micro/walls.md).")
    # the n/a note only where an n/a cell is shown
    na = any(lam_cell(res.record(c.spec(), m)) == "n/a" for c in res.plan.cases for m in res.plan.methods)
    t.note = f"n/a: the micro wall cannot be built (shorter than half a block). {cut}" if na else cut
    local = [_local_note(c.label, m.column, rec.local) for c in res.plan.cases for m in res.plan.methods
             if (rec := res.record(c.spec(), m)).local is not None]
    if local:  # none of the paper's walls (docs/micro/walls.md); said wherever one is
        t.note += (" A sliver's local mechanism governs the wall as built of " + "; ".join(local)
                   + ": Δ % is taken against the wall as built.")
    return t


def _local_note(case: str, column: str, local: LocalRecord) -> str:
    """``Set 8, micro-assoc: the cut end piece ... tips over alone at λ = 0.5 (held, λ 0.52)``."""
    return (f"{case}, {column}: {local.description} at λ = {local.load_factor:.4f} (with the slivers held, λ "
            f"{local.held_load_factor:.4f})")


def mechanism_record(res: Results, case: PaperCase) -> Record:
    """The record whose mechanism is shown for ``case``.

    The reference's, else (no converged mechanism) the associative one.
    """
    rec = res.record(case.spec(), res.plan.reference)
    return rec if rec.failure is not None else res.record(case.spec(), res.plan.methods[0])


def failure_modes(res: Results) -> Table:
    """The macro crack and hinge against the micro mechanism, case by case."""
    t = Table(
        "failure_modes",
        f"Failure modes: macro crack and hinge against the {res.plan.reference.column} mechanism",
        [
            "Case",
            "micro mechanism of",
            "macro α_c",
            "macro α_c*",
            "macro hinge",
            "micro crack slope angle",
            "micro conventional angle",
            "micro hinge",
            "moving blocks %",
            "courses moving whole",
            "micro sliding contacts",
            "micro opening contacts",
        ],
    )
    for c in res.plan.cases:
        r = res.macro[c.spec()]
        rec = mechanism_record(res, c)
        fm, micro = rec.failure, rec.micro
        states = micro is not None and micro.closed_contacts + micro.opening_contacts + micro.sliding_contacts > 0
        t.add(
            c.label, rec.method.column, r.alpha_c_deg, r.alpha_c_star_deg, r.hinge_storey,
            None if fm is None else fm.crack_angle_deg, None if fm is None else fm.conventional_angle_deg,
            None if fm is None else fm.hinge_storey, None if fm is None else 100.0 * fm.moving_fraction,
            None if fm is None else fm.whole_length_courses,
            micro.sliding_contacts if micro is not None and states else None,
            micro.opening_contacts if micro is not None and states else None,
        )  # fmt: skip
    t.note = (
        "α_c: the macro crack through the hinge (Eq. 10's variable); α_c*: its stepped crack (Eq. 9). "
        "Micro: a block moves when its corner speed exceeds 1e-3 of the largest, and a contact opens or slides "
        "when its opening or slip rate exceeds 1e-3 of the largest; the crack slope is a line "
        "fitted, course by course, to the far edge of the moving blocks (to compare with α_c*); the conventional "
        "angle joins the hinge to the crack's highest point (to compare with α_c). Where the non-associative "
        "sequence did not converge, the associative mechanism is shown."
    )
    return t


def sensitivity(res: Results) -> Table:
    """λ against each parameter of the base wall, macro and micro."""
    plan = res.plan
    t = Table(
        "sensitivity",
        "Sensitivity: λ against each parameter, macro and micro",
        ["parameter", "value", "macro λ", *[f"{m.column} λ" for m in plan.methods],
         "micro-nonassoc iterated LP (its mechanism's states)"],
        keys=2,
    )
    for param, values in plan.sweeps.items():
        for v in values:
            spec = plan.sweep_spec(param, v)
            t.add(
                param, f"{v:.4g}", res.macro[spec].load_factor, *[lam_cell(res.record(spec, m)) for m in plan.methods],
                iterated_cell(res.nonassoc_record(spec)),
            )
    t.note = f"Base wall: {', '.join(f'{k} = {v:.4g}' for k, v in plan.base.items())}. Figure: `sensitivity.png`."
    return t


def histories(res: Results) -> Table:
    """Iterations and status of the iterated LP on every case."""
    t = Table(
        "histories",
        "Iterated LP: iterations and status",
        ["case", "status", "selection", "iterations", "λ of the iterated LP", "band min", "band max"],
    )
    for c in res.plan.cases:
        rec = res.record(c.spec(), res.plan.reference)
        na = rec.nonassoc
        band = (None, None) if na is None or na.lambda_band is None else na.lambda_band
        selection = None if na is None else selection_cell(na)
        t.add(c.label, rec.status, selection, None if na is None else na.iterations, rec.iterated_load_factor, *band)
    t.note = (
        "selection: how the iterates went on from an LP: `vertex` (from the simplex's vertex, Gilbert et al.'s "
        "iteration), or `proximal after vertex (...)`: the vertex sequence ended as said in brackets, and the "
        "proximal sequence (each LP's capacities moved towards the force field closest to them that carries "
        f"the last LP's load; at most {NONASSOC_RETRY_LPS} LPs) ran after it; the iterations count both, the "
        "band is the last sequence's. `reduced wall (N bodies)`: on the walls above 1,500 blocks whose "
        "associative mechanism has a dominant rigid part, the reduced wall: the sequences and their descent run "
        "on models of the mechanism's rigid parts, each mechanism they reach is lifted onto the whole wall, and "
        "the lowest state that passes the checks there is kept (the iterations count the models' LPs and the "
        "lifts). `fused wall (N bodies)`: elsewhere above 2,000 blocks, the fused wall with the continuation, "
        "whose vertex sequence reaches scheme a from associative friction (its first 31 LPs bound the shear "
        "by lines of falling slope) with the blocks that move as one rigid body fused into one body, its state "
        "checked on the whole wall. Figure: `histories.png`."
    )
    return t
