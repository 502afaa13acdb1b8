"""The validation report: the paper's cases through both models, set beside the published values.

:func:`build_report` runs (through the caching :class:`~comparison.runner.Runner`)
the macro model, the associative micro LP and the non-associative iterated LP
(on walls of at most :data:`NONASSOC_MAX_BLOCKS` blocks) on the paper's cases, and writes
``REPORT.md``, one CSV per table, ``report.json`` with every number shown and
the figures. ``quick`` keeps the small walls only (Sets 11-14 and 12-row
variants) for the micro model; the macro model always runs every case.
"""

from __future__ import annotations

import csv
import json
import math
import os
import platform
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import macro
from comparison import figures
from comparison.cases import CASES, MODELS, SET4_HINGE_LOAD_FACTORS, PaperCase, cases_in_table
from comparison.runner import MACRO, MICRO_ASSOC, MICRO_NONASSOC, Method, Record, Runner
from comparison.spec import WallSpec

# ----------------------------------------------------------------- tables


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
        self.rows.append(list(cells))

    def markdown(self) -> str:
        out = [f"### {self.title}", "", "| " + " | ".join(self.header) + " |", "|" + "|".join("---" for _ in self.header) + "|"]
        out += ["| " + " | ".join(_fmt(c) for c in r) + " |" for r in self.rows]
        if self.note:
            out += ["", self.note]
        return "\n".join(out)

    def records(self) -> list[dict[str, Any]]:
        return [{"row": self.row_id(r)} | {h: _plain(c) for h, c in zip(self.header, r, strict=True)} for r in self.rows]


def _fmt(c: Any) -> str:
    if c is None:
        return "–"
    if isinstance(c, float):
        if not math.isfinite(c):
            return "n/a"
        return f"{c:.4f}" if abs(c) < 10 else f"{c:.2f}"
    return str(c)


def _plain(c: Any) -> Any:
    if isinstance(c, float) and not math.isfinite(c):
        return None
    return c


def lam_cell(rec: Record) -> Any:
    """The cell showing a record's load factor: the number, the band of a
    cycling sequence, or the status of a method that gave no number."""
    if math.isfinite(rec.load_factor):
        return rec.load_factor
    band = rec.get("band")
    if rec.status == "cycling" and band and None not in band:
        return f"{band[0]:.4f}-{band[1]:.4f} (cycling)"
    return {"not_applicable": "n/a", "not_run": "not run"}.get(rec.status, rec.status)


def mechanism_band(study: Study, c: PaperCase) -> tuple[float, float] | None:
    """The mechanism band of the non-associative record of ``c``, if it has a finite one."""
    band = study.run(c.spec(), MICRO_NONASSOC).get("mechanism_band")
    if not band or any(v is None or not math.isfinite(v) for v in band):
        return None
    return band[0], band[1]


def band_cell(band: tuple[float, float] | None) -> str | None:
    """``"lo-hi"`` of a mechanism band (4 decimals), or ``None``."""
    return None if band is None else f"{band[0]:.4f}-{band[1]:.4f}"


def pct(ours: float | None, ref: float | None) -> str | None:
    """Signed percentage difference of ``ours`` against ``ref`` (one decimal)."""
    if ours is None or ref is None or not math.isfinite(ours) or not math.isfinite(ref) or ref == 0:
        return None
    return f"{100.0 * (ours - ref) / ref:+.1f}"


# ------------------------------------------------------------------ study

#: The report runs the iterated non-associative LP on walls of at most this many
#: blocks: the Table 5 walls of up to 1,830 blocks take 1-120 s each (the
#: runner caps a sequence at :data:`comparison.runner.NONASSOC_SECONDS`); Set 10
#: (3,630 blocks) ran over 12 minutes without settling and the 7,575-block
#: Table 9 walls over 20 minutes (see the README), which would not fit the
#: report's 15 minutes.
NONASSOC_MAX_BLOCKS = 2000


def approximate_blocks(spec: WallSpec) -> int:
    """Blocks of the running-bond wall of ``spec`` (to within one per course)."""
    return int(round(spec.rows * (spec.length / spec.block_length + 0.5)))



def micro_methods() -> list[Method]:
    """The micro methods of the report: the associative LP by Clarabel (the
    fastest accurate back end; HiGHS IPM stopped with an unknown status on the
    7,575-block Set 17) and the iterated non-associative LP."""
    return [replace(MICRO_ASSOC, solver="clarabel"), MICRO_NONASSOC]


@dataclass
class Study:
    """Everything the report computes, through one runner."""

    runner: Runner
    quick: bool
    methods: list[Method]
    macro_results: dict[str, macro.MacroResult] = field(default_factory=dict)

    @property
    def reference(self) -> Method:
        """The best micro reference: non-associative when available."""
        return self.methods[-1]

    def micro_cases(self) -> list[PaperCase]:
        return [c for c in CASES if not self.quick or c.rows <= 12]

    def run(self, spec: WallSpec, method: Method) -> Record:
        """The record of ``method`` on ``spec`` (``not_run``: the iterated LP on a wall too large for the report)."""
        blocks = approximate_blocks(spec)
        if method.kind == "micro-nonassoc" and blocks > NONASSOC_MAX_BLOCKS:
            return Record(spec.name or "wall", method.label, float("nan"), "not_run", 0.0, {"message": f"about {blocks} blocks: above {NONASSOC_MAX_BLOCKS}"})
        return self.runner.run(spec, method)

    def best_micro(self, spec: WallSpec) -> Record:
        """The non-associative record when it has a load factor, else the associative one."""
        rec = self.run(spec, self.reference)
        return rec if math.isfinite(rec.load_factor) else self.run(spec, self.methods[0])


# ------------------------------------------------------------ report parts


def table5(study: Study) -> Table:
    t = Table(
        "table5",
        "Table 5: sensitivity analysis, macro model (three storeys; reference t = 1, m = 1/3, o = 60, p = 0, f = 0.6)",
        ["Set", "parameters", "λ paper", "λ ours (Eq. 10)", "Δ %", "α_c paper", "α_c ours", "α_c/α_b paper", "α_c/α_b ours", "hinge paper", "hinge ours", "λ = min(λ_r, f)", "mechanism"],
    )
    for c in cases_in_table("5"):
        r = study.macro_results[c.case]
        pub = {q: c.value("proposed", q) for q in ("lambda", "alpha_c_deg", "alpha_ratio", "hinge_storey")}
        t.add(
            c.label, f"t={c.t:g} m={c.m:.3g} o={c.rows} p={c.p:g} f={c.f:g}", pub["lambda"].value, r.rocking_load_factor,  # type: ignore[union-attr]
            pct(r.rocking_load_factor, pub["lambda"].value), pub["alpha_c_deg"].value, r.alpha_c_deg,  # type: ignore[union-attr]
            pub["alpha_ratio"].value, r.alpha_ratio, int(pub["hinge_storey"].value), r.hinge_storey, r.load_factor, r.mechanism,  # type: ignore[union-attr]
        )  # fmt: skip
    set4 = study.macro_results["4"]
    t.note = (
        f"Set 4, λ with the hinge at storeys 1, 2, 3: paper {', '.join(f'{x:.3f}' for x in SET4_HINGE_LOAD_FACTORS)}; "
        f"ours {', '.join(f'{h.rocking_load_factor:.4f}' for h in set4.hinges)}."
    )
    return t


def table7(study: Study) -> Table:
    ref = study.reference
    hdr = ["Set", "Orduña micro", "paper macro", "Δ % paper", "macro ours", "Δ % ours vs Orduña"]
    for m in study.methods:
        hdr += [f"{m.kind} ours", f"Δ % vs Orduña ({m.kind})"]
    hdr += [f"Δ % macro vs {ref.kind}", "collapse states of the non-assoc. mechanism"]
    t = Table("table7", "Table 7: micro-block against macro-block model (one storey, o = 12, f = 0.75)", hdr)
    for c in cases_in_table("7"):
        micro_pub = c.value("orduna_micro").value  # type: ignore[union-attr]
        paper = c.value("proposed").value  # type: ignore[union-attr]
        lam = study.macro_results[c.case].load_factor
        row: list[Any] = [c.label, micro_pub, paper, pct(paper, micro_pub), lam, pct(lam, micro_pub)]
        ours = None
        for m in study.methods:
            rec = study.run(c.spec(), m)
            ours = rec.load_factor
            row += [lam_cell(rec), pct(ours, micro_pub)]
        row.append(pct(lam, ours))
        row.append(band_cell(mechanism_band(study, c)))
        t.add(*row)
    return t


def bond_variants(study: Study) -> Table:
    t = Table(
        "bond_variants",
        "Micro model variants on Table 7's walls: bond phase and head-joint friction",
        ["Set", "method", "Orduña micro", "full first, frictional heads", "half first", "frictionless heads"],
        keys=2,
    )
    for c in cases_in_table("7"):
        pub = c.value("orduna_micro").value  # type: ignore[union-attr]
        for m in study.methods:
            cells = [lam_cell(study.run(c.spec(), v)) for v in (m, replace(m, first_course="half"), replace(m, head_joints="frictionless"))]
            t.add(c.label, m.kind, pub, *cells)
    return t


def table8(study: Study) -> Table:
    ref = study.reference
    t = Table(
        "table8",
        f"Table 8: other macro-block models (published) against Orduña's micro model and our {ref.kind}",
        ["Set", "Orduña micro", f"ours {ref.kind}", "Orduña macro", "Δ %", "De Buhan & de Felice", "Δ %", "Speranza", "Δ %", "Δ % Speranza vs ours"],
    )
    for c in cases_in_table("8"):
        micro_pub = c.value("orduna_micro").value  # type: ignore[union-attr]
        rec = study.run(c.spec(), ref)
        ours = rec.load_factor
        cells: list[Any] = [c.label, micro_pub, lam_cell(rec)]
        for model in ("orduna_macro", "debuhan_defelice", "speranza"):
            v = c.value(model).value  # type: ignore[union-attr]
            cells += [v, pct(v, micro_pub)]
        cells.append(pct(c.value("speranza").value, ours))  # type: ignore[union-attr]
        t.add(*cells)
    return t


def table9(study: Study) -> Table:
    hdr = ["Set", "p", "λ paper", "λ ours (m = 1/3)", "Δ %", "λ ours, m = 1/2", "Speranza", "Δ % ours vs Speranza"]
    if not study.quick:
        hdr += [f"{m.kind} ours" for m in study.methods] + ["Δ % macro vs micro (non-assoc., else assoc.)"]
    t = Table("table9", "Table 9: five-storey walls (t = 1, m = 1/3, o = 150, f = 0.75)", hdr)
    for c in cases_in_table("9"):
        r = study.macro_results[c.case]
        paper = c.value("proposed").value  # type: ignore[union-attr]
        sp = c.value("speranza").value  # type: ignore[union-attr]
        alt = macro.solve(WallSpec.from_paper(t=c.t, m=0.5, rows=c.rows, f=c.f, p=c.p, storeys=c.storeys).to_macro())
        row: list[Any] = [c.label, f"{c.p:g}", paper, r.load_factor, pct(r.load_factor, paper), alt.load_factor, sp, pct(r.load_factor, sp)]
        if not study.quick:
            recs = [study.run(c.spec(), m) for m in study.methods]
            row += [lam_cell(x) for x in recs] + [pct(r.load_factor, study.best_micro(c.spec()).load_factor)]
        t.add(*row)
    return t


def all_cases(study: Study) -> Table:
    hdr = ["Case", "storeys", "t", "m", "o", "p", "f", "macro λ", "macro mechanism"]
    for m in study.methods:
        hdr += [f"{m.kind} λ", f"{m.kind} s"]
    hdr += ["Δ % macro vs micro (non-assoc., else assoc.)", "blocks"]
    t = Table("all_cases", "All cases: macro against micro (micro values the paper does not have)", hdr)
    for c in study.micro_cases():
        r = study.macro_results[c.case]
        row: list[Any] = [c.label, c.storeys, f"{c.t:g}", f"{c.m:.4g}", c.rows, f"{c.p:g}", f"{c.f:g}", r.load_factor, r.mechanism]
        blocks = None
        for m in study.methods:
            rec = study.run(c.spec(), m)
            ran = rec.status not in ("not_applicable", "not_run")
            row += [lam_cell(rec), rec.get("build_seconds", 0.0) + rec.get("solve_seconds", rec.seconds) if ran else None]
            blocks = rec.get("blocks", blocks)
        row += [pct(r.load_factor, study.best_micro(c.spec()).load_factor), blocks]
        t.add(*row)
    t.note = "n/a: the micro wall cannot be built (wall length not a whole number of half blocks, e.g. Set 8: L = 20, v = 1.5)."
    return t


def failure_modes(study: Study) -> Table:
    ref = study.reference
    t = Table(
        "failure_modes",
        f"Failure modes: macro crack and hinge against the {ref.kind} mechanism",
        ["Case", "micro mechanism of", "macro α_c", "macro α_c*", "macro hinge", "micro crack slope angle", "micro conventional angle", "micro hinge", "moving blocks %", "courses moving whole", "micro sliding contacts", "micro opening contacts"],
    )
    for c in study.micro_cases():
        r = study.macro_results[c.case]
        rec = study.run(c.spec(), ref)
        if rec.get("failure_hinge_storey") is None and ref is not study.methods[0]:
            rec = study.run(c.spec(), study.methods[0])  # no converged mechanism: the associative one
        star = math.degrees(math.atan(r.tan_alpha_c - r.wall.overlap / (sum(r.wall.rows[: r.hinge_storey]) * r.wall.block_height)))
        states = rec.get("contact_states") or {}
        frac = rec.get("failure_moving_fraction")
        t.add(
            c.label, rec.method.split(" (")[0], r.alpha_c_deg, star, r.hinge_storey, rec.get("failure_crack_angle_deg"),
            rec.get("failure_conventional_angle_deg"), rec.get("failure_hinge_storey"), None if frac is None else 100.0 * frac,
            rec.get("failure_whole_length_courses"), states.get("sliding"), states.get("opening"),
        )  # fmt: skip
    t.note = (
        "α_c: the macro crack through the hinge (Eq. 10's variable); α_c*: its stepped crack (Eq. 9). "
        "Micro: a block moves when its corner speed exceeds 1e-3 of the largest; the crack slope is a line "
        "fitted, course by course, to the far edge of the moving blocks (to compare with α_c*); the conventional "
        "angle joins the hinge to the crack's highest point (to compare with α_c). Where the non-associative "
        "sequence did not converge, the associative mechanism is shown."
    )
    return t


# --------------------------------------------------------------- figures


def _base(quick: bool) -> dict[str, Any]:
    if quick:
        return dict(t=1.0, m=1 / 3, rows=12, f=0.75, p=0.0, storeys=1)
    return dict(t=1.0, m=1 / 3, rows=60, f=0.6, p=0.0, storeys=3)


SWEEPS_FULL = {
    "f": [0.4, 0.5, 0.6, 0.7, 0.8],
    "t": [0.5, 1.0, 1.25, 2.0, 2.5],
    "m": [0.25, 1 / 3, 0.5, 1.0],
    "rows": [12, 24, 36, 45, 60],
    "p": [0.0, 1.0, 2.0, 4.0, 8.0],
}
SWEEPS_QUICK = {
    "f": [0.5, 0.6, 0.75, 0.9],
    "t": [0.5, 1.0, 2.0],
    "m": [0.25, 1 / 3, 0.5, 1.0],
    "rows": [6, 9, 12, 18, 24],
    "p": [0.0, 1.0, 4.0],
}


def sensitivity(study: Study, out: Path) -> Table:
    base = _base(study.quick)
    sweeps = SWEEPS_QUICK if study.quick else SWEEPS_FULL
    t = Table(
        "sensitivity",
        "Sensitivity: λ against each parameter, macro and micro",
        ["parameter", "value", "macro λ", *[f"{m.kind} λ" for m in study.methods]],
        keys=2,
    )
    panels: dict[str, dict[str, tuple[list[float], list[float]]]] = {}
    for param, values in sweeps.items():
        series: dict[str, tuple[list[float], list[float]]] = {"macro": ([], [])}
        for m in study.methods:
            series[m.kind] = ([], [])
        for v in values:
            spec = WallSpec.from_paper(**{**base, param: v}, name=f"{param}={v:.4g}")  # type: ignore[arg-type]
            lam_macro = macro.solve(spec.to_macro()).load_factor
            series["macro"][0].append(v)
            series["macro"][1].append(lam_macro)
            cells = []
            for m in study.methods:
                rec = study.run(spec, m)
                series[m.kind][0].append(v)
                series[m.kind][1].append(rec.load_factor)
                cells.append(lam_cell(rec))
            t.add(param, f"{v:.4g}", lam_macro, *cells)
        panels[param] = series
    published = None
    if not study.quick:
        ref = {c.case: c for c in cases_in_table("5")}
        pick = {"f": ("1", "Ref", "2"), "p": ("Ref", "3", "4"), "rows": ("5", "6", "Ref"), "t": ("Ref", "7", "8"), "m": ("Ref", "9", "10")}
        published = {
            k: ([getattr(ref[n], "rows" if k == "rows" else k) for n in names], [ref[n].value("proposed").value for n in names])  # type: ignore[union-attr]
            for k, names in pick.items()
        }
    figures.sensitivity(panels, out / "sensitivity.png", published)
    t.note = f"Base wall: {', '.join(f'{k} = {v:.4g}' for k, v in base.items())}. Figure: `sensitivity.png`."
    return t


def speed_accuracy(study: Study, out: Path) -> Table:
    """Each method, back end and block resolution against the finest micro reference."""
    base = _base(study.quick)
    resolutions = [3, 6, 9, 12] if study.quick else [12, 24, 36, 60]
    solvers = ["highs", "clarabel", "cvxpy"] + (["highs-simplex"] if study.quick else [])
    finest = WallSpec.from_paper(**{**base, "rows": resolutions[-1]}, name="finest")  # type: ignore[arg-type]
    ref_rec = study.best_micro(finest)
    lam_ref = ref_rec.load_factor
    ref_name = ref_rec.method.split(" (")[0]
    t = Table(
        "speed_accuracy",
        f"Speed against accuracy (reference: {ref_name}, {resolutions[-1]} rows, λ = {lam_ref:.4f})",
        ["method", "rows", "blocks", "seconds", "λ", "rel. error of λ"],
        keys=2,
    )
    points: list[figures.SpeedPoint] = []

    def add(label: str, family: str, rows: int, blocks: Any, seconds: float, lam: float) -> None:
        err = abs(lam - lam_ref) / lam_ref if math.isfinite(lam) else float("nan")
        t.add(label, rows, blocks, seconds, lam, err)
        points.append(figures.SpeedPoint(f"{rows} rows" if family.startswith("micro") else label, family, seconds, err))

    spec = WallSpec.from_paper(**base, name="macro")  # type: ignore[arg-type]
    t0 = time.perf_counter()
    n = 20
    for _ in range(n):
        r = macro.solve(spec.to_macro())
    add("macro", "macro", base["rows"], None, (time.perf_counter() - t0) / n, r.load_factor)
    for rows in resolutions:
        spec = WallSpec.from_paper(**{**base, "rows": rows}, name=f"{rows} rows")  # type: ignore[arg-type]
        for solver in solvers:
            rec = study.run(spec, replace(MICRO_ASSOC, solver=solver))
            add(f"micro-assoc {solver}", f"micro-assoc {solver}", rows, rec.get("blocks"), rec.seconds, rec.load_factor)
        for m in study.methods[1:]:
            rec = study.run(spec, m)
            if rec.status == "not_run":
                continue
            add(m.label, m.kind, rows, rec.get("blocks"), rec.seconds, rec.load_factor)
    figures.speed_accuracy(points, f"{ref_name}, {resolutions[-1]} rows", out / "speed_accuracy.png")
    t.note = "Seconds: build and solve as run (first computation, not a cache read); figure: `speed_accuracy.png`."
    return t


def mechanisms(study: Study, out: Path) -> list[str]:
    """One figure per case: the micro mechanism with the macro crack drawn over it."""
    from micro.plot import draw_mechanism

    plt = figures._plt()
    names = []
    for c in study.micro_cases():
        spec = c.spec()
        rec = study.run(spec, study.reference)
        method = study.reference if rec.get("failure_hinge_storey") is not None else study.methods[0]
        mech = study.runner.mechanism(spec, method)
        if mech is None:
            continue
        wall = spec.to_micro()
        r = study.macro_results[c.case]
        fig, ax = plt.subplots(figsize=(7, 7 * min(1.4, max(0.4, wall.height / wall.length))), dpi=100)
        draw_mechanism(ax, wall, mech["velocities"], fig=fig)
        direction = str(mech["direction"])
        _draw_macro_crack(ax, r, direction)
        ax.set_title(f"{c.label}: {method.kind} λ = {study.run(spec, method).load_factor:.3f}, macro λ = {r.load_factor:.3f} (α_c = {r.alpha_c_deg:.1f}°)", fontsize=9)
        ax.legend(fontsize=7, loc="upper right")
        name = f"mechanism_{c.case.lower()}.png"
        fig.savefig(out / name, bbox_inches="tight")
        plt.close(fig)
        names.append(name)
    return names


def _draw_macro_crack(ax: Any, r: macro.MacroResult, direction: str) -> None:
    w = r.wall
    k = r.hinge_storey
    base = sum(w.rows[k:]) * w.block_height
    height = sum(w.rows[:k]) * w.block_height
    L, v = w.length, w.overlap
    tau_star = r.tan_alpha_c - v / height
    ys = [0.0, height]
    lines = {
        "macro crack through the hinge (α_c)": [0.0, r.tan_alpha_c * height],
        "macro stepped crack (α_c*)": [v, v + tau_star * height],
    }
    for (label, xs), style in zip(lines.items(), ("--", "-"), strict=True):
        xs_c = [min(x, L) for x in xs]
        ys_c = [ys[0], ys[0] + (ys[1] - ys[0]) * (xs_c[1] - xs[0]) / (xs[1] - xs[0]) if xs[1] != xs[0] else ys[1]]
        if direction == "+x":
            xs_c = [L - x for x in xs_c]
        ax.plot(xs_c, [base + y for y in ys_c], style, color="red", lw=1.5, label=label)


def histories(study: Study, out: Path) -> Table | None:
    """Convergence histories of the iterated LP (when the non-associative method exists)."""
    if len(study.methods) < 2:
        return None
    m = study.methods[-1]
    series: dict[str, list[float]] = {}
    t = Table("histories", "Iterated LP: iterations and status", ["case", "status", "iterations", "λ", "band min", "band max"])
    for c in study.micro_cases():
        rec = study.run(c.spec(), m)
        hist = rec.get("history_load_factor")
        if hist:
            series[c.label] = hist
        band = rec.get("band") or [None, None]
        t.add(c.label, rec.status, rec.get("iterations"), rec.load_factor, band[0], band[1])
    if series:
        figures.histories(series, out / "histories.png", "λ per iteration of the iterated LP")
    t.note = "Figure: `histories.png`."
    return t


# ------------------------------------------------------------------ text

DISCREPANCIES = """\
* **Set 1 (f = 0.4).** Eq. (10)'s minimum is 0.519, as published, but it exceeds
  f = 0.4: the whole wall slides on a bed joint first (the paper itself calls f an
  upper bound of the load factor). `load_factor` reports min(λ_r, f) = 0.400 and the
  mechanism `sliding`; `rocking_load_factor` keeps the paper's 0.519.
* **Sets 3-4 (p = 2, 8).** Ours is 0.4 % and 0.2 % below the paper; reading H in
  p = q/(γHb) as the storey height instead of the wall height moves the values by
  less than 0.25 %, so the reading of p does not explain the gap; a different
  treatment of the floor terms in the paper's spreadsheet may. For Set 4 the paper
  finds the hinge at the top storey (λ = 0.576, 0.578, 0.582 from the top); ours gives
  0.5752, 0.5751, 0.5751: all three hinges lie within 2e-4 of each other, and the
  global minimum is at the base.
* **Set 5 (o = 36).** The paper prints 0.513 (-11.9 %), yet concludes that the
  number of rows is "substantially irrelevant"; the faithful model gives 0.588
  (+0.9 % on the reference wall), in line with o = 45 (0.585 both). No single
  parameter change we tried reproduces both 0.513 and 37.42°: most likely a
  transcription error in the table.
* **Sets 7-8 (t = 2, 3).** Ours is 0.7 % and 1.0 % above. Here the crack leaves
  through the side of the wall: Eq. (2) finds the exit with the conventional line
  tan α_c while Table 2 draws parts C and D with tan α_c* (Eq. 9), so the triangle D
  overhangs the wall end by v(1 - e/n). Any treatment of that overhang moves these
  two sets and no other.
* **Sets 15-17 (Table 9).** The faithful model gives 0.61 for the five-storey wall
  of Table 6 (m = 1/3), not 0.47. With m = 1/2 it gives 0.467, 0.465, 0.465, i.e. the
  published 0.47 for all three sets: Table 9 was most likely computed with m = 1/2.
  We keep m = 1/3 as Table 6 states.
"""


def _findings(study: Study, tables: dict[str, Table]) -> str:
    """Headline findings, from the numbers of the tables."""
    lines = []

    def number(x: Any) -> bool:
        return isinstance(x, float) and math.isfinite(x)

    sens = tables.get("sensitivity")
    rows = [r for r in sens.rows if r[0] == "rows"] if sens is not None else []
    if len(rows) >= 2:
        lo, hi = rows[0], rows[-1]
        both = [i for i in range(3, len(lo)) if number(lo[i]) and number(hi[i])]  # micro columns with two numbers
        if both:
            i = both[-1]
            name = sens.header[i].removesuffix(" λ")  # type: ignore[union-attr]
            lines.append(
                f"* **Number of rows.** From o = {lo[1]} to o = {hi[1]} rows (the same wall of smaller blocks) the "
                f"macro λ goes from {lo[2]:.3f} to {hi[2]:.3f}, the {name} λ from {lo[i]:.3f} to {hi[i]:.3f}: the "
                "rigid-block wall loses strength as its blocks get smaller, the macro model hardly does. The paper "
                "validated it on 12-row walls only (Table 7)."
            )
    allc = tables.get("all_cases")
    if allc is not None:
        deltas = [(r[0], float(r[-2])) for r in allc.rows if isinstance(r[-2], str)]
        big = [(c, d) for c, d in deltas if c not in ("Set 11", "Set 12", "Set 13", "Set 14")]
        if big:
            above = [d for _, d in big if d > 0]
            nac = allc.header.index("micro-nonassoc λ") if "micro-nonassoc λ" in allc.header else None
            n_na = sum(1 for r in allc.rows if r[0] in dict(big) and nac is not None and number(r[nac]))
            ref_note = ("" if n_na == len(big) else
                        f" (against the non-associative λ on {n_na} of them, elsewhere against the associative LP, "
                        "itself an upper bound of the non-associative λ)")
            lines.append(
                f"* **Macro against micro beyond Table 7.** On the {len(big)} other walls the micro model can build "
                f"(30-150 rows), the macro λ lies above the micro one on {len(above)}, by "
                f"{min(above):+.1f} % to {max(above):+.1f} %" + ref_note + "; below it only "
                + ", ".join(f"{c} ({d:+.1f} %)" for c, d in big if d <= 0) + "."
                if above else f"* **Macro against micro beyond Table 7.** The macro λ lies below the micro one on all {len(big)} walls."
            )
    t7 = tables.get("table7")
    if t7 is not None:
        devs, below = [], []
        for c in cases_in_table("7"):
            pub = c.value("orduna_micro").value  # type: ignore[union-attr]
            lam = study.run(c.spec(), MICRO_NONASSOC).load_factor
            if math.isfinite(lam):
                devs.append(100.0 * (lam - pub) / pub)
            band = mechanism_band(study, c)
            if band is not None and band[0] <= pub * 1.02:
                below.append(c.label)
        na = (f"the iterated non-associative LP lies {min(devs):+.1f} % to {max(devs):+.1f} % from them on the "
              f"{len(devs)} sets where it converged" if devs else "the iterated non-associative LP did not converge")
        lines.append(
            "* **Table 7.** The associative LP lies above Orduña's non-associative values, as friction with "
            f"dilatancy must; {na} (default bond, frictional head joints; `bond_variants` below for the others). "
            "The non-associative solution is not unique: the final mechanism can form at any load factor of its band "
            "(last column), whose lower end comes within 2 % of Orduña's value on "
            f"{len(below)} of {len(t7.rows)} sets ({', '.join(below) or 'none'})."
        )
    return "\n".join(lines)


# ------------------------------------------------------------------ entry


def build_report(
    out_dir: Path,
    *,
    quick: bool = False,
    cache_dir: Path | None = Path(".xcheck-cache"),
    progress: Callable[[str], None] | None = None,
    workers: int | None = None,
) -> Path:
    """Compute everything and write ``REPORT.md``, CSVs, ``report.json`` and the figures.

    With a cache, a first pass only plans the micro computations the report
    needs; those missing from the cache are computed in ``workers`` processes
    (default: the number of CPUs), and the report is then written from the cache.

    Args:
        out_dir: where to write.
        quick: small walls only for the micro model.
        cache_dir: the result cache (``None``: no cache, one process).
        progress: called with one line per computation.
        workers: processes for the micro computations.

    Returns:
        The path of ``REPORT.md``.
    """
    start = time.perf_counter()
    out_dir.mkdir(parents=True, exist_ok=True)
    computed = 0
    if cache_dir is not None:
        import tempfile

        planner = Runner(cache_dir, plan_only=True)
        with tempfile.TemporaryDirectory() as scratch:
            _write(Study(planner, quick, micro_methods()), Path(scratch), start)
        runner = Runner(cache_dir, progress)
        runner.prefetch(list(planner.planned.values()), workers or os.cpu_count() or 1)
        computed = runner.computed
    study = Study(Runner(cache_dir, progress), quick, micro_methods())
    path = _write(study, out_dir, start, computed)
    return path


def _write(study: Study, out_dir: Path, start: float, computed_before: int = 0) -> Path:
    quick = study.quick
    study.macro_results = {c.case: macro.solve(c.spec().to_macro()) for c in CASES}
    tables: dict[str, Table] = {}
    for build in (table5, table7, bond_variants, table8, table9, all_cases, failure_modes):
        tb = build(study)
        tables[tb.name] = tb
    tables["sensitivity"] = sensitivity(study, out_dir)
    tables["speed_accuracy"] = speed_accuracy(study, out_dir)
    hist = histories(study, out_dir)
    if hist is not None:
        tables["histories"] = hist
    mech_figs = mechanisms(study, out_dir)

    for tb in tables.values():
        with (out_dir / f"{tb.name}.csv").open("w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(tb.header)
            w.writerows([[_plain(c) for c in r] for r in tb.rows])
    elapsed = time.perf_counter() - start
    meta = {
        "quick": quick,
        "methods": [m.label for m in [MACRO, *study.methods]],
        "python": platform.python_version(),
        "machine": platform.machine(),
        "cpus": os.cpu_count(),
        "seconds": elapsed,
        "computed": study.runner.computed + computed_before,
        "cached": study.runner.hits,
    }
    (out_dir / "report.json").write_text(
        json.dumps({"meta": meta, "tables": {k: v.records() for k, v in tables.items()}}, indent=1, default=str)
    )
    figs = "\n".join(f"![{n}]({n})" for n in ["sensitivity.png", "speed_accuracy.png"] + (["histories.png"] if hist else []))
    mech = " ".join(f"[{n}]({n})" for n in mech_figs)
    order = ["table7", "bond_variants", "table8", "table9", "table5", "all_cases", "failure_modes", "sensitivity", "speed_accuracy", "histories"]
    body = "\n\n".join(tables[k].markdown() for k in order if k in tables)
    text = f"""# Macro-block against rigid-block limit analysis: validation report

Argiento, Maione & Casapulla (2018), *Formulating the in-plane frictional resistances and
collapse mechanisms for multi-storey masonry block walls*, Frattura ed Integrità Strutturale
46, 226-239, recomputed. Methods: {", ".join(meta["methods"])}.
{"**Quick run: the micro model on the small walls only.**" if quick else ""}
Δ % is the first value against the second named. Every number shown is in `report.json`
and in one CSV per table; `n/a` marks a wall the method cannot build or a failed solve.

## Findings

{_findings(study, tables)}

## Tables

{body}

## Figures

{figs}

Micro mechanisms with the macro crack drawn over them: {mech}

The iterated LP over 104 small walls, seven settings: [stability.md](stability.md); Table 7 per
scheme, bond phase and head-joint friction: [table7_nonassoc.md](table7_nonassoc.md)
(both by `xcheck stability`).

## Where the paper and the model differ

{DISCREPANCIES}
## Models

{chr(10).join(f"* `{k}`: {v}" for k, v in MODELS.items())}

## Machine and timings

Python {meta["python"]} on {meta["machine"]}, {meta["cpus"]} CPUs. This run: {elapsed:.1f} s,
{meta["computed"]} computations, {meta["cached"]} read from the cache (`.xcheck-cache/`, keyed by the
wall, the method and the source of the packages it runs).
"""
    path = out_dir / "REPORT.md"
    path.write_text(text)
    return path


__all__ = ["NONASSOC_MAX_BLOCKS", "Study", "Table", "build_report", "lam_cell", "pct"]
